//! The scenes, described once as plain data. `ours.rs` and `theirs.rs` each turn the same
//! description into bodies of their engine, so any difference in the results comes from the
//! engines and not from two hand-written copies of a scene drifting apart.

use glam::{DQuat, DVec3};

/// Gravity used by both engines, m/s² (downwards along y).
pub const GRAVITY: f64 = 9.81;

/// The one step length both engines run at, s.
pub const DT: f64 = 1.0 / 60.0;

/// The four primitive shapes both engines have natively, in the same conventions: half
/// extents, and capsules and cylinders along their local y axis; and convex hulls of a point
/// cloud of the scene's (`SceneDesc::hulls`), which each engine builds with its own hull
/// code, once per cloud, and shares between the bodies that use it.
#[derive(Clone, Copy, Debug)]
pub enum ShapeDesc {
    Sphere {
        radius: f64,
    },
    Cuboid {
        half_extents: DVec3,
    },
    Capsule {
        half_height: f64,
        radius: f64,
    },
    Cylinder {
        half_height: f64,
        radius: f64,
    },
    /// The hull of `SceneDesc::hulls[hull]`.
    Hull {
        hull: usize,
    },
}

#[derive(Clone, Copy, Debug)]
pub struct MaterialDesc {
    /// kg/m³
    pub density: f64,
    pub restitution: f64,
    pub friction: f64,
}

/// One body as both engines should build it.
#[derive(Clone, Copy, Debug)]
pub struct BodyDesc {
    pub shape: ShapeDesc,
    pub material: MaterialDesc,
    pub position: DVec3,
    pub rotation: DQuat,
    pub velocity: DVec3,
    pub fixed: bool,
}

impl BodyDesc {
    fn dynamic(shape: ShapeDesc, material: MaterialDesc, position: DVec3) -> Self {
        BodyDesc {
            shape,
            material,
            position,
            rotation: DQuat::IDENTITY,
            velocity: DVec3::ZERO,
            fixed: false,
        }
    }

    fn fixed(shape: ShapeDesc, material: MaterialDesc, position: DVec3) -> Self {
        BodyDesc {
            fixed: true,
            ..BodyDesc::dynamic(shape, material, position)
        }
    }
}

/// One joint as both engines should build it: a ball (spherical) joint between bodies `a`
/// and `b` (indices into `SceneDesc::bodies`) at the world point `anchor` of the start,
/// where the two bodies are held together. Joined bodies do not collide with each other, in
/// either engine.
#[derive(Clone, Copy, Debug)]
pub struct JointDesc {
    pub a: usize,
    pub b: usize,
    pub anchor: DVec3,
}

impl JointDesc {
    /// The anchor in the frame of body `i` (`a` or `b`) as it starts: its offset from the
    /// body's centre, in the body's axes. Each engine keeps it fixed in the body.
    pub fn local_anchor(&self, bodies: &[BodyDesc], i: usize) -> DVec3 {
        let body = &bodies[i];
        body.rotation.inverse() * (self.anchor - body.position)
    }
}

/// A scene: its bodies (indices into `bodies` name the same body in both engines), the point
/// clouds of its hulls, the joints between its bodies, how long it runs and whether bodies
/// may sleep.
#[derive(Clone, Debug)]
pub struct SceneDesc {
    pub bodies: Vec<BodyDesc>,
    /// Point clouds, m, in shape coordinates, each centred on the centre of mass of its hull
    /// (so that a hull body's centre of mass, which both engines report as its position, is
    /// also its shape's origin).
    pub hulls: Vec<Vec<DVec3>>,
    pub joints: Vec<JointDesc>,
    pub steps: usize,
    /// Whether bodies may fall asleep (each engine with its own default thresholds); off, no
    /// body ever sleeps in either engine.
    pub sleeping: bool,
}

fn steps_for(seconds: f64) -> usize {
    (seconds / DT).round() as usize
}

/// The 20-layer pyramid of 210 unit boxes on a static floor, read from our own scene file
/// (`scenes/pyramid.ron`) so that sizes, gaps and material are exactly the file's. Only the
/// bodies are taken: the file's dt (1/240) is replaced by the shared `DT`.
pub fn pyramid() -> SceneDesc {
    let scene = rigid::scene::load("pyramid").expect("built-in scene `pyramid` loads");
    let descs = scene.body_descs().expect("pyramid bodies are valid");
    let bodies = descs.iter().map(from_rigid_desc).collect();
    SceneDesc {
        bodies,
        hulls: Vec::new(),
        joints: Vec::new(),
        steps: steps_for(10.0),
        sleeping: true,
    }
}

/// Converts one of our scene-file bodies into the shared description (primitives only: the
/// scene files used here have nothing else).
fn from_rigid_desc(desc: &rigid::physics::BodyDesc) -> BodyDesc {
    use rigid::physics::{Motion, Shape};
    let shape = match desc.shape {
        Shape::Sphere { radius } => ShapeDesc::Sphere { radius },
        Shape::Cuboid { half_extents } => ShapeDesc::Cuboid { half_extents },
        Shape::Capsule {
            half_height,
            radius,
        } => ShapeDesc::Capsule {
            half_height,
            radius,
        },
        Shape::Cylinder {
            half_height,
            radius,
        } => ShapeDesc::Cylinder {
            half_height,
            radius,
        },
        ref other => panic!("shape {} has no rapier counterpart here", other.kind_name()),
    };
    let m = desc.material;
    BodyDesc {
        shape,
        material: MaterialDesc {
            density: m.density,
            restitution: m.restitution,
            friction: m.friction,
        },
        position: desc.position,
        rotation: desc.rotation,
        velocity: desc.velocity,
        fixed: desc.motion == Motion::Static,
    }
}

