//! Convex hulls: construction from point clouds, topology, and polyhedral mass properties.

use std::f64::consts::PI;

use glam::{DMat3, DQuat, DVec3};
use proptest::prelude::*;
use rigid::physics::{
    AddBodyError, BodyDesc, BodyError, CONTAINMENT_CHECK_BUDGET, ConvexHull, HullError, HullFace,
    MAX_HULL_POINTS, MassProperties, Shape, ShapeError, World,
};

mod common;
use common::xorshift::XorShift;

const DENSITY: f64 = 1200.0;

fn matrix_error(actual: DMat3, expected: DMat3) -> f64 {
    let diff = (actual - expected).to_cols_array();
    let scale = expected
        .to_cols_array()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    diff.iter().fold(0.0f64, |m, x| m.max(x.abs())) / scale
}

fn relative_error(actual: f64, expected: f64) -> f64 {
    (actual - expected).abs() / expected.abs()
}

fn box_corners(half: DVec3) -> Vec<DVec3> {
    (0..8)
        .map(|i| {
            let sign = |bit: u32| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
            DVec3::new(sign(0), sign(1), sign(2)) * half
        })
        .collect()
}

fn face_points(hull: &ConvexHull, face: &HullFace) -> Vec<DVec3> {
    face.vertices
        .iter()
        .map(|&v| hull.vertices[v as usize])
        .collect()
}

/// Everything a well-formed hull promises, with distances allowed to be off by `tolerance`.
fn check_structure(hull: &ConvexHull, tolerance: f64) {
    let (v, e, f) = (hull.vertices.len(), hull.edges.len(), hull.faces.len());
    assert_eq!(v + f, e + 2, "Euler characteristic: V={v} E={e} F={f}");
    for edge in &hull.edges {
        assert!(edge[0] < edge[1] && (edge[1] as usize) < v, "edge {edge:?}");
    }
    let mut sorted = hull.edges.clone();
    sorted.dedup();
    assert_eq!(sorted.len(), e, "duplicate edges");
    for face in &hull.faces {
        assert!(
            (face.normal.length() - 1.0).abs() < 1e-12,
            "normal not unit"
        );
        let points = face_points(hull, face);
        let n = points.len();
        assert!(n >= 3);
        for (i, &p) in points.iter().enumerate() {
            let off_plane = face.normal.dot(p) - face.offset;
            assert!(
                off_plane.abs() <= tolerance,
                "vertex off its face plane by {off_plane}"
            );
            // Strictly left turns about the normal: convex, counter-clockwise, no collinear
            // leftovers.
            let (next, after) = (points[(i + 1) % n], points[(i + 2) % n]);
            let turn = (next - p).cross(after - next).dot(face.normal);
            assert!(turn > 0.0, "face not convex and counter-clockwise");
        }
        for &q in &hull.vertices {
            let above = face.normal.dot(q) - face.offset;
            assert!(above <= tolerance, "hull vertex above a face by {above}");
        }
    }
    assert!(hull.volume() > 0.0);
}

fn assert_contains(hull: &ConvexHull, points: &[DVec3], tolerance: f64) {
    for face in &hull.faces {
        for &p in points {
            let above = face.normal.dot(p) - face.offset;
            assert!(
                above <= tolerance,
                "input point {p} above a face by {above}"
            );
        }
    }
}

fn assert_same_props(actual: MassProperties, expected: MassProperties, tolerance: f64) {
    assert!(relative_error(actual.mass, expected.mass) <= tolerance);
    let size = expected
        .inertia
        .to_cols_array()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let lever = (size / expected.mass).sqrt();
    assert!(
        (actual.center - expected.center).length() <= tolerance * lever,
        "centre {} vs {}",
        actual.center,
        expected.center
    );
    let error = matrix_error(actual.inertia, expected.inertia);
    assert!(error <= tolerance, "inertia relative error {error:e}");
}

