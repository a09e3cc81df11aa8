//! Closed-form mass properties of the primitives, checked against integrals computed here by
//! other means (slices, lattices, Monte Carlo), and compounds against the parallel-axis theorem.

use std::f64::consts::PI;
use std::sync::Arc;

use glam::{DMat3, DQuat, DVec3};
use rigid::physics::{Compound, CompoundPart, ConvexHull, MassProperties, Pose, Shape};

mod common;
use common::xorshift::XorShift;

const DENSITY: f64 = 750.0;

fn relative_error(actual: f64, expected: f64) -> f64 {
    (actual - expected).abs() / expected.abs()
}

/// Largest entry of |a − b| over the largest entry of |b|.
fn matrix_error(actual: DMat3, expected: DMat3) -> f64 {
    let diff = (actual - expected).to_cols_array();
    let scale = expected
        .to_cols_array()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    diff.iter().fold(0.0f64, |m, x| m.max(x.abs())) / scale
}

fn assert_close(what: &str, actual: f64, expected: f64, tolerance: f64) {
    let error = relative_error(actual, expected);
    assert!(
        error <= tolerance,
        "{what}: got {actual}, expected {expected} (relative error {error:e} > {tolerance:e})"
    );
}

fn assert_matrix_close(what: &str, actual: DMat3, expected: DMat3, tolerance: f64) {
    let error = matrix_error(actual, expected);
    assert!(
        error <= tolerance,
        "{what}: got {actual}, expected {expected} (relative error {error:e} > {tolerance:e})"
    );
}

/// Mass and inertia of a solid of revolution about the y axis with radius profile `radius(y)`
/// on [y0, y1], integrated as a stack of thin discs with composite Simpson's rule.
/// A disc of radius R and thickness dy has dm = ρπR² dy, axial inertia dm R²/2 and, about the
/// x axis through the origin, dm (R²/4 + y²).
struct Revolution {
    mass: f64,
    axial: f64,
    transverse: f64,
}

fn integrate_revolution(radius: impl Fn(f64) -> f64, y0: f64, y1: f64) -> Revolution {
    const INTERVALS: usize = 2000; // even, as Simpson's rule needs
    let step = (y1 - y0) / INTERVALS as f64;
    let mut total = Revolution {
        mass: 0.0,
        axial: 0.0,
        transverse: 0.0,
    };
    for i in 0..=INTERVALS {
        let weight = if i == 0 || i == INTERVALS {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        let y = y0 + step * i as f64;
        let r2 = radius(y).powi(2);
        let dm = DENSITY * PI * r2 * weight * step / 3.0;
        total.mass += dm;
        total.axial += dm * r2 / 2.0;
        total.transverse += dm * (r2 / 4.0 + y * y);
    }
    total
}

/// A radius profile R(y) and the interval [y0, y1] it covers.
type ProfilePiece<'a> = (&'a dyn Fn(f64) -> f64, f64, f64);

/// Sums of the pieces of a piecewise profile, each integrated separately so that Simpson's
/// rule never straddles a kink.
fn integrate_pieces(pieces: &[ProfilePiece]) -> Revolution {
    pieces.iter().fold(
        Revolution {
            mass: 0.0,
            axial: 0.0,
            transverse: 0.0,
        },
        |sum, &(radius, y0, y1)| {
            let piece = integrate_revolution(radius, y0, y1);
            Revolution {
                mass: sum.mass + piece.mass,
                axial: sum.axial + piece.axial,
                transverse: sum.transverse + piece.transverse,
            }
        },
    )
}

/// Checks a y-symmetric solid of revolution: centre at the origin, diagonal (T, A, T) tensor.
fn assert_revolution(props: MassProperties, expected: Revolution, tolerance: f64) {
    assert_close("mass", props.mass, expected.mass, tolerance);
    assert!(props.center.length() < 1e-15, "centre {}", props.center);
    let tensor = DMat3::from_diagonal(DVec3::new(
        expected.transverse,
        expected.axial,
        expected.transverse,
    ));
    assert_matrix_close("inertia", props.inertia, tensor, tolerance);
}

#[test]
fn sphere_matches_disc_slices() {
    let r = 0.7;
    let props = MassProperties::of_shape(&Shape::sphere(r), DENSITY);
    // R(y)² = r² − y² is a polynomial, so Simpson's error (∝ step⁴ · R⁴'s 4th derivative)
    // is about 1e-13 relative with 2000 slices; 1e-10 leaves room for rounding.
    let slices = integrate_revolution(|y| (r * r - y * y).max(0.0).sqrt(), -r, r);
    assert_revolution(props, slices, 1e-10);
}