/// The open bin of a rain scene: interior is |x|, |z| < `half_width`, 0 < y < `wall_height`.
#[derive(Clone, Copy, Debug)]
pub struct Bin {
    pub half_width: f64,
    pub wall_height: f64,
}

impl Bin {
    /// Whether a body centre is still in the bin: inside the walls' footprint and not below
    /// the floor's top. A small tolerance keeps resting overlap from counting.
    pub fn holds(&self, p: DVec3) -> bool {
        const TOLERANCE: f64 = 0.05;
        let inside = self.half_width + TOLERANCE;
        p.x.abs() < inside && p.z.abs() < inside && p.y > -TOLERANCE
    }
}

// The materials of `scenes/rain.ron`.
const CONCRETE: MaterialDesc = MaterialDesc {
    density: 2400.0,
    restitution: 0.2,
    friction: 0.7,
};
const RUBBER: MaterialDesc = MaterialDesc {
    density: 1100.0,
    restitution: 0.7,
    friction: 0.9,
};
const WOOD: MaterialDesc = MaterialDesc {
    density: 600.0,
    restitution: 0.4,
    friction: 0.5,
};
const PLASTIC: MaterialDesc = MaterialDesc {
    density: 950.0,
    restitution: 0.5,
    friction: 0.4,
};

/// `euler_deg(x, y, z)` as our scene files read `Euler(x, y, z)`: Rz · Ry · Rx.
fn euler_deg(x: f64, y: f64, z: f64) -> DQuat {
    DQuat::from_rotation_z(z.to_radians())
        * DQuat::from_rotation_y(y.to_radians())
        * DQuat::from_rotation_x(x.to_radians())
}

/// A rain of `count` mixed bodies (spheres, boxes, capsules and cylinders, taking turns so
/// each kind is a quarter of the total) with the shapes, materials and tilts of
/// `scenes/rain.ron`, on a grid above an open bin sized for `count`, run for 5 s.
pub fn rain(count: usize) -> (SceneDesc, Bin) {
    let (mut bodies, bin, drops) = rain_layout(count);
    for (i, position) in drops.into_iter().enumerate() {
        let (shape, material, rotation) = match i % 4 {
            0 => (ShapeDesc::Sphere { radius: 0.15 }, RUBBER, DQuat::IDENTITY),
            1 => (
                ShapeDesc::Cuboid {
                    half_extents: DVec3::new(0.15, 0.1, 0.12),
                },
                WOOD,
                euler_deg(15.0, 30.0, 0.0),
            ),
            2 => (
                ShapeDesc::Capsule {
                    half_height: 0.12,
                    radius: 0.08,
                },
                PLASTIC,
                euler_deg(90.0, 0.0, 30.0),
            ),
            _ => (
                ShapeDesc::Cylinder {
                    half_height: 0.08,
                    radius: 0.15,
                },
                WOOD,
                euler_deg(0.0, 0.0, 40.0),
            ),
        };
        bodies.push(BodyDesc {
            rotation,
            ..BodyDesc::dynamic(shape, material, position)
        });
    }
    let scene = SceneDesc {
        bodies,
        hulls: Vec::new(),
        joints: Vec::new(),
        steps: steps_for(5.0),
        sleeping: true,
    };
    (scene, bin)
}

/// The bin of a rain of `count` bodies (floor and four walls, fixed) and the `count` drop
/// points above it, for bodies that reach at most 0.2 m from their centre.
///
/// Sizing: a settled body takes at most about 0.05 m³ of the pile (its bounding box plus
/// the gaps of a random pile), so the walls are made twice as tall as that pile would be;
/// the bodies start above the walls, 0.5 m apart (the largest body spans 0.4 m), so no two
/// touch at the start.
fn rain_layout(count: usize) -> (Vec<BodyDesc>, Bin, Vec<DVec3>) {
    const SPACING: f64 = 0.5;
    const WALL: f64 = 0.1; // half thickness of floor and walls
    let half_width = if count <= 1000 { 2.5 } else { 4.0 };
    let floor_area = (2.0 * half_width) * (2.0 * half_width);
    let pile_height = count as f64 * 0.05 / floor_area;
    let wall_height = (2.0 * pile_height).max(2.0);
    let bin = Bin {
        half_width,
        wall_height,
    };

    let mut bodies = Vec::with_capacity(count + 5);
    let (w, h) = (half_width, wall_height);
    // Floor top at y = 0; walls stand on the floor's edge, outside the interior.
    bodies.push(BodyDesc::fixed(
        ShapeDesc::Cuboid {
            half_extents: DVec3::new(w + 2.0 * WALL, WALL, w + 2.0 * WALL),
        },
        CONCRETE,
        DVec3::new(0.0, -WALL, 0.0),
    ));
    for (x, z, half_extents) in [
        (-(w + WALL), 0.0, DVec3::new(WALL, h / 2.0, w + 2.0 * WALL)),
        (w + WALL, 0.0, DVec3::new(WALL, h / 2.0, w + 2.0 * WALL)),
        (0.0, -(w + WALL), DVec3::new(w, h / 2.0, WALL)),
        (0.0, w + WALL, DVec3::new(w, h / 2.0, WALL)),
    ] {
        bodies.push(BodyDesc::fixed(
            ShapeDesc::Cuboid { half_extents },
            CONCRETE,
            DVec3::new(x, h / 2.0, z),
        ));
    }

    // Columns across the interior; layers from 1 m above the walls, odd layers shifted by
    // 0.1 m so that columns do not stack exactly. The outermost column, shifted, still has
    // its bodies (at most 0.2 m from their centre) 0.05 m clear of the walls.
    let per_row = ((2.0 * (w - 0.35)) / SPACING).floor() as usize + 1;
    let start = -((per_row - 1) as f64) * SPACING / 2.0;
    let drops = (0..count)
        .map(|i| {
            let layer = i / (per_row * per_row);
            let in_layer = i % (per_row * per_row);
            let shift = if layer % 2 == 1 { 0.1 } else { 0.0 };
            DVec3::new(
                start + (in_layer % per_row) as f64 * SPACING + shift,
                h + 1.0 + layer as f64 * SPACING,
                start + (in_layer / per_row) as f64 * SPACING + shift,
            )
        })
        .collect();
    (bodies, bin, drops)
}

