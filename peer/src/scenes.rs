//! The scenes, described once as plain data. `ours.rs` and `theirs.rs` each turn the same
//! description into bodies of their engine, so any difference in the results comes from the
//! engines and not from two hand-written copies of a scene drifting apart.

use glam::{DQuat, DVec3};

/// Gravity used by both engines, m/s² (downwards along y).
pub const GRAVITY: f64 = 9.81;

/// The one step length both engines run at, s.
pub const DT: f64 = 1.0 / 60.0;

/// The four primitive shapes both engines have natively, in the same conventions: half
/// extents, and capsules and cylinders along their local y axis.
#[derive(Clone, Copy, Debug)]
pub enum ShapeDesc {
    Sphere { radius: f64 },
    Cuboid { half_extents: DVec3 },
    Capsule { half_height: f64, radius: f64 },
    Cylinder { half_height: f64, radius: f64 },
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

/// A scene: its bodies (indices into `bodies` name the same body in both engines) and how
/// long it runs.
#[derive(Clone, Debug)]
pub struct SceneDesc {
    pub bodies: Vec<BodyDesc>,
    pub steps: usize,
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
        steps: steps_for(10.0),
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
///
/// Sizing: a settled body takes at most about 0.05 m³ of the pile (its bounding box plus
/// the gaps of a random pile), so the walls are made twice as tall as that pile would be;
/// the bodies start above the walls, 0.5 m apart (the largest body spans 0.4 m), so no two
/// touch at the start.
pub fn rain(count: usize) -> (SceneDesc, Bin) {
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
    for i in 0..count {
        let layer = i / (per_row * per_row);
        let in_layer = i % (per_row * per_row);
        let shift = if layer % 2 == 1 { 0.1 } else { 0.0 };
        let position = DVec3::new(
            start + (in_layer % per_row) as f64 * SPACING + shift,
            h + 1.0 + layer as f64 * SPACING,
            start + (in_layer / per_row) as f64 * SPACING + shift,
        );
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
        steps: steps_for(5.0),
    };
    (scene, bin)
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
        steps: steps_for(6.0),
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
        steps: steps_for(3.0),
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
        steps: steps_for(2.0),
    }
}
