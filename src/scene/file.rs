//! The scene file format: plain serde structs read from RON. Every struct and enum denies
//! unknown fields, so a typo is an error rather than a silently ignored line.
//!
//! Units are SI (m, kg, s, kg/m³), y is up. Angles in `Rotation` are in degrees because people
//! write them by hand; angular velocities are in rad/s because the engine uses them as they are.

use std::collections::BTreeMap;

use glam::DVec3;
use serde::Deserialize;

use crate::physics::{Breaking, Integrator, Material, Motor, Servo, Spring};
use crate::scene::material_ref::MaterialRef;

/// A parsed scene. `origin` is the file it came from (or the name given to `parse`); every
/// error message starts with it.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename = "Scene")]
pub struct Scene {
    /// The scene's title; required, and not blank.
    pub name: String,
    /// Free text saying what the scene shows; optional.
    #[serde(default)]
    pub description: String,
    /// Time step and integrator; omitted, dt = 1/240 s and `Midpoint`.
    #[serde(default)]
    pub settings: SceneSettings,
    /// Where the viewer's camera starts; omitted, eye (0, 5, 15) looking at (0, 1, 0).
    #[serde(default)]
    pub camera: Camera,
    /// Environmental forces. None by default: a scene without `Gravity` is weightless.
    #[serde(default)]
    pub forces: Vec<ForceSpec>,
    /// Materials that bodies refer to by name.
    #[serde(default)]
    pub materials: BTreeMap<String, Material>,
    /// The bodies, in the order the world numbers them; a line with `repeat` stands for all
    /// its copies, in generation order.
    #[serde(default)]
    pub bodies: Vec<BodySpec>,
    /// Joints between bodies named in `bodies` (see [`JointSpec`]), added after every body.
    #[serde(default)]
    pub joints: Vec<JointSpec>,
    /// Not read from the file: the file's path, or the `origin` given to `parse`.
    #[serde(skip)]
    pub origin: String,
}

/// `settings: (dt: …, integrator: …)`: how the scene is stepped. Either field may be left out.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SceneSettings {
    /// Time step, s; must lie in `scene::DT_RANGE`.
    pub dt: f64,
    /// How orientations are advanced: `Midpoint` (the default), `ExactRotation` or
    /// `ReportEuler` (see [`Integrator`]).
    pub integrator: Integrator,
}

impl Default for SceneSettings {
    fn default() -> Self {
        SceneSettings {
            dt: 1.0 / 240.0,
            integrator: Integrator::default(),
        }
    }
}

/// Where a viewer should place its camera at start: a hint, not physics.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Camera {
    /// The camera's position, m.
    pub eye: DVec3,
    /// The point it looks at, m; must differ from `eye`.
    pub target: DVec3,
    /// A body's name: the camera then moves with that body (a car driving away), keeping
    /// where it looks from relative to it. The viewer can turn this off.
    pub follow: Option<String>,
}

impl Default for Camera {
    fn default() -> Self {
        Camera {
            eye: DVec3::new(0.0, 5.0, 15.0),
            target: DVec3::new(0.0, 1.0, 0.0),
            follow: None,
        }
    }
}

/// The engine's `EnvironmentForce`, with field names checked strictly.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ForceSpec {
    /// Uniform field, m/s²: `Gravity(acceleration: (0, -9.81, 0))`.
    Gravity {
        /// g, m/s²; any finite vector.
        acceleration: DVec3,
    },
    /// F = −k v, k in N·s/m.
    LinearDrag {
        /// k, N·s/m; not negative.
        coefficient: f64,
    },
    /// F = −c |v| v, c in N·s²/m².
    QuadraticDrag {
        /// c, N·s²/m²; not negative.
        coefficient: f64,
    },
    /// F = k (w − v): air moving at `velocity`.
    Wind {
        /// w, the air's velocity, m/s.
        velocity: DVec3,
        /// k, N·s/m; not negative.
        coefficient: f64,
    },
}

/// One body, or a template for many when `repeat` is set.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Generated copies are named `name_0`, `name_1`, … in generation order.
    #[serde(default)]
    pub name: String,
    /// The shape, in the body's own frame (see [`ShapeSpec`]).
    pub shape: ShapeSpec,
    /// Where the shape's own origin is placed (for a compound, the origin of its parts' frame).
    #[serde(default)]
    pub position: DVec3,
    /// Orientation, about the shape's origin; omitted, none.
    #[serde(default)]
    pub rotation: Rotation,
    /// Velocity of the centre of mass, m/s; ignored for a static body.
    #[serde(default)]
    pub velocity: DVec3,
    /// rad/s, world axes; ignored for a static body.
    #[serde(default)]
    pub angular_velocity: DVec3,
    /// A name from `materials`, or an inline `(density: …, restitution: …, friction: …)`.
    /// Omitted: the engine's default material.
    #[serde(default)]
    pub material: MaterialRef,
    /// kg; overrides the mass from density, keeping the shape's mass distribution.
    #[serde(default)]
    pub mass: Option<f64>,
    /// A static body never moves (infinite mass).
    #[serde(default, rename = "static")]
    pub is_static: bool,
    /// Makes the body kinematic, moved by a script (see [`KinematicSpec`]); written
    /// `kinematic: Velocity(…)`, without `Some`. Not with `static`, `velocity` or
    /// `angular_velocity`: the script gives the motion.
    #[serde(default)]
    pub kinematic: Option<KinematicSpec>,
    /// Simulated but not drawn, like a machine's front glass.
    #[serde(default)]
    pub hidden: bool,
    /// Makes copies of the body, placed by offsets from `position` (see [`Repeat`]); written
    /// `repeat: Grid(…)`, without `Some`.
    #[serde(default)]
    pub repeat: Option<Repeat>,
}