/// A large static floor with its top at y = 0, of the given material.
fn floor(material: MaterialDesc) -> BodyDesc {
    BodyDesc::fixed(
        ShapeDesc::Cuboid {
            half_extents: DVec3::new(50.0, 0.5, 50.0),
        },
        material,
        DVec3::new(0.0, -0.5, 0.0),
    )
}

/// C2: a ball r = 0.5 dropped with its bottom at `drop_height` onto the floor, ε = 0.8 and
/// μ = 0 on both bodies (so min, average, max and geometric mean all give 0.8 and 0). Body 1
/// is the ball. Long enough for three bounces (the third apex comes at about 4.8 s).
pub fn bounce(drop_height: f64, restitution: f64) -> SceneDesc {
    let material = MaterialDesc {
        density: 1000.0,
        restitution,
        friction: 0.0,
    };
    let ball = BodyDesc::dynamic(
        ShapeDesc::Sphere { radius: 0.5 },
        material,
        DVec3::new(0.0, drop_height + 0.5, 0.0),
    );
    SceneDesc {
        bodies: vec![floor(material), ball],
        hulls: Vec::new(),
        joints: Vec::new(),
        steps: steps_for(6.0),
        sleeping: true,
    }
}

/// The material of the friction cases: μ = 0.5 on both bodies (every combine rule gives
/// 0.5) and no bounce.
const FRICTION_CASE: MaterialDesc = MaterialDesc {
    density: 1000.0,
    restitution: 0.0,
    friction: 0.5,
};

/// C4: a unit box resting on the floor, launched along x at `speed`. Body 1 is the box. It
/// stops after v/(μg) ≈ 1 s; 3 s leaves room for any late creep to show.
pub fn slide(speed: f64) -> SceneDesc {
    let block = BodyDesc {
        velocity: DVec3::new(speed, 0.0, 0.0),
        ..BodyDesc::dynamic(
            ShapeDesc::Cuboid {
                half_extents: DVec3::splat(0.5),
            },
            FRICTION_CASE,
            DVec3::new(0.0, 0.5, 0.0),
        )
    };
    SceneDesc {
        bodies: vec![floor(FRICTION_CASE), block],
        hulls: Vec::new(),
        joints: Vec::new(),
        steps: steps_for(3.0),
        sleeping: true,
    }
}

/// C6: a ball r = 0.5 resting on the floor, launched along x at `speed` without spin. Body 1
/// is the ball. Slipping ends after 2v/(7μg) ≈ 0.17 s; it then rolls for the rest of 2 s.
pub fn roll(speed: f64) -> SceneDesc {
    let ball = BodyDesc {
        velocity: DVec3::new(speed, 0.0, 0.0),
        ..BodyDesc::dynamic(
            ShapeDesc::Sphere { radius: 0.5 },
            FRICTION_CASE,
            DVec3::new(0.0, 0.5, 0.0),
        )
    };
    SceneDesc {
        bodies: vec![floor(FRICTION_CASE), ball],
        hulls: Vec::new(),
        joints: Vec::new(),
        steps: steps_for(2.0),
        sleeping: true,
    }
}

// ---------------------------------------------------------------------------------------
// Stress scenes: large stacks and piles, several of them Box3D's benchmarks
// (`shared/benchmarks.c` of erincatto/box3d), rebuilt here from their description.

/// Where a body must stay to count as kept: inside this box, with a finite position.
#[derive(Clone, Copy, Debug)]
pub struct Region {
    pub min: DVec3,
    pub max: DVec3,
}

impl Region {
    /// Above a floor whose top is at y = 0, within its footprint |x| ≤ `half_x`,
    /// |z| ≤ `half_z` widened by 1 m, and no more than 1 m below its top: a body that slides
    /// off the edge or sinks through the floor is lost.
    fn above_floor(half_x: f64, half_z: f64) -> Self {
        Region {
            min: DVec3::new(-half_x - 1.0, -1.0, -half_z - 1.0),
            max: DVec3::new(half_x + 1.0, f64::INFINITY, half_z + 1.0),
        }
    }