#[test]
fn box_corners_give_the_box() {
    let half = DVec3::new(0.5, 0.3, 0.2);
    let hull = ConvexHull::from_points(&box_corners(half)).unwrap();
    assert_eq!(hull.vertices.len(), 8);
    assert_eq!(hull.faces.len(), 6);
    assert_eq!(hull.edges.len(), 12);
    assert!(hull.faces.iter().all(|face| face.vertices.len() == 4));
    check_structure(&hull, 1e-12);
    // The polyhedral sums and the cuboid closed form agree to rounding.
    let expected = MassProperties::of_shape(&Shape::cuboid(half), DENSITY);
    assert_same_props(hull.mass_properties(DENSITY), expected, 1e-12);
    assert!(relative_error(hull.volume(), 8.0 * half.x * half.y * half.z) < 1e-12);
}

#[test]
fn extra_points_on_and_inside_a_box_are_dropped() {
    let half = DVec3::new(1.5, 0.7, 0.4);
    let corners = box_corners(half);
    let mut points = corners.clone();
    points.extend(corners.iter().map(|&c| c * 1.0)); // exact duplicates
    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
        // face centres
        points.push(axis * half);
        points.push(-axis * half);
    }
    for (i, &a) in corners.iter().enumerate() {
        for &b in &corners[i + 1..] {
            // corners differing in one coordinate: edge midpoints and thirds
            if ((a - b).abs().cmpgt(DVec3::ZERO)).bitmask().count_ones() == 1 {
                points.push((a + b) * 0.5);
                points.push(a + (b - a) / 3.0);
            }
        }
    }
    points.push(DVec3::ZERO);
    points.push(half * 0.5);
    points.push(DVec3::new(half.x, 0.1, -0.2)); // inside the +x face
    let hull = ConvexHull::from_points(&points).unwrap();
    assert_eq!(hull.vertices.len(), 8);
    assert_eq!(hull.faces.len(), 6);
    assert_eq!(hull.edges.len(), 12);
    for v in &hull.vertices {
        assert!(corners.contains(v), "{v} is not a corner");
    }
    check_structure(&hull, 1e-12);
    let expected = MassProperties::of_shape(&Shape::cuboid(half), DENSITY);
    assert_same_props(hull.mass_properties(DENSITY), expected, 1e-12);
    assert_contains(&hull, &points, 1e-12);
}

#[test]
fn cuboid_constructor_matches_the_hull_of_its_corners() {
    let half = DVec3::new(0.25, 1.0, 0.5);
    let built = ConvexHull::cuboid(half);
    assert_eq!(
        (built.vertices.len(), built.faces.len(), built.edges.len()),
        (8, 6, 12)
    );
    check_structure(&built, 1e-15);
    built.validate().unwrap();
    let expected = MassProperties::of_shape(&Shape::cuboid(half), DENSITY);
    assert_same_props(built.mass_properties(DENSITY), expected, 1e-12);
    // Outward normals: the +x face has normal +x and offset half.x.
    let plus_x = built.faces.iter().find(|f| f.normal.x > 0.5).unwrap();
    assert!((plus_x.normal - DVec3::X).length() < 1e-15);
    assert!((plus_x.offset - half.x).abs() < 1e-15);
}

/// N points spread evenly over a sphere: the golden-angle (Fibonacci) spiral.
fn fibonacci_sphere(n: usize, radius: f64) -> Vec<DVec3> {
    let golden_angle = PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let ring = (1.0 - y * y).sqrt();
            let theta = golden_angle * i as f64;
            DVec3::new(ring * theta.cos(), y, ring * theta.sin()) * radius
        })
        .collect()
}

