//! Exact mass properties of every shape: mass, centre of mass and inertia tensor.
//!
//! Primitives use their closed forms; hulls use polyhedral volume integrals (see `hull.rs`);
//! compounds combine their parts with the parallel-axis theorem.

use std::f64::consts::PI;

use glam::{DMat3, DVec3};

use crate::physics::geometry::shape::Shape;

/// Mass properties in the shape's local frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass in shape coordinates.
    pub center: DVec3,
    /// Inertia tensor about the centre of mass, in shape axes.
    pub inertia: DMat3,
}

impl MassProperties {
    /// Mass properties of `shape` filled with uniform `density` (kg/m³).
    pub fn of_shape(shape: &Shape, density: f64) -> MassProperties {
        match shape {
            Shape::Sphere { radius } => sphere(*radius, density),
            Shape::Cuboid { half_extents } => cuboid(*half_extents, density),
            Shape::Capsule {
                half_height,
                radius,
            } => capsule(*half_height, *radius, density),
            Shape::Cylinder {
                half_height,
                radius,
            } => cylinder(*half_height, *radius, density),
            Shape::ConvexHull(hull) => hull.mass_properties(density),
            Shape::Compound(compound) => compound.mass_properties(density),
        }
    }

    /// The same body with its density scaled so that the mass becomes `mass`.
    pub fn with_mass(self, mass: f64) -> MassProperties {
        let scale = mass / self.mass;
        MassProperties {
            mass,
            center: self.center,
            inertia: self.inertia * scale,
        }
    }

    /// Inertia about `point` instead of the centre of mass (parallel-axis theorem).
    pub fn inertia_about(&self, point: DVec3) -> DMat3 {
        self.inertia + parallel_axis_term(self.mass, self.center - point)
    }
}

/// m (|d|² I − d dᵀ): what moving the reference point by `d` adds to an inertia tensor.
pub fn parallel_axis_term(mass: f64, d: DVec3) -> DMat3 {
    (DMat3::IDENTITY * d.length_squared() - outer(d, d)) * mass
}

/// a bᵀ
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// Mass properties of a closed polyhedron whose faces are convex polygons over `vertices`,
/// counter-clockwise seen from outside.
///
/// Each face is fanned into triangles, and each triangle (a, b, c) closes a tetrahedron with a
/// reference point r, taken as the origin below. Summing the tetrahedra's signed integrals
/// gives the solid's (the divergence theorem: the triangles cover the closed surface once,
/// so everything outside the solid cancels). For the tetrahedron (0, a, b, c):
/// - volume V = a · (b × c) / 6,
/// - first moment ∫x dV = V (a + b + c) / 4 (its centroid times its volume),
/// - second moment ∫x xᵀ dV = V/20 (a aᵀ + b bᵀ + c cᵀ + s sᵀ) with s = a + b + c: the map
///   x = a u + b v + c w (Jacobian 6V) sends the unit corner simplex onto it, and over that
///   simplex ∫u² = 2/5! and ∫uv = 1/5!, so ∫x xᵀ = 6V/120 (2 Σ p pᵀ + Σ_{p≠q} p qᵀ).
///
/// The inertia about the centre is then ρ (tr(S) I − S) with S = ∫(x − c)(x − c)ᵀ dV.
pub(crate) fn polyhedron<'a>(
    vertices: &[DVec3],
    faces: impl Iterator<Item = &'a [u32]>,
    density: f64,
) -> MassProperties {
    // Integrating about a point inside the solid keeps every term small: less cancellation.
    let reference = vertices.iter().sum::<DVec3>() / vertices.len().max(1) as f64;
    let mut volume = 0.0;
    let mut first = DVec3::ZERO;
    let mut second = DMat3::ZERO;
    for face in faces {
        let corner = |i: u32| vertices[i as usize] - reference;
        let a = corner(face[0]);
        for pair in face[1..].windows(2) {
            let (b, c) = (corner(pair[0]), corner(pair[1]));
            let tetra_volume = a.dot(b.cross(c)) / 6.0;
            let s = a + b + c;
            volume += tetra_volume;
            first += s * (tetra_volume / 4.0);
            second +=
                (outer(a, a) + outer(b, b) + outer(c, c) + outer(s, s)) * (tetra_volume / 20.0);
        }
    }
    let centroid = first / volume;
    let central = second - outer(centroid, centroid) * volume;
    let trace = central.x_axis.x + central.y_axis.y + central.z_axis.z;
    MassProperties {
        mass: density * volume,
        center: reference + centroid,
        inertia: (DMat3::IDENTITY * trace - central) * density,
    }
}

fn diagonal(ixx: f64, iyy: f64, izz: f64) -> DMat3 {
    DMat3::from_diagonal(DVec3::new(ixx, iyy, izz))
}

fn sphere(radius: f64, density: f64) -> MassProperties {
    let mass = density * 4.0 / 3.0 * PI * radius.powi(3);
    let i = 0.4 * mass * radius * radius;
    MassProperties {
        mass,
        center: DVec3::ZERO,
        inertia: diagonal(i, i, i),
    }
}

fn cuboid(half: DVec3, density: f64) -> MassProperties {
    let mass = density * 8.0 * half.x * half.y * half.z;
    let d = half * 2.0;
    let k = mass / 12.0;
    MassProperties {
        mass,
        center: DVec3::ZERO,
        inertia: diagonal(
            k * (d.y * d.y + d.z * d.z),
            k * (d.x * d.x + d.z * d.z),
            k * (d.x * d.x + d.y * d.y),
        ),
    }
}

fn cylinder(half_height: f64, radius: f64, density: f64) -> MassProperties {
    let height = 2.0 * half_height;
    let mass = density * PI * radius * radius * height;
    let axial = 0.5 * mass * radius * radius;
    let transverse = mass * (3.0 * radius * radius + height * height) / 12.0;
    MassProperties {
        mass,
        center: DVec3::ZERO,
        inertia: diagonal(transverse, axial, transverse),
    }
}

/// A cylinder of height 2h plus two hemispherical caps; each cap's own centre of mass sits
/// 3r/8 from its flat face, hence the 3hr/4 cross term.
fn capsule(half_height: f64, radius: f64, density: f64) -> MassProperties {
    let height = 2.0 * half_height;
    let r2 = radius * radius;
    let cylinder_mass = density * PI * r2 * height;
    let caps_mass = density * 4.0 / 3.0 * PI * r2 * radius;
    let axial = cylinder_mass * r2 / 2.0 + caps_mass * 2.0 * r2 / 5.0;
    let transverse = cylinder_mass * (height * height / 12.0 + r2 / 4.0)
        + caps_mass * (2.0 * r2 / 5.0 + height * height / 4.0 + 3.0 * height * radius / 8.0);
    MassProperties {
        mass: cylinder_mass + caps_mass,
        center: DVec3::ZERO,
        inertia: diagonal(transverse, axial, transverse),
    }
}