    /// The box around the bodies' start positions, widened by `margin` on every side: for a
    /// scene with no floor, a body that ends further than that from where any body started
    /// is lost.
    fn around(bodies: &[BodyDesc], margin: f64) -> Self {
        let (min, max) = bodies
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(min, max), b| {
                (min.min(b.position), max.max(b.position))
            });
        Region {
            min: min - margin,
            max: max + margin,
        }
    }

    pub fn holds(&self, p: DVec3) -> bool {
        p.is_finite() && p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}

impl Bin {
    /// The region of `holds` (without the upper bound: bodies start above the walls).
    fn region(&self) -> Region {
        const TOLERANCE: f64 = 0.05;
        let inside = self.half_width + TOLERANCE;
        Region {
            min: DVec3::new(-inside, -TOLERANCE, -inside),
            max: DVec3::new(inside, f64::INFINITY, inside),
        }
    }
}

/// What a stress scene is measured by, besides the figures all of them get (deepest
/// overlap, bodies lost, bodies awake).
#[derive(Clone, Copy, Debug)]
pub enum StressKind {
    /// A stack that should stand still: drift (the largest distance any box moved from its
    /// start), and, when given, the sideways (x, z) displacement of the apex body.
    Stack { apex: Option<usize> },
    /// A pile, rain or hanging grid with no answer to compare against: overlap, lost and
    /// awake only (and, as in every scene with joints, the joints' largest separation).
    Pile,
    /// A wall hit by a ball (body `ball`): how many boxes moved more than 0.5 m.
    Smash { ball: usize },
}

/// A stress scene: its description, where its bodies must stay, what it is measured by, and
/// the name of the same scene in Box3D's benchmark program, if it is one of its.
#[derive(Clone, Debug)]
pub struct Stress {
    pub name: &'static str,
    /// Says what it is, for the table.
    pub title: String,
    pub scene: SceneDesc,
    pub region: Region,
    pub kind: StressKind,
    pub box3d: Option<&'static str>,
    /// Timed runs of each engine when not told otherwise.
    pub repeats: usize,
}

/// The stress scenes, by name, in the order the report lists them.
pub const STRESS: &[&str] = &[
    "pyramid20",
    "large_pyramid",
    "many_pyramids",
    "convex_pile",
    "hull_rain",
    "wall_smash",
    "joint_grid",
    "ragdoll_rain",
    "column30",
];

pub fn stress(name: &str) -> Option<Stress> {
    Some(match name {
        "pyramid20" => pyramid20(),
        "large_pyramid" => large_pyramid(),
        "many_pyramids" => many_pyramids(),
        "convex_pile" => convex_pile(),
        "hull_rain" => hull_rain(800),
        "wall_smash" => wall_smash(),
        "joint_grid" => joint_grid(),
        "ragdoll_rain" => ragdoll_rain(),
        "column30" => column30(),
        _ => return None,
    })
}

/// The index of the body that starts highest (the apex of a single pyramid).
fn highest(bodies: &[BodyDesc]) -> usize {
    (0..bodies.len())
        .max_by(|&a, &b| bodies[a].position.y.total_cmp(&bodies[b].position.y))
        .expect("a scene has bodies")
}

/// `pyramid` (20 layers, 210 boxes, 5 cm gaps, on its 40 × 10 m floor) with sleeping off, so
/// that every box is solved in every step of the 10 s.
fn pyramid20() -> Stress {
    let scene = SceneDesc {
        sleeping: false,
        ..pyramid()
    };
    let apex = highest(&scene.bodies);
    Stress {
        name: "pyramid20",
        title: "pyramid20: 20 layers, 210 boxes, gaps 5 cm".to_owned(),
        region: Region::above_floor(20.0, 5.0),
        kind: StressKind::Stack { apex: Some(apex) },
        box3d: None,
        scene,
        // A run takes a tenth of a second: see `PYRAMID_REPEATS` in main.rs.
        repeats: 31,
    }
}

/// Box3D's material for its benchmark boxes: its default friction and restitution, density
/// 100 (its pyramids set it; `convex_pile` keeps the default 1000).
const BOX3D_BOX: MaterialDesc = MaterialDesc {
    density: 100.0,
    restitution: 0.0,
    friction: 0.6,
};

/// A column of 30 unit cubes stacked face on face (density 100, friction 0.6, touching), on
/// Box3D's ground, sleeping off, 600 steps (10 s). A rigid column stands: any sway is the
/// solver's.
fn column30() -> Stress {
    const COUNT: usize = 30;
    let mut bodies = vec![box3d_ground(50.0, BOX3D_BOX)];
    for k in 0..COUNT {
        bodies.push(BodyDesc::dynamic(
            ShapeDesc::Cuboid {
                half_extents: DVec3::splat(0.5),
            },
            BOX3D_BOX,
            DVec3::new(0.0, 0.5 + k as f64, 0.0),
        ));
    }
    let apex = highest(&bodies);
    Stress {
        name: "column30",
        title: format!("column30: {COUNT} unit cubes face on face"),
        scene: SceneDesc {
            bodies,
            hulls: Vec::new(),
            joints: Vec::new(),
            steps: 600,
            sleeping: false,
        },
        region: Region::above_floor(50.0, 50.0),
        kind: StressKind::Stack { apex: Some(apex) },
        box3d: None,
        repeats: 5,
    }
}