/// An inscribed polytope with N evenly spread vertices has ~2N triangles of circumradius ρ
/// with ρ² ≈ 8π/(3√3 N) (equilateral triangles tiling 4π). Under each triangle the sphere
/// bulges out by (ρ² − s²)/2 at distance s from its centre, so the missing volume is
/// Σ 3Aρ²/8 = 1.5πρ² and the relative volume error ≈ 9ρ²/8 ≈ 5.4/N; the missing mass sits
/// at the surface, where x² + y² averages 2/3, so the inertia error ≈ 15ρ²/8 ≈ 9.1/N.
/// Both stay below 1% from N ≈ 1000 on.
#[test]
fn fibonacci_sphere_hull_converges_to_the_sphere() {
    let radius = 0.8;
    let sphere = MassProperties::of_shape(&Shape::sphere(radius), DENSITY);
    let mut previous = (f64::INFINITY, f64::INFINITY);
    for n in [100, 250, 500, 1000, 2000] {
        let points = fibonacci_sphere(n, radius);
        let hull = ConvexHull::from_points(&points).unwrap();
        assert_eq!(hull.vertices.len(), n, "every point on a sphere is extreme");
        check_structure(&hull, 1e-12);
        let props = hull.mass_properties(DENSITY);
        let volume_error = relative_error(props.mass, sphere.mass);
        let inertia_error = matrix_error(props.inertia, sphere.inertia);
        println!("N = {n}: volume error {volume_error:.3e}, inertia error {inertia_error:.3e}");
        assert!(
            volume_error < previous.0 && inertia_error < previous.1,
            "not converging"
        );
        // Twice the estimate above, for the spiral's less regular triangles.
        assert!(volume_error < 2.0 * 5.4 / n as f64);
        assert!(inertia_error < 2.0 * 9.1 / n as f64);
        assert!(props.center.length() < 1e-2 * radius / n as f64 * 100.0);
        previous = (volume_error, inertia_error);
    }
    assert!(previous.0 < 0.01 && previous.1 < 0.01);
}

#[test]
fn off_centre_rotated_box_has_the_rotated_tensor() {
    let half = DVec3::new(0.6, 0.35, 0.15);
    let rotation = DQuat::from_euler(glam::EulerRot::ZYX, 0.4, -0.9, 1.3);
    let centre = DVec3::new(3.0, -1.5, 0.75);
    let points: Vec<DVec3> = box_corners(half)
        .into_iter()
        .map(|c| centre + rotation * c)
        .collect();
    let hull = ConvexHull::from_points(&points).unwrap();
    assert_eq!((hull.faces.len(), hull.edges.len()), (6, 12));
    check_structure(&hull, 1e-12);
    let props = hull.mass_properties(DENSITY);
    let upright = MassProperties::of_shape(&Shape::cuboid(half), DENSITY);
    let r = DMat3::from_quat(rotation);
    let expected = r * upright.inertia * r.transpose();
    assert!((props.center - centre).length() < 1e-12);
    assert!(relative_error(props.mass, upright.mass) < 1e-12);
    assert!(matrix_error(props.inertia, expected) < 1e-12);
    // The products of inertia really are exercised: at least one is a sizeable fraction.
    let products = [expected.y_axis.x, expected.z_axis.x, expected.z_axis.y];
    assert!(products.iter().any(|p| p.abs() > 0.05 * expected.x_axis.x));
    // Symmetric, as an inertia tensor must be.
    assert!(matrix_error(props.inertia, props.inertia.transpose()) < 1e-14);
}

/// The corner tetrahedron x, y, z ≥ 0, x + y + z ≤ 1. Over it (Dirichlet integrals)
/// ∫1 = 1/3! = 1/6, ∫x = 1/4! = 1/24, ∫x² = 2/5! = 1/60, ∫xy = 1/5! = 1/120. About the
/// centroid c = (1/4, 1/4, 1/4): ∫(x−cx)² = 1/60 − (1/6)(1/16) = 1/160 and
/// ∫(x−cx)(y−cy) = 1/120 − 1/96 = −1/480. Hence I_xx = 2/160 = 1/80 and
/// I_xy = −∫(x−cx)(y−cy) = +1/480, per unit density.
#[test]
fn corner_tetrahedron_matches_its_closed_form() {
    let points = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    let scale = 2.0; // every length doubled: volume × 8, inertia × 32
    let scaled: Vec<DVec3> = points.iter().map(|&p| p * scale).collect();
    let hull = ConvexHull::from_points(&scaled).unwrap();
    assert_eq!(
        (hull.vertices.len(), hull.faces.len(), hull.edges.len()),
        (4, 4, 6)
    );
    check_structure(&hull, 1e-14);
    let props = hull.mass_properties(DENSITY);
    assert!(relative_error(hull.volume(), 8.0 / 6.0) < 1e-14);
    assert!(relative_error(props.mass, DENSITY * 8.0 / 6.0) < 1e-14);
    assert!((props.center - DVec3::splat(0.25 * scale)).length() < 1e-14);
    let k = DENSITY * scale.powi(5);
    let diagonal = k / 80.0;
    let product = k / 480.0;
    let expected = DMat3::from_cols(
        DVec3::new(diagonal, product, product),
        DVec3::new(product, diagonal, product),
        DVec3::new(product, product, diagonal),
    );
    assert!(matrix_error(props.inertia, expected) < 1e-13);
}

