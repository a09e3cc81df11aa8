//! The scene file format: plain serde structs read from RON. Every struct and enum denies
//! unknown fields, so a typo is an error rather than a silently ignored line.
//!
//! Units are SI (m, kg, s, kg/m³), y is up. Angles in `Rotation` are in degrees because people
//! write them by hand; angular velocities are in rad/s because the engine uses them as they are.

use std::collections::BTreeMap;

use glam::DVec3;
use serde::Deserialize;

use crate::physics::{Integrator, Material};
use crate::scene::material_ref::MaterialRef;

/// A parsed scene. `origin` is the file it came from (or the name given to `parse`); every
/// error message starts with it.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename = "Scene")]
pub struct Scene {
    pub name: String,
    #[serde(default)]
    pub description: String,
    #[serde(default)]
    pub settings: SceneSettings,
    #[serde(default)]
    pub camera: Camera,
    /// Environmental forces. None by default: a scene without `Gravity` is weightless.
    #[serde(default)]
    pub forces: Vec<ForceSpec>,
    /// Materials that bodies refer to by name.
    #[serde(default)]
    pub materials: BTreeMap<String, Material>,
    #[serde(default)]
    pub bodies: Vec<BodySpec>,
    #[serde(skip)]
    pub origin: String,
}

#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SceneSettings {
    /// Time step, s; must lie in `scene::DT_RANGE`.
    pub dt: f64,
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
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Camera {
    pub eye: DVec3,
    pub target: DVec3,
}

impl Default for Camera {
    fn default() -> Self {
        Camera {
            eye: DVec3::new(0.0, 5.0, 15.0),
            target: DVec3::new(0.0, 1.0, 0.0),
        }
    }
}

/// The engine's `EnvironmentForce`, with field names checked strictly.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ForceSpec {
    /// Uniform field, m/s²: `Gravity(acceleration: (0, -9.81, 0))`.
    Gravity { acceleration: DVec3 },
    /// F = −k v, k in N·s/m.
    LinearDrag { coefficient: f64 },
    /// F = −c |v| v, c in N·s²/m².
    QuadraticDrag { coefficient: f64 },
    /// F = k (w − v): air moving at `velocity`.
    Wind { velocity: DVec3, coefficient: f64 },
}

/// One body, or a template for many when `repeat` is set.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Generated copies are named `name_0`, `name_1`, … in generation order.
    #[serde(default)]
    pub name: String,
    pub shape: ShapeSpec,
    /// Where the shape's own origin is placed (for a compound, the origin of its parts' frame).
    #[serde(default)]
    pub position: DVec3,
    #[serde(default)]
    pub rotation: Rotation,
    /// m/s
    #[serde(default)]
    pub velocity: DVec3,
    /// rad/s, world axes.
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
    /// Simulated but not drawn, like a machine's front glass.
    #[serde(default)]
    pub hidden: bool,
    #[serde(default)]
    pub repeat: Option<Repeat>,
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ShapeSpec {
    Sphere {
        radius: f64,
    },
    Cuboid {
        half_extents: DVec3,
    },
    /// Along the local y axis.
    Capsule {
        half_height: f64,
        radius: f64,
    },
    /// Along the local y axis.
    Cylinder {
        half_height: f64,
        radius: f64,
    },
    /// The convex hull of the points, in the body's shape frame.
    Hull {
        points: Vec<DVec3>,
    },
    /// Convex parts, each placed in the body's shape frame. Parts may not be compounds.
    Compound {
        parts: Vec<PartSpec>,
    },
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartSpec {
    pub shape: ShapeSpec,
    #[serde(default)]
    pub position: DVec3,
    #[serde(default)]
    pub rotation: Rotation,
}

#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Rotation {
    /// Degrees about the world x axis, then the world y axis, then the world z axis.
    Euler(f64, f64, f64),
    /// `degrees` about `axis` (any non-zero length).
    AxisAngle { axis: DVec3, degrees: f64 },
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
        count: (u32, u32, u32),
        spacing: DVec3,
        #[serde(default)]
        stagger: DVec3,
    },
    /// A triangle of copies in the x–y plane: layer l (0 at the bottom) holds `layers − l`
    /// copies, moved by `((i + l/2) spacing.0, l spacing.1, 0)`, so it has
    /// `layers (layers + 1) / 2` copies in all.
    Pyramid { layers: u32, spacing: (f64, f64) },
}