/// Box3D's ground: a box of half extents `half` × 1 × `half` at y = -1 (top at y = 0).
fn box3d_ground(half: f64, material: MaterialDesc) -> BodyDesc {
    BodyDesc::fixed(
        ShapeDesc::Cuboid {
            half_extents: DVec3::new(half, 1.0, half),
        },
        material,
        DVec3::new(0.0, -1.0, 0.0),
    )
}

/// One of Box3D's pyramids (`CreateLargePyramid`, `CreateSmallPyramid`): `base` cubes of half
/// extent `h` along x on the bottom row, one fewer each row up, every box touching its
/// neighbours and the row below (no gaps), in the plane z = `z`. Row i has its centres at
/// y = (2i + 1)h, x = (i + 1)h + 2(j − i)h + `x0` for j = i..base.
fn box3d_pyramid(bodies: &mut Vec<BodyDesc>, base: usize, h: f64, x0: f64, z: f64) {
    for i in 0..base {
        let y = (2.0 * i as f64 + 1.0) * h;
        for j in i..base {
            let x = (i as f64 + 1.0) * h + 2.0 * (j - i) as f64 * h + x0;
            bodies.push(BodyDesc::dynamic(
                ShapeDesc::Cuboid {
                    half_extents: DVec3::splat(h),
                },
                BOX3D_BOX,
                DVec3::new(x, y, z),
            ));
        }
    }
}

/// Box3D's `large_pyramid`: a pyramid of base 100 (5050 unit cubes, density 100, touching)
/// on a 800 × 800 m ground, sleeping off, 200 steps.
fn large_pyramid() -> Stress {
    const BASE: usize = 100;
    const H: f64 = 0.5;
    let mut bodies = vec![box3d_ground(400.0, BOX3D_BOX)];
    box3d_pyramid(&mut bodies, BASE, H, -H * BASE as f64, 0.0);
    let apex = highest(&bodies);
    Stress {
        name: "large_pyramid",
        title: format!(
            "large_pyramid (Box3D): base {BASE}, {} boxes",
            bodies.len() - 1
        ),
        scene: SceneDesc {
            bodies,
            hulls: Vec::new(),
            joints: Vec::new(),
            steps: 200,
            sleeping: false,
        },
        region: Region::above_floor(400.0, 400.0),
        kind: StressKind::Stack { apex: Some(apex) },
        box3d: Some("large_pyramid"),
        repeats: 3,
    }
}

/// Box3D's `many_pyramids`: 14 rows × 14 columns of pyramids of base 10 (55 unit cubes
/// each, 10 780 in all, density 100), sleeping off, 100 steps. As `CreateManyPyramids`: the
/// ground's half extent is 0.5 · 14 · 11 = 77 m; pyramid (row r, column c) has its bottom
/// row from x = −77 + 11c + 1 − 0.5 and lies in the plane z = −76 + r · 152/13.
fn many_pyramids() -> Stress {
    const BASE: usize = 10;
    const EXTENT: f64 = 0.5;
    const ROWS: usize = 14;
    const COLUMNS: usize = 14;
    let ground = EXTENT * COLUMNS as f64 * (BASE as f64 + 1.0);
    let mut bodies = vec![box3d_ground(ground, BOX3D_BOX)];
    let base_width = 2.0 * EXTENT * BASE as f64;
    let delta_z = 2.0 * (ground - 2.0 * EXTENT) / (ROWS as f64 - 1.0);
    for row in 0..ROWS {
        let z = -ground + 2.0 * EXTENT + row as f64 * delta_z;
        for column in 0..COLUMNS {
            let center_x = -ground + column as f64 * (base_width + 2.0 * EXTENT) + 2.0 * EXTENT;
            box3d_pyramid(&mut bodies, BASE, EXTENT, center_x - 0.5, z);
        }
    }
    Stress {
        name: "many_pyramids",
        title: format!(
            "many_pyramids (Box3D): {ROWS} × {COLUMNS} pyramids of base {BASE}, {} boxes",
            bodies.len() - 1
        ),
        scene: SceneDesc {
            bodies,
            hulls: Vec::new(),
            joints: Vec::new(),
            steps: 100,
            sleeping: false,
        },
        region: Region::above_floor(ground, ground),
        kind: StressKind::Stack { apex: None },
        box3d: Some("many_pyramids"),
        repeats: 3,
    }
}

/// PEEL's `BasicRandom`, as Box3D's `convex_pile` uses it (a 32-bit linear congruential
/// generator), so that the same seed gives the same points as there.
struct PeelRandom {
    state: u32,
}

impl PeelRandom {
    fn next(&mut self) -> u32 {
        self.state = self
            .state
            .wrapping_mul(2_147_001_325)
            .wrapping_add(715_136_305);
        self.state
    }

    /// In [-0.5, 0.5], in f32 as the original computes it.
    fn float(&mut self) -> f32 {
        (self.next() & 0xffff) as f32 / 65535.0 - 0.5
    }