/// An irregular hull against Monte Carlo integration over its bounding box, with a
/// point-in-hull test by face planes: an independent check of the polyhedral sums,
/// products of inertia included.
#[test]
fn irregular_hull_matches_monte_carlo() {
    let mut rng = XorShift(0x0123_4567_89AB_CDEF);
    let stretch = DVec3::new(1.5, 0.8, 0.5);
    let shift = DVec3::new(0.4, -0.3, 0.2);
    let rotation = DQuat::from_axis_angle(DVec3::new(0.6, 0.0, 0.8), 0.9);
    let points: Vec<DVec3> = (0..40)
        .map(|_| rotation * (rng.in_unit_cube() * stretch) + shift)
        .collect();
    let hull = ConvexHull::from_points(&points).unwrap();
    let props = hull.mass_properties(DENSITY);

    let (min, max) = points.iter().fold(
        (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let inside = |p: DVec3| hull.faces.iter().all(|f| f.normal.dot(p) <= f.offset);
    const SAMPLES: usize = 400_000;
    let mut hits = 0usize;
    let mut first = DVec3::ZERO;
    let mut second = DMat3::ZERO;
    for _ in 0..SAMPLES {
        let p = min + (max - min) * (rng.in_unit_cube() * 0.5 + 0.5);
        if inside(p) {
            hits += 1;
            first += p;
            second += DMat3::from_cols(p * p.x, p * p.y, p * p.z);
        }
    }
    let box_volume = (max - min).x * (max - min).y * (max - min).z;
    let cell_mass = DENSITY * box_volume / SAMPLES as f64;
    let mass = hits as f64 * cell_mass;
    let centre = first / hits as f64;
    // Second moments about the Monte Carlo centre, then I = tr(S) 1 − S.
    let central = second * cell_mass
        - DMat3::from_cols(centre * centre.x, centre * centre.y, centre * centre.z) * mass;
    let trace = central.x_axis.x + central.y_axis.y + central.z_axis.z;
    let inertia = DMat3::IDENTITY * trace - central;
    // The hull fills a sizeable fraction f of its box, so the hit count's relative standard
    // error sqrt((1 − f)/(f N)) is below 0.3% for N = 4e5; 1.5% is over 5 of them, for the
    // mass, the centre (relative to the hull's size) and the tensor's largest entry.
    println!(
        "Monte Carlo: mass {:.2e}, centre {:.2e}, inertia {:.2e}",
        relative_error(props.mass, mass),
        (props.center - centre).length() / (max - min).length(),
        matrix_error(props.inertia, inertia)
    );
    assert!(relative_error(props.mass, mass) < 0.015);
    assert!((props.center - centre).length() < 0.015 * (max - min).length());
    assert!(matrix_error(props.inertia, inertia) < 0.015);
    let products = [inertia.y_axis.x, inertia.z_axis.x, inertia.z_axis.y];
    assert!(products.iter().any(|p| p.abs() > 0.05 * inertia.x_axis.x));
}

/// A small box far from the origin: its coordinates carry rounding a thousand times its own
/// size, which the construction tolerances must absorb.
#[test]
fn small_box_far_from_the_origin() {
    let half = DVec3::new(2e-3, 1e-3, 5e-4);
    let centre = DVec3::new(1e3, -2e3, 5e2);
    let rotation = DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 1.0).normalize(), 0.3);
    let mut points: Vec<DVec3> = box_corners(half)
        .into_iter()
        .map(|c| centre + rotation * c)
        .collect();
    let edge_midpoints: Vec<DVec3> = points.iter().map(|&p| (p + points[0]) * 0.5).collect();
    points.extend(edge_midpoints);
    let hull = ConvexHull::from_points(&points).unwrap();
    assert_eq!(
        (hull.vertices.len(), hull.faces.len(), hull.edges.len()),
        (8, 6, 12)
    );
    hull.validate().unwrap();
    // Coordinates of 2e3 m are rounded to ~5e-13 m: relative to a 1e-3 m box, 1e-9 is
    // a comfortable bound on the volume and inertia errors this causes.
    let expected = MassProperties::of_shape(&Shape::cuboid(half), DENSITY);
    let props = hull.mass_properties(DENSITY);
    assert!(relative_error(props.mass, expected.mass) < 1e-9);
    assert!((props.center - centre).length() < 1e-12 * centre.length());
    let r = DMat3::from_quat(rotation);
    assert!(matrix_error(props.inertia, r * expected.inertia * r.transpose()) < 1e-9);
}