/// A body's shape. Every length is in m and must lie in [1e-4, 1e4] (the engine's
/// `MIN_EXTENT`, `MAX_EXTENT`).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ShapeSpec {
    /// Centred on the shape's origin.
    Sphere {
        /// m
        radius: f64,
    },
    /// A box centred on the shape's origin, its edges along the local axes.
    Cuboid {
        /// Half the edge lengths along local x, y, z, m.
        half_extents: DVec3,
    },
    /// Along the local y axis.
    Capsule {
        /// Half the distance between the centres of the two end caps, m.
        half_height: f64,
        /// Radius of the cylinder and of its hemispherical caps, m.
        radius: f64,
    },
    /// Along the local y axis.
    Cylinder {
        /// Half the height, m.
        half_height: f64,
        /// m
        radius: f64,
    },
    /// The convex hull of the points, in the body's shape frame.
    Hull {
        /// 4 to 100 000 points, m, each coordinate within 1e4 of the origin; not all in one
        /// plane.
        points: Vec<DVec3>,
    },
    /// Convex parts, each placed in the body's shape frame. Parts may not be compounds.
    Compound {
        /// At least one part.
        parts: Vec<PartSpec>,
    },
}

/// One part of a `Compound`: `(shape: …, position: …, rotation: …)`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartSpec {
    /// Any shape but `Compound`.
    pub shape: ShapeSpec,
    /// Where the part's own origin lies in the body's shape frame, m; omitted, at its origin.
    #[serde(default)]
    pub position: DVec3,
    /// The part's orientation in the body's shape frame; omitted, none.
    #[serde(default)]
    pub rotation: Rotation,
}

/// An orientation as written in a scene file.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Rotation {
    /// Degrees about the world x axis, then the world y axis, then the world z axis.
    Euler(f64, f64, f64),
    /// `degrees` about `axis` (any non-zero length).
    AxisAngle {
        /// The rotation axis; any non-zero length.
        axis: DVec3,
        /// Angle, degrees, right-handed about `axis`.
        degrees: f64,
    },
}

impl Default for Rotation {
    fn default() -> Self {
        Rotation::Euler(0.0, 0.0, 0.0)
    }
}

/// Generators: one body line becomes many bodies.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Repeat {
    /// `count.0 × count.1 × count.2` copies; copy (i, j, k) is moved by
    /// `(i spacing.x, j spacing.y, k spacing.z)`, plus `stagger` when j is odd (staggered rows
    /// of pins). Copies are generated with i fastest, then k, then j (bottom layer first).
    Grid {
        /// Copies along x, y and z; each at least 1.
        count: (u32, u32, u32),
        /// Distance between neighbouring copies along x, y and z, m.
        spacing: DVec3,
        /// Extra offset of the odd layers (j odd), m; omitted, none.
        #[serde(default)]
        stagger: DVec3,
    },
    /// A triangle of copies in the x–y plane: layer l (0 at the bottom) holds `layers − l`
    /// copies, moved by `((i + l/2) spacing.0, l spacing.1, 0)`, so it has
    /// `layers (layers + 1) / 2` copies in all.
    Pyramid {
        /// Number of layers, and of copies in the bottom one; at least 1.
        layers: u32,
        /// Horizontal distance between neighbours in a layer and height of a layer, m.
        spacing: (f64, f64),
    },
}

/// How a kinematic body moves. Its `position` and `rotation` are its pose at rest (t = 0 for
/// `Velocity`, the centre of the swing for `Sinusoid`).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum KinematicSpec {
    /// Constant velocities, world axes; the angular one turns the body about its centre of
    /// mass.
    Velocity {
        /// m/s; omitted, zero.
        #[serde(default)]
        linear: DVec3,
        /// rad/s; omitted, zero.
        #[serde(default)]
        angular: DVec3,
    },
    /// With s(t) = sin(2π `frequency` t + `phase`): the shape's origin is at
    /// `position + amplitude s(t) axis/|axis|` and the body turned by `angle_amplitude s(t)`
    /// degrees about `angle_axis` (through the shape's origin), then by `rotation`.
    Sinusoid {
        /// Direction of the swing; any non-zero length (unused when `amplitude` is 0).
        #[serde(default = "unit_x")]
        axis: DVec3,
        /// Half the swing's travel, m; finite.
        #[serde(default)]
        amplitude: f64,
        /// Axis of the turn, world; any non-zero length (unused when `angle_amplitude` is 0).
        #[serde(default = "unit_y")]
        angle_axis: DVec3,
        /// Largest turn, degrees; finite.
        #[serde(default)]
        angle_amplitude: f64,
        /// Hz; finite, not negative.
        frequency: f64,
        /// Degrees; omitted, 0 (the body starts at its rest pose).
        #[serde(default)]
        phase: f64,
    },
}