#[test]
fn cylinder_matches_disc_slices() {
    let (h, r) = (0.9, 0.35);
    let props = MassProperties::of_shape(&Shape::cylinder(h, r), DENSITY);
    // Constant profile: Simpson is exact for the y² term; only rounding remains.
    let slices = integrate_revolution(|_| r, -h, h);
    assert_revolution(props, slices, 1e-10);
}

#[test]
fn capsule_matches_disc_slices() {
    let (h, r) = (0.6, 0.25);
    let props = MassProperties::of_shape(&Shape::capsule(h, r), DENSITY);
    let lower_cap = |y: f64| (r * r - (y + h).powi(2)).max(0.0).sqrt();
    let body = |_: f64| r;
    let upper_cap = |y: f64| (r * r - (y - h).powi(2)).max(0.0).sqrt();
    let slices = integrate_pieces(&[
        (&lower_cap, -h - r, -h),
        (&body, -h, h),
        (&upper_cap, h, h + r),
    ]);
    // Same polynomial-integrand argument as for the sphere.
    assert_revolution(props, slices, 1e-10);
}

#[test]
fn capsule_matches_monte_carlo() {
    let (h, r) = (0.5, 0.3);
    let props = MassProperties::of_shape(&Shape::capsule(h, r), DENSITY);
    let half_box = DVec3::new(r, h + r, r);
    let box_volume = 8.0 * half_box.x * half_box.y * half_box.z;
    let inside = |p: DVec3| {
        let on_axis = DVec3::new(0.0, p.y.clamp(-h, h), 0.0);
        (p - on_axis).length_squared() <= r * r
    };
    const SAMPLES: usize = 400_000;
    let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
    let mut hits = 0usize;
    let mut second = DMat3::ZERO; // Σ p pᵀ over hits
    let mut first = DVec3::ZERO;
    for _ in 0..SAMPLES {
        let p = rng.in_box(half_box);
        if inside(p) {
            hits += 1;
            first += p;
            second += DMat3::from_cols(p * p.x, p * p.y, p * p.z);
        }
    }
    let cell_mass = DENSITY * box_volume / SAMPLES as f64;
    let mass = hits as f64 * cell_mass;
    let trace = second.x_axis.x + second.y_axis.y + second.z_axis.z;
    let inertia = (DMat3::IDENTITY * trace - second) * cell_mass;
    // The capsule (0.396 m³) fills f ≈ 69% of its box (0.576 m³), so the mass's relative
    // standard error is sqrt((1 − f)/(f N)) ≈ 0.11%; the inertia's, weighted towards the
    // rim, is a few times that. 1% is several standard errors for both.
    println!(
        "Monte Carlo capsule: mass {:.2e}, inertia {:.2e}",
        relative_error(props.mass, mass),
        matrix_error(props.inertia, inertia)
    );
    assert_close("mass", props.mass, mass, 0.01);
    assert!(
        (first / hits as f64).length() < 0.01 * r,
        "Monte Carlo centre off"
    );
    assert_matrix_close("inertia", props.inertia, inertia, 0.01);
}

#[test]
fn cuboid_matches_point_lattice() {
    let half = DVec3::new(0.3, 0.5, 0.8);
    let props = MassProperties::of_shape(&Shape::cuboid(half), DENSITY);
    // Midpoint rule on an n³ lattice: each cell's ∫x² exceeds its centre value by Δ³/12 per
    // unit area, so the relative error of every second moment is exactly 1/n² = 1e-4.
    const N: usize = 100;
    let cell = half * 2.0 / N as f64;
    let cell_mass = DENSITY * cell.x * cell.y * cell.z;
    let mut mass = 0.0;
    let mut second = DMat3::ZERO;
    for i in 0..N {
        for j in 0..N {
            for k in 0..N {
                let p = -half + cell * (DVec3::new(i as f64, j as f64, k as f64) + 0.5);
                mass += cell_mass;
                second += DMat3::from_cols(p * p.x, p * p.y, p * p.z) * cell_mass;
            }
        }
    }
    let trace = second.x_axis.x + second.y_axis.y + second.z_axis.z;
    let inertia = DMat3::IDENTITY * trace - second;
    // The lattice mass is exact up to the rounding of 10⁶ additions (≲ 1e-10 relative).
    assert_close("mass", props.mass, mass, 1e-9);
    assert!(props.center.length() < 1e-15);
    assert_matrix_close("inertia", props.inertia, inertia, 1.5e-4);
}