    /// A uniformly random unit vector: rejection sampled in the ball of radius 0.5 (in f32,
    /// so the accepted points are the original's), then normalized (in f64).
    fn unit(&mut self) -> DVec3 {
        loop {
            let (x, y, z) = (self.float(), self.float(), self.float());
            if x * x + y * y + z * z <= 0.25 {
                return DVec3::new(x.into(), y.into(), z.into()).normalize();
            }
        }
    }
}

/// `points` moved so that the centre of mass of their hull (our hull code's: its exact
/// polyhedral integral) is the origin, and that centre of mass in the points' own frame: a
/// body placed at its old origin + centre has its hull exactly where the old points were.
/// Panics if the points span no volume.
fn centred(points: Vec<DVec3>) -> (Vec<DVec3>, DVec3) {
    let hull = rigid::physics::ConvexHull::from_points(&points).expect("hull points span a volume");
    let center = hull.mass_properties(1.0).center;
    (points.into_iter().map(|p| p - center).collect(), center)
}

/// Box3D's `convex_pile` (ported there from PEEL): one hull of 32 random points on a sphere
/// of radius 2 (PEEL's generator, seed 42), on 5120 bodies in 80 layers of 8 × 8 columns
/// 4 m apart (the hull's bounding sphere has diameter 4: bottom layer on the ground, and
/// neighbours at most touching), default density 1000 and friction 0.6, sleeping on as
/// there, 500 steps. The cloud is centred on its hull's centre of mass (see
/// `SceneDesc::hulls`) and each body placed that much further on, so the hulls lie exactly
/// where Box3D puts them.
fn convex_pile() -> Stress {
    const COUNT_X: usize = 8;
    const COUNT_Z: usize = 8;
    const LAYERS: usize = 80;
    const AMPLITUDE: f64 = 2.0;
    const POINTS: usize = 32;
    const SCATTER: f64 = 2.0 * AMPLITUDE;
    let material = MaterialDesc {
        density: 1000.0,
        ..BOX3D_BOX
    };
    let mut random = PeelRandom { state: 42 };
    let (points, center) = centred((0..POINTS).map(|_| AMPLITUDE * random.unit()).collect());
    let mut bodies = vec![box3d_ground(250.0, material)];
    for layer in 0..LAYERS {
        for z in 0..COUNT_Z {
            for x in 0..COUNT_X {
                let origin = DVec3::new(
                    (x as f64 - 0.5 * COUNT_X as f64) * SCATTER,
                    AMPLITUDE + 2.0 * AMPLITUDE * layer as f64,
                    (z as f64 - 0.5 * COUNT_Z as f64) * SCATTER,
                );
                bodies.push(BodyDesc::dynamic(
                    ShapeDesc::Hull { hull: 0 },
                    material,
                    origin + center,
                ));
            }
        }
    }
    Stress {
        name: "convex_pile",
        title: format!(
            "convex_pile (Box3D): {} hulls of {POINTS} points on a sphere r = {AMPLITUDE} m",
            bodies.len() - 1
        ),
        scene: SceneDesc {
            bodies,
            hulls: vec![points],
            joints: Vec::new(),
            steps: 500,
            sleeping: true,
        },
        region: Region::above_floor(250.0, 250.0),
        kind: StressKind::Pile,
        box3d: Some("convex_pile"),
        repeats: 3,
    }
}

/// A rain of `count` hulls into the bin of `rain(count)`, from its drop grid, for 5 s,
/// sleeping on: each its own hull of 10 random points (PEEL's generator, seed 7) on an
/// ellipsoid of semi-axes drawn from [0.1, 0.2] m, so that every body reaches at most 0.2 m
/// from its centre as the grid needs. Materials take turns as the rain's do (rubber, wood,
/// plastic, wood).
fn hull_rain(count: usize) -> Stress {
    const POINTS: usize = 10;
    let (mut bodies, bin, drops) = rain_layout(count);
    let mut random = PeelRandom { state: 7 };
    let mut hulls = Vec::with_capacity(count);
    for (i, position) in drops.into_iter().enumerate() {
        let axes = DVec3::new(
            0.15 + 0.1 * f64::from(random.float()),
            0.15 + 0.1 * f64::from(random.float()),
            0.15 + 0.1 * f64::from(random.float()),
        );
        let (points, center) = centred((0..POINTS).map(|_| axes * random.unit()).collect());
        hulls.push(points);
        let material = [RUBBER, WOOD, PLASTIC, WOOD][i % 4];
        bodies.push(BodyDesc::dynamic(
            ShapeDesc::Hull { hull: i },
            material,
            position + center,
        ));
    }
    Stress {
        name: "hull_rain",
        title: format!(
            "hull_rain: {count} hulls of {POINTS} points, bin {w:.0} × {w:.0} × {h:.2} m",
            w = 2.0 * bin.half_width,
            h = bin.wall_height
        ),
        scene: SceneDesc {
            bodies,
            hulls,
            joints: Vec::new(),
            steps: steps_for(5.0),
            sleeping: true,
        },
        region: bin.region(),
        kind: StressKind::Pile,
        box3d: None,
        repeats: 5,
    }
}