fn unit_x() -> DVec3 {
    DVec3::X
}

fn unit_y() -> DVec3 {
    DVec3::Y
}

/// One joint, or a chain of them: `(name: "hinge", body_a: "frame", body_b: "door",
/// kind: Hinge(anchor: (…), axis: (…)), limits: (-90, 0))`. Anchors and axes are world
/// coordinates in the scene as written (the bodies' starting poses). Bodies are named as the
/// world names them: a body made by a generator is `name_0`, `name_1`, ….
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSpec {
    /// Names the joint in error messages; optional (errors then give its index, `#2`).
    #[serde(default)]
    pub name: String,
    /// The first body's name; not with `Chain`.
    #[serde(default)]
    pub body_a: String,
    /// The second body's name; limits, motors and reactions are of b relative to a. Not with
    /// `Chain`.
    #[serde(default)]
    pub body_b: String,
    /// What the joint allows, with its anchors and axis.
    pub kind: JointKindSpec,
    /// Hinge: angles of b relative to a, degrees; cone-twist: its twist, degrees; slider:
    /// offsets along the axis, m;
    /// distance: the least and greatest length, m (a rope). `(lo, hi)` with lo ≤ hi.
    #[serde(default)]
    pub limits: Option<(f64, f64)>,
    /// Hinge or slider motor: `(speed: rad/s or m/s, max_force: N·m or N)`.
    #[serde(default)]
    pub motor: Option<Motor>,
    /// Hinge or slider servo, not with a motor: `(target: degrees or m, hertz: …,
    /// damping_ratio: …, max_force: N·m or N)`.
    #[serde(default)]
    pub servo: Option<Servo>,
    /// Distance spring toward the length at creation: `(hertz: …, damping_ratio: …)`.
    #[serde(default)]
    pub spring: Option<Spring>,
    /// The load that breaks the joint: `(force: N, torque: N·m)`, either may be `inf`.
    #[serde(default)]
    pub breaking: Option<Breaking>,
    /// Whether the two bodies still collide with each other; omitted, false.
    #[serde(default)]
    pub colliding: bool,
}

/// A joint's kind, as the engine's `JointDesc` constructors take it; points are in m.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum JointKindSpec {
    /// Spherical joint at `anchor`.
    Ball {
        /// m
        anchor: DVec3,
    },
    /// Revolute joint at `anchor` about `axis`.
    Hinge {
        /// m
        anchor: DVec3,
        /// Any non-zero length.
        axis: DVec3,
    },
    /// Prismatic joint through `anchor` along `axis`.
    Slider {
        /// m
        anchor: DVec3,
        /// Any non-zero length.
        axis: DVec3,
    },
    /// Spherical joint at `anchor` whose bodies' axes (both along `axis` as placed) stay
    /// within `cone` degrees of each other; `limits` bound the twist about them, degrees.
    ConeTwist {
        /// m
        anchor: DVec3,
        /// Any non-zero length.
        axis: DVec3,
        /// Degrees, in (0, 180].
        cone: f64,
    },
    /// Weld, its reaction measured at `anchor`.
    Fixed {
        /// m
        anchor: DVec3,
    },
    /// A rod between `anchor_a` on body a and `anchor_b` on body b, of their distance.
    Distance {
        /// m
        anchor_a: DVec3,
        /// m; not equal to `anchor_a`.
        anchor_b: DVec3,
    },
    /// A generator: joins the copies `links_0`, `links_1`, … of the generated body `links`,
    /// each to the next, in generation order (n copies, n − 1 joints; `pin` adds one more).
    /// A `Ball` joint sits halfway between two links' origins; a `Distance` joint is a rod
    /// between them. The joint's `limits`, `spring` and `colliding` apply to each joint.
    Chain {
        /// The `name` of a body line with a `repeat` making at least 2 copies.
        links: String,
        /// `Ball` or `Distance`.
        joint: ChainJoint,
        /// A body that holds the first link as a link before it would: with the first two
        /// links' origins p₀ and p₁, a ball joint at p₀ − (p₁ − p₀)/2, or a rod from
        /// p₀ − (p₁ − p₀) on the pin to p₀. Omitted, the chain hangs free.
        #[serde(default)]
        pin: Option<String>,
    },
}

/// The joint between two links of a `Chain`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ChainJoint {
    /// A ball joint where the links meet.
    Ball,
    /// A rod between the links' origins.
    Distance,
}