fn part(shape: Shape, translation: DVec3, rotation: DQuat) -> CompoundPart {
    CompoundPart {
        pose: Pose::new(translation, rotation),
        shape,
    }
}

fn compound_props(parts: Vec<CompoundPart>) -> MassProperties {
    let compound = Compound::new(parts).expect("valid compound");
    MassProperties::of_shape(&Shape::Compound(Arc::new(compound)), DENSITY)
}

#[test]
fn two_boxes_side_by_side_equal_one_long_box() {
    let half = DVec3::new(0.4, 0.25, 0.15);
    let offset = DVec3::new(2.0, 1.0, -3.0);
    let props = compound_props(vec![
        part(
            Shape::cuboid(half),
            offset - DVec3::X * half.x,
            DQuat::IDENTITY,
        ),
        part(
            Shape::cuboid(half),
            offset + DVec3::X * half.x,
            DQuat::IDENTITY,
        ),
    ]);
    let long = MassProperties::of_shape(
        &Shape::cuboid(DVec3::new(2.0 * half.x, half.y, half.z)),
        DENSITY,
    );
    // Both sides are sums of a few products: only rounding separates them.
    assert_close("mass", props.mass, long.mass, 1e-12);
    assert!((props.center - offset).length() < 1e-12);
    assert_matrix_close("inertia", props.inertia, long.inertia, 1e-12);
}

#[test]
fn two_spheres_follow_parallel_axis_theorem() {
    let (r, d) = (0.2, 1.5);
    let props = compound_props(vec![
        part(Shape::sphere(r), DVec3::X * d, DQuat::IDENTITY),
        part(Shape::sphere(r), -DVec3::X * d, DQuat::IDENTITY),
    ]);
    let m = DENSITY * 4.0 / 3.0 * PI * r.powi(3);
    let own = 0.4 * m * r * r;
    // About x each sphere spins on its own axis; about y and z each is d off the axis.
    let expected = DMat3::from_diagonal(DVec3::new(
        2.0 * own,
        2.0 * (own + m * d * d),
        2.0 * (own + m * d * d),
    ));
    assert_close("mass", props.mass, 2.0 * m, 1e-12);
    assert!(props.center.length() < 1e-12);
    assert_matrix_close("inertia", props.inertia, expected, 1e-12);
}

#[test]
fn rotated_part_gives_rotated_tensor() {
    let half = DVec3::new(0.5, 0.2, 0.1);
    let rotation = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    let translation = DVec3::new(0.3, -0.2, 0.9);
    let props = compound_props(vec![part(Shape::cuboid(half), translation, rotation)]);
    let body = MassProperties::of_shape(&Shape::cuboid(half), DENSITY);

    // Kinetic energy does not depend on the frame: ωᵀ I ω in compound axes must equal
    // ω_bᵀ I_b ω_b with ω_b = R⁻¹ ω the same spin in the part's own axes.
    for omega in [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(0.3, -1.2, 0.7)] {
        let in_part = rotation.inverse() * omega;
        assert_close(
            "2 × kinetic energy",
            omega.dot(props.inertia * omega),
            in_part.dot(body.inertia * in_part),
            1e-12,
        );
    }
    // Independently: the polyhedral integrals over the placed box's corners.
    let corners: Vec<DVec3> = (0..8)
        .map(|i| {
            let sign = |bit: u32| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
            translation + rotation * (DVec3::new(sign(0), sign(1), sign(2)) * half)
        })
        .collect();
    let hull = ConvexHull::from_points(&corners).expect("box corners span a solid");
    let integrated = hull.mass_properties(DENSITY);
    assert!((props.center - translation).length() < 1e-12);
    assert!((props.center - integrated.center).length() < 1e-12);
    assert_matrix_close("inertia", props.inertia, integrated.inertia, 1e-12);
    let off_diagonal = props.inertia.y_axis.x.abs() + props.inertia.z_axis.x.abs();
    assert!(
        off_diagonal > 1e-3 * props.inertia.x_axis.x,
        "products of inertia vanish"
    );
}

#[test]
fn with_mass_keeps_the_distribution() {
    let props = MassProperties::of_shape(&Shape::cylinder(0.5, 0.2), DENSITY);
    let scaled = props.with_mass(3.0);
    assert_eq!(scaled.mass, 3.0);
    // I/m depends only on the shape.
    assert_matrix_close(
        "inertia per mass",
        scaled.inertia * (1.0 / 3.0),
        props.inertia * (1.0 / props.mass),
        1e-14,
    );
}