/// A wall of 20 × 10 wooden cubes (0.5 m, density 500, touching, no gaps) standing on the
/// floor across x in the plane z = 0, hit by a steel ball (r = 0.5 m, density 7800: 15.6
/// times the boxes', 4084 kg against 62.5 kg a box) launched along +z at 8 m/s from 3 m in
/// front of the wall, its centre 2 m up; it reaches the wall at about 0.3 s, about 1.6 m up
/// (the fourth row). Sleeping on, 3 s.
fn wall_smash() -> Stress {
    const WIDE: usize = 20;
    const HIGH: usize = 10;
    const H: f64 = 0.25;
    let wood = MaterialDesc {
        density: 500.0,
        restitution: 0.0,
        friction: 0.6,
    };
    let steel = MaterialDesc {
        density: 7800.0,
        restitution: 0.2,
        friction: 0.4,
    };
    let mut bodies = vec![floor(wood)];
    for row in 0..HIGH {
        for column in 0..WIDE {
            bodies.push(BodyDesc::dynamic(
                ShapeDesc::Cuboid {
                    half_extents: DVec3::splat(H),
                },
                wood,
                DVec3::new(
                    (column as f64 - (WIDE as f64 - 1.0) / 2.0) * 2.0 * H,
                    (2.0 * row as f64 + 1.0) * H,
                    0.0,
                ),
            ));
        }
    }
    let ball = bodies.len();
    bodies.push(BodyDesc {
        velocity: DVec3::new(0.0, 0.0, 8.0),
        ..BodyDesc::dynamic(
            ShapeDesc::Sphere { radius: 0.5 },
            steel,
            DVec3::new(0.0, 2.0, -3.0),
        )
    });
    Stress {
        name: "wall_smash",
        title: format!("wall_smash: {WIDE} × {HIGH} boxes of 0.5 m, steel ball r 0.5 m at 8 m/s"),
        scene: SceneDesc {
            bodies,
            hulls: Vec::new(),
            joints: Vec::new(),
            steps: steps_for(3.0),
            sleeping: true,
        },
        region: Region::above_floor(50.0, 50.0),
        kind: StressKind::Smash { ball },
        box3d: None,
        repeats: 11,
    }
}

/// Box3D's `joint_grid` (`CreateJointGrid`): a 100 × 100 grid of spheres of radius 0.4, 1 m
/// apart in the vertical plane z = 0, column k at x = k and row i at y = −i, the top row
/// (i = 0) static. Each sphere is joined by a ball joint to the one above it and to the one on
/// its left, at the midpoint between them: Box3D's 19 800 joints less the 99 between two
/// static spheres of the top row, 19 701. Box3D's default density (1000) and
/// friction; sleeping off, as there; 100 steps. The grid starts hanging straight down, so the
/// scene measures how the joints hold a 99-link chain's weight, not a fall. Box3D also filters
/// the spheres out of colliding with each other; neither engine here has filtering set up,
/// but spheres 1 m apart with radius 0.4 do not touch while the grid hangs.
fn joint_grid() -> Stress {
    const N: usize = 100;
    let material = MaterialDesc {
        density: 1000.0,
        ..BOX3D_BOX
    };
    let sphere = ShapeDesc::Sphere { radius: 0.4 };
    let index = |k: usize, i: usize| k * N + i;
    let mut bodies = Vec::with_capacity(N * N);
    let mut joints = Vec::with_capacity(2 * N * (N - 1));
    for k in 0..N {
        for i in 0..N {
            let position = DVec3::new(k as f64, -(i as f64), 0.0);
            bodies.push(if i == 0 {
                BodyDesc::fixed(sphere, material, position)
            } else {
                BodyDesc::dynamic(sphere, material, position)
            });
            let mut join = |a: usize, offset: DVec3| {
                joints.push(JointDesc {
                    a,
                    b: index(k, i),
                    anchor: position + offset,
                });
            };
            if i > 0 {
                join(index(k, i - 1), DVec3::new(0.0, 0.5, 0.0));
            }
            // Box3D also joins the static spheres of the top row to each other; such a joint
            // holds nothing, and ours refuses it.
            if k > 0 && i > 0 {
                join(index(k - 1, i), DVec3::new(-0.5, 0.0, 0.0));
            }
        }
    }
    Stress {
        name: "joint_grid",
        title: format!(
            "joint_grid (Box3D): {N} × {N} spheres r 0.4, {} ball joints, top row static",
            joints.len()
        ),
        region: Region::around(&bodies, 10.0),
        scene: SceneDesc {
            bodies,
            hulls: Vec::new(),
            joints,
            steps: 100,
            sleeping: false,
        },
        kind: StressKind::Pile,
        box3d: Some("joint_grid"),
        repeats: 3,
    }
}