/// The same cloud in another order gives the same solid; the same cloud twice gives the
/// identical hull (construction uses no hash-order or other run-dependent choice).
#[test]
fn hull_is_deterministic_and_order_independent() {
    let points = fibonacci_sphere(500, 1.0);
    let first = ConvexHull::from_points(&points).unwrap();
    assert_eq!(first, ConvexHull::from_points(&points).unwrap());
    let mut reversed = points.clone();
    reversed.reverse();
    let other = ConvexHull::from_points(&reversed).unwrap();
    assert_eq!(other.vertices.len(), first.vertices.len());
    assert!(relative_error(other.volume(), first.volume()) < 1e-12);
    let (a, b) = (first.mass_properties(1.0), other.mass_properties(1.0));
    assert!(matrix_error(a.inertia, b.inertia) < 1e-12);
}

#[test]
fn support_reaches_the_farthest_input_point() {
    let points = fibonacci_sphere(300, 1.0)
        .into_iter()
        .map(|p| p * DVec3::new(2.0, 1.0, 0.5) + DVec3::new(0.1, 0.2, 0.3))
        .collect::<Vec<_>>();
    let hull = ConvexHull::from_points(&points).unwrap();
    for direction in fibonacci_sphere(64, 1.0) {
        let best = points
            .iter()
            .map(|p| p.dot(direction))
            .fold(f64::MIN, f64::max);
        assert!((hull.support(direction).dot(direction) - best).abs() < 1e-14);
    }
}

#[test]
fn degenerate_inputs_are_errors() {
    let three = [DVec3::ZERO, DVec3::X, DVec3::Y];
    assert_eq!(
        ConvexHull::from_points(&three),
        Err(HullError::TooFewPoints(3))
    );
    assert_eq!(
        ConvexHull::from_points(&[]),
        Err(HullError::TooFewPoints(0))
    );

    let tilt = DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 0.3).normalize(), 0.8);
    let grid: Vec<DVec3> = (0..25)
        .map(|i| tilt * DVec3::new((i % 5) as f64, (i / 5) as f64, 0.0) + DVec3::splat(7.0))
        .collect();
    assert!(matches!(
        ConvexHull::from_points(&grid),
        Err(HullError::Degenerate(_))
    ));

    let line: Vec<DVec3> = (0..10)
        .map(|i| DVec3::new(1.0, 2.0, 3.0) * i as f64)
        .collect();
    assert!(matches!(
        ConvexHull::from_points(&line),
        Err(HullError::Degenerate(_))
    ));

    let same = vec![DVec3::new(0.5, -0.25, 2.0); 6];
    assert!(matches!(
        ConvexHull::from_points(&same),
        Err(HullError::Degenerate(_))
    ));

    let mut with_nan = box_corners(DVec3::ONE);
    with_nan[5].y = f64::NAN;
    assert_eq!(
        ConvexHull::from_points(&with_nan),
        Err(HullError::NotFinite(5))
    );
    let mut with_infinity = box_corners(DVec3::ONE);
    with_infinity[2].z = f64::NEG_INFINITY;
    assert_eq!(
        ConvexHull::from_points(&with_infinity),
        Err(HullError::NotFinite(2))
    );
}

#[test]
fn clouds_up_to_the_point_limit_are_hulls_and_larger_ones_are_errors() {
    // The limit itself is accepted: a box's corners and interior points fill it.
    let half = DVec3::new(1.0, 0.5, 0.25);
    let mut random = XorShift(0x9e37_79b9_7f4a_7c15);
    let mut points = box_corners(half);
    while points.len() < MAX_HULL_POINTS {
        points.push(random.in_unit_cube() * half * 0.99);
    }
    let hull = ConvexHull::from_points(&points).unwrap();
    assert_eq!(hull.vertices.len(), 8);
    assert_eq!(hull.faces.len(), 6);

    points.push(DVec3::ZERO);
    let too_many = MAX_HULL_POINTS + 1;
    assert_eq!(
        ConvexHull::from_points(&points),
        Err(HullError::TooManyPoints(too_many))
    );
    assert_eq!(
        Shape::hull(&points),
        Err(ShapeError::Hull(HullError::TooManyPoints(too_many)))
    );
    let message = HullError::TooManyPoints(too_many).to_string();
    assert!(
        message.contains("100001") && message.contains("100000"),
        "{message}"
    );
}

#[test]
fn a_hand_built_hull_with_too_many_vertices_is_refused_by_the_world() {
    // Vertices no face uses, inside the box: only the count is wrong.
    let mut crowded = ConvexHull::cuboid(DVec3::ONE);
    crowded
        .vertices
        .resize(MAX_HULL_POINTS + 1, DVec3::splat(0.5));
    assert_eq!(
        crowded.validate(),
        Err(HullError::TooManyPoints(MAX_HULL_POINTS + 1))
    );
    let shape = Shape::ConvexHull(std::sync::Arc::new(crowded));
    let mut world = World::default();
    let error = world.add_body(BodyDesc::dynamic(shape)).unwrap_err();
    assert!(
        matches!(
            error,
            AddBodyError::Invalid(BodyError::Shape {
                source: ShapeError::Hull(HullError::TooManyPoints(_)),
                ..
            })
        ),
        "{error:?}"
    );
    assert!(world.bodies().is_empty());
}

/// Construction tolerances are about 1e4 f64 epsilons (2.2e-12) of the cloud's half-extent.
#[test]
fn thin_slabs_are_hulls_until_they_flatten_below_tolerance() {
    for thickness in [1e-3, 1e-6, 1e-8] {
        let half = DVec3::new(1.0, 1.0, thickness);
        let mut slab = box_corners(half);
        // Interior points and points on the top and bottom faces, inside the corners.
        slab.extend(fibonacci_sphere(60, 0.9).iter().map(|p| *p * half));
        slab.extend(
            fibonacci_sphere(60, 0.7)
                .iter()
                .map(|p| p.with_z(thickness)),
        );
        slab.extend(
            fibonacci_sphere(60, 0.7)
                .iter()
                .map(|p| p.with_z(-thickness)),
        );
        let hull = ConvexHull::from_points(&slab).unwrap();
        assert_eq!((hull.vertices.len(), hull.faces.len()), (8, 6));
        // A box volume from exact corners: rounding only.
        assert!(relative_error(hull.volume(), 8.0 * thickness) < 1e-12);
    }
    // Relative thickness 1e-13 is below tolerance: a flat cloud.
    let flat = box_corners(DVec3::new(1.0, 1.0, 1e-13));
    assert!(matches!(
        ConvexHull::from_points(&flat),
        Err(HullError::Degenerate(_))
    ));
}

/// Random points in a rotated slab: nothing is exactly coplanar, but the top and bottom
/// surfaces are nearly flat.
#[test]
fn random_thin_slabs_give_valid_hulls() {
    let rotation = DQuat::from_axis_angle(DVec3::new(0.1, 0.9, 0.4).normalize(), 1.1);
    for thickness in [1e-2, 1e-4, 1e-6, 1e-8] {
        for seed in 0..10 {
            let mut rng = XorShift(0x2545_F491_4F6C_DD1D + seed);
            let points: Vec<DVec3> = (0..300)
                .map(|_| rotation * (rng.in_unit_cube() * DVec3::new(1.0, 1.0, thickness)))
                .collect();
            let hull = ConvexHull::from_points(&points).unwrap();
            // As for the random clouds below: on_plane tolerance (2.2e-12) plus refitting.
            check_structure(&hull, 1e-10);
            assert_contains(&hull, &points, 1e-10);
        }
    }
}