/// The parts of a ragdoll standing with its feet at y = 0, facing +z: each part's shape and
/// centre. Pelvis, torso, head, then left upper arm and forearm, right upper arm and forearm,
/// left thigh and shin, right thigh and shin; about 1.76 m tall and 62 kg.
const RAGDOLL_PARTS: [(ShapeDesc, DVec3); 11] = {
    const fn capsule(half_height: f64, radius: f64) -> ShapeDesc {
        ShapeDesc::Capsule {
            half_height,
            radius,
        }
    }
    const fn cuboid(x: f64, y: f64, z: f64) -> ShapeDesc {
        ShapeDesc::Cuboid {
            half_extents: DVec3::new(x, y, z),
        }
    }
    [
        (cuboid(0.17, 0.08, 0.1), DVec3::new(0.0, 1.0, 0.0)),
        (cuboid(0.18, 0.2, 0.11), DVec3::new(0.0, 1.3, 0.0)),
        (
            ShapeDesc::Sphere { radius: 0.11 },
            DVec3::new(0.0, 1.65, 0.0),
        ),
        (capsule(0.12, 0.05), DVec3::new(-0.26, 1.3, 0.0)),
        (capsule(0.12, 0.045), DVec3::new(-0.26, 0.99, 0.0)),
        (capsule(0.12, 0.05), DVec3::new(0.26, 1.3, 0.0)),
        (capsule(0.12, 0.045), DVec3::new(0.26, 0.99, 0.0)),
        (capsule(0.16, 0.07), DVec3::new(-0.1, 0.72, 0.0)),
        (capsule(0.15, 0.06), DVec3::new(-0.1, 0.3, 0.0)),
        (capsule(0.16, 0.07), DVec3::new(0.1, 0.72, 0.0)),
        (capsule(0.15, 0.06), DVec3::new(0.1, 0.3, 0.0)),
    ]
};

/// The ball joints of a ragdoll, standing as in `RAGDOLL_PARTS`: the two parts and the anchor.
/// Spine, neck, shoulders and elbows, hips and knees.
const RAGDOLL_JOINTS: [(usize, usize, DVec3); 10] = [
    (0, 1, DVec3::new(0.0, 1.09, 0.0)),
    (1, 2, DVec3::new(0.0, 1.52, 0.0)),
    (1, 3, DVec3::new(-0.26, 1.47, 0.0)),
    (3, 4, DVec3::new(-0.26, 1.15, 0.0)),
    (1, 5, DVec3::new(0.26, 1.47, 0.0)),
    (5, 6, DVec3::new(0.26, 1.15, 0.0)),
    (0, 7, DVec3::new(-0.1, 0.95, 0.0)),
    (7, 8, DVec3::new(-0.1, 0.5, 0.0)),
    (0, 9, DVec3::new(0.1, 0.95, 0.0)),
    (9, 10, DVec3::new(0.1, 0.5, 0.0)),
];

/// Adds one ragdoll to `bodies` and `joints`, turned as a whole by `rotation` about its
/// middle (y = 0.9 standing), which is put at `middle`.
fn ragdoll(
    bodies: &mut Vec<BodyDesc>,
    joints: &mut Vec<JointDesc>,
    middle: DVec3,
    rotation: DQuat,
) {
    const MATERIAL: MaterialDesc = MaterialDesc {
        density: 1000.0,
        restitution: 0.0,
        friction: 0.6,
    };
    let place = |p: DVec3| middle + rotation * (p - DVec3::new(0.0, 0.9, 0.0));
    let first = bodies.len();
    for (shape, centre) in RAGDOLL_PARTS {
        bodies.push(BodyDesc {
            rotation,
            ..BodyDesc::dynamic(shape, MATERIAL, place(centre))
        });
    }
    for (a, b, anchor) in RAGDOLL_JOINTS {
        joints.push(JointDesc {
            a: first + a,
            b: first + b,
            anchor: place(anchor),
        });
    }
}

/// A rain of 50 ragdolls (`RAGDOLL_PARTS`, `RAGDOLL_JOINTS`: 550 bodies on 500 ball joints)
/// onto the floor, for 5 s, sleeping on: two layers of 5 × 5, 2 m apart (a ragdoll turned any
/// way reaches at most 0.9 m from its middle, so none touch at the start), the lower layer's
/// middles 1.5 m up and the upper layer's 4 m up and shifted by 1 m in x and z so that its
/// ragdolls land across the lower ones. Each is turned by a random heading and a random tilt
/// of up to 90° (PEEL's generator, seed 11), so that they tumble and tangle.
fn ragdoll_rain() -> Stress {
    const SIDE: usize = 5;
    const LAYERS: usize = 2;
    const SPACING: f64 = 2.0;
    let mut bodies = vec![floor(BOX3D_BOX)];
    let mut joints = Vec::new();
    let mut random = PeelRandom { state: 11 };
    let start = -((SIDE - 1) as f64) * SPACING / 2.0;
    for layer in 0..LAYERS {
        let shift = layer as f64 * SPACING / 2.0;
        for i in 0..SIDE * SIDE {
            let middle = DVec3::new(
                start + (i % SIDE) as f64 * SPACING + shift,
                1.5 + 2.5 * layer as f64,
                start + (i / SIDE) as f64 * SPACING + shift,
            );
            let heading = std::f64::consts::TAU * (f64::from(random.float()) + 0.5);
            let tilt = std::f64::consts::PI * f64::from(random.float());
            let rotation = DQuat::from_rotation_y(heading) * DQuat::from_rotation_x(tilt);
            ragdoll(&mut bodies, &mut joints, middle, rotation);
        }
    }
    Stress {
        name: "ragdoll_rain",
        title: format!(
            "ragdoll_rain: {} ragdolls of {} bodies (boxes, capsules, a sphere), {} ball joints",
            LAYERS * SIDE * SIDE,
            RAGDOLL_PARTS.len(),
            joints.len()
        ),
        scene: SceneDesc {
            bodies,
            hulls: Vec::new(),
            joints,
            steps: steps_for(5.0),
            sleeping: true,
        },
        region: Region::above_floor(50.0, 50.0),
        kind: StressKind::Pile,
        box3d: None,
        repeats: 5,
    }
}