#[test]
fn validate_catches_hand_built_mistakes() {
    let good = ConvexHull::cuboid(DVec3::new(0.5, 0.5, 0.5));
    assert_eq!(good.validate(), Ok(()));

    let mut dangling = good.clone();
    dangling.faces[2].vertices[1] = 99;
    assert_eq!(dangling.validate(), Err(HullError::InvalidFace(2)));

    // Reversed windings with planes left as they were pass every per-face check but enclose
    // a negative volume.
    let mut inside_out = good.clone();
    inside_out
        .faces
        .iter_mut()
        .for_each(|f| f.vertices.reverse());
    assert!(matches!(
        inside_out.validate(),
        Err(HullError::Degenerate(_))
    ));

    let mut wrong_offset = good.clone();
    wrong_offset.faces[4].offset += 0.01;
    assert_eq!(wrong_offset.validate(), Err(HullError::BadPlane(4)));

    let mut flipped_normal = good.clone();
    flipped_normal.faces[1].normal = -flipped_normal.faces[1].normal;
    flipped_normal.faces[1].offset = -flipped_normal.faces[1].offset;
    assert_eq!(flipped_normal.validate(), Err(HullError::NotConvex(1)));

    let mut dented = good.clone();
    dented.vertices[0] *= 0.5; // pulls a corner in: its three faces stop being planar
    assert!(matches!(dented.validate(), Err(HullError::BadPlane(_))));

    let mut bulged = good.clone();
    bulged.vertices.push(DVec3::new(0.0, 0.0, 2.0)); // a vertex no face uses, outside
    assert!(matches!(bulged.validate(), Err(HullError::NotConvex(_))));

    let mut not_finite = good.clone();
    not_finite.vertices[3].x = f64::INFINITY;
    assert_eq!(not_finite.validate(), Err(HullError::NotFinite(3)));

    let tiny = ConvexHull::cuboid(DVec3::new(0.5, 0.5, 1e-6));
    assert!(matches!(
        tiny.validate(),
        Err(HullError::ExtentOutOfRange(_))
    ));

    let mut too_few = good.clone();
    too_few.vertices.truncate(3);
    assert_eq!(too_few.validate(), Err(HullError::TooFewPoints(3)));

    assert!(
        Shape::hull(&box_corners(DVec3::ONE))
            .unwrap()
            .validate()
            .is_ok()
    );
}

/// Random clouds with the structures that break naive hulls: exact duplicates, points on a
/// common plane (on the hull or cutting through it, exactly or within a small jitter) and
/// integer lattices (many collinear and coplanar points at once); then scaled and moved off
/// the origin.
fn cloud() -> impl Strategy<Value = Vec<DVec3>> {
    let point =
        (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64).prop_map(|(x, y, z)| DVec3::new(x, y, z));
    let lattice_point = (0..4i32, 0..4i32, 0..4i32)
        .prop_map(|(x, y, z)| DVec3::new(x as f64, y as f64, z as f64) * 0.5 - 0.75);
    let base = prop_oneof![
        prop::collection::vec(point.clone(), 4..200),
        prop::collection::vec(lattice_point, 4..80),
    ];
    let planar = (
        prop::collection::vec((-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64), 0..40),
        point.clone(),
        0.0..1.0f64,
        any::<bool>(),
        prop_oneof![Just(0.0), Just(1e-9), Just(1e-6)],
    );
    let placement = (
        -3.0..3.0f64,
        prop_oneof![Just(DVec3::ZERO), point.clone()],
        0.0..3.0f64,
    );
    (
        base,
        prop::collection::vec(any::<prop::sample::Index>(), 0..30),
        planar,
        placement,
    )
        .prop_map(|(mut points, duplicates, planar, placement)| {
            let picks: Vec<DVec3> = duplicates
                .iter()
                .map(|i| points[i.index(points.len())])
                .collect();
            points.extend(picks);
            // A plane z = 1 (the cloud's top: on the hull) or a tilted plane across it.
            let (uvs, normal, height, on_top, jitter) = planar;
            let tilt = DQuat::from_rotation_arc(DVec3::Z, normal.normalize_or(DVec3::Z));
            for (u, v, w) in uvs {
                let p = if on_top {
                    DVec3::new(u, v, 1.0 - jitter * w.abs())
                } else {
                    tilt * DVec3::new(u, v, height - 0.5 + jitter * w)
                };
                points.push(p);
            }
            let (log_scale, direction, log_distance) = placement;
            let offset = direction * 10f64.powf(log_distance);
            points
                .iter()
                .map(|&p| p * 10f64.powf(log_scale) + offset)
                .collect()
        })
}

/// Farthest distance of the cloud from a plane through three of its points chosen the simple
/// way (first point, farthest from it, farthest from their line), relative to its size: zero
/// for a flat cloud, of the order of its thickness otherwise.
fn flatness(points: &[DVec3]) -> f64 {
    let farthest = |measure: &dyn Fn(DVec3) -> f64| {
        points
            .iter()
            .copied()
            .max_by(|p, q| measure(*p).total_cmp(&measure(*q)))
            .unwrap()
    };
    let a = points[0];
    let b = farthest(&|p| (p - a).length());
    let size = (b - a).length();
    if size == 0.0 {
        return 0.0;
    }
    let c = farthest(&|p| (p - a).cross(b - a).length());
    let normal = (b - a).cross(c - a);
    if normal.length() <= 1e-12 * size * size {
        return 0.0;
    }
    let normal = normal.normalize();
    points
        .iter()
        .map(|p| normal.dot(*p - a).abs())
        .fold(0.0, f64::max)
        / size
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    #[test]
    fn random_clouds_give_valid_hulls(points in cloud()) {
        let extent = points.iter().fold(0.0f64, |m, p| m.max(p.abs().max_element()));
        match ConvexHull::from_points(&points) {
            Ok(hull) => {
                // Construction counts points within ~2e-12 × extent of a plane as on it, and
                // merged faces are refitted planes: 1e-9 × extent leaves a wide margin.
                let tolerance = 1e-9 * extent;
                check_structure(&hull, tolerance);
                assert_contains(&hull, &points, tolerance);
                for v in &hull.vertices {
                    prop_assert!(points.contains(v));
                }
                if hull.validate().is_err() {
                    // Only the size limits may reject a hull built here.
                    prop_assert!(matches!(hull.validate(), Err(HullError::ExtentOutOfRange(_))), "{:?}", hull.validate());
                }
            }
            Err(HullError::Degenerate(_)) => {
                let flat = flatness(&points);
                prop_assert!(flat < 1e-9, "a cloud {flat:e} thick was called degenerate");
            }
            Err(other) => prop_assert!(false, "unexpected error {other:?}"),
        }
    }
}

/// A hull beyond `CONTAINMENT_CHECK_BUDGET` vertex-face pairs is validated edge by edge
/// (checking each vertex against each face of a 100 000-point hull took 16 s): a convex one
/// passes, and a dent whose faces' planes were refitted, so that every face is still flat,
/// is caught as a surface that is not convex.
#[test]
fn a_large_hull_is_validated_edge_by_edge() {
    let hull = ConvexHull::from_points(&fibonacci_sphere(4000, 1.0)).unwrap();
    assert!(hull.vertices.len() * hull.faces.len() > CONTAINMENT_CHECK_BUDGET);
    assert_eq!(hull.validate(), Ok(()));
    // A fresh copy, as `validate` keeps its result.
    let mut dented = ConvexHull::new(
        hull.vertices.clone(),
        hull.faces.clone(),
        hull.edges.clone(),
    );
    dented.vertices[1234] *= 0.9;
    for face in &mut dented.faces {
        let corner = |k: usize| dented.vertices[face.vertices[k] as usize];
        let area: DVec3 = (0..face.vertices.len())
            .map(|k| corner(k).cross(corner((k + 1) % face.vertices.len())))
            .sum();
        face.normal = area.normalize();
        face.offset = face.normal.dot(corner(0));
    }
    assert_eq!(dented.validate(), Err(HullError::NotConvexSurface));
    // A vertex on no face cannot be placed by the edge-by-edge check.
    let mut loose = ConvexHull::new(
        hull.vertices.clone(),
        hull.faces.clone(),
        hull.edges.clone(),
    );
    loose.vertices.push(DVec3::ZERO);
    assert_eq!(loose.validate(), Err(HullError::LooseVertex(4000)));
}
