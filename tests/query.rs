//! Ray and shape casts against analytic answers.

mod common;

use common::*;
use glam::{DMat3, DQuat, DVec3};
use proptest::prelude::*;
use rigid::physics::ray_cast_shape;
use rigid::physics::{BodyDesc, PosedShape, QueryError, Shape, World, gjk_distance};

const TOL: f64 = 1e-9;

fn assert_close(actual: DVec3, expected: DVec3, tolerance: f64) {
    assert!(
        actual.distance(expected) <= tolerance,
        "{actual} vs {expected}"
    );
}

fn world_with(shapes: Vec<(Shape, DVec3, DQuat)>) -> World {
    let mut world = World::default();
    for (shape, at, rotation) in shapes {
        world
            .add_body(BodyDesc::fixed(shape).at(at).rotated(rotation))
            .unwrap();
    }
    world
}

#[test]
fn ray_hits_sphere_box_and_hull_analytically() {
    // Sphere of radius 1 at (0, 0, 5), ray along +z from the origin, offset by 0.6 in x:
    // hits where z = 5 − √(1 − 0.36) = 4.2.
    let world = world_with(vec![(
        Shape::sphere(1.0),
        DVec3::new(0.0, 0.0, 5.0),
        DQuat::IDENTITY,
    )]);
    let hit = world
        .ray_cast(DVec3::new(0.6, 0.0, 0.0), DVec3::Z * 2.0, 10.0)
        .expect("a valid query")
        .unwrap();
    assert!((hit.distance - 4.2).abs() < TOL);
    assert!((hit.fraction - 0.42).abs() < TOL);
    assert_close(hit.point, DVec3::new(0.6, 0.0, 4.2), TOL);
    assert_close(hit.normal, DVec3::new(0.6, 0.0, -0.8), TOL);

    // Box turned 45° about y: the ray along +x meets the vertical edge at x = 3 − √2/2·... no:
    // a box of half size 1 turned 45° presents an edge at x = 3 − √2; just off-centre the
    // ray meets the face whose normal is (−1, 0, −1)/√2.
    let turn = DQuat::from_rotation_y(std::f64::consts::FRAC_PI_4);
    let world = world_with(vec![(
        Shape::cuboid(DVec3::ONE),
        DVec3::new(3.0, 0.0, 0.0),
        turn,
    )]);
    let hit = world
        .ray_cast(DVec3::new(0.0, 0.0, -0.2), DVec3::X, 10.0)
        .expect("a valid query")
        .unwrap();
    assert!(
        (hit.distance - (3.0 - 2f64.sqrt() + 0.2)).abs() < TOL,
        "{}",
        hit.distance
    );
    assert_close(hit.normal, DVec3::new(-1.0, 0.0, -1.0).normalize(), TOL);

    // Octahedron |x| + |y| + |z| ≤ 1 at the origin, ray down the diagonal towards it.
    let octa = hull_shape(octahedron_hull(DVec3::ONE));
    let posed = PosedShape::new(&octa, DVec3::ZERO, DMat3::IDENTITY);
    let direction = -DVec3::ONE.normalize();
    let hit = ray_cast_shape(&posed, DVec3::splat(2.0), direction, 10.0).unwrap();
    let entry = DVec3::splat(1.0 / 3.0);
    assert!((hit.distance - DVec3::splat(2.0).distance(entry)).abs() < TOL);
    assert_close(hit.point, entry, TOL);
    assert_close(hit.normal, DVec3::ONE.normalize(), TOL);
}

#[test]
fn ray_misses_stops_and_starts_inside() {
    let world = world_with(vec![(
        Shape::cuboid(DVec3::ONE),
        DVec3::new(5.0, 0.0, 0.0),
        DQuat::IDENTITY,
    )]);
    assert!(
        world
            .ray_cast(DVec3::ZERO, DVec3::Y, 100.0)
            .expect("a valid query")
            .is_none()
    );
    assert!(
        world
            .ray_cast(DVec3::ZERO, DVec3::X, 3.9)
            .expect("a valid query")
            .is_none()
    );
    assert!(
        world
            .ray_cast(DVec3::ZERO, DVec3::X, 4.0)
            .expect("a valid query")
            .is_some()
    );
    let inside = world
        .ray_cast(DVec3::new(5.0, 0.5, 0.0), DVec3::X, 10.0)
        .expect("a valid query")
        .unwrap();
    assert_eq!(inside.distance, 0.0);
    assert_close(inside.normal, -DVec3::X, TOL);
}

#[test]
fn ray_picks_the_nearest_body() {
    let world = world_with(vec![
        (
            Shape::sphere(0.5),
            DVec3::new(0.0, 8.0, 0.0),
            DQuat::IDENTITY,
        ),
        (
            Shape::capsule(1.0, 0.25),
            DVec3::new(0.1, 4.0, 0.0),
            DQuat::from_rotation_z(1.0),
        ),
        (
            Shape::cylinder(0.5, 0.5),
            DVec3::new(0.0, 12.0, 0.0),
            DQuat::IDENTITY,
        ),
    ]);
    let hit = world
        .ray_cast(DVec3::ZERO, DVec3::Y, 100.0)
        .expect("a valid query")
        .unwrap();
    assert_eq!(hit.body.0, 1);
    // The capsule's axis (−sin 1, cos 1, 0) passes through (0.1, 4); its surface faces the
    // ray with normal −(cos 1, sin 1, 0), at 0.25 from the axis: 0.1 cos 1 − (y − 4) sin 1 = 0.25.
    let (sin, cos) = 1f64.sin_cos();
    let expected = 4.0 + (0.1 * cos - 0.25) / sin;
    assert!(
        (hit.distance - expected).abs() < 1e-7,
        "{} vs {expected}",
        hit.distance
    );
    assert_close(hit.normal, -DVec3::new(cos, sin, 0.0), 1e-6);
    // Cylinder cap from below.
    let cap = world
        .ray_cast(DVec3::new(0.0, 10.0, 0.2), DVec3::Y, 100.0)
        .expect("a valid query")
        .unwrap();
    assert_eq!(cap.body.0, 2);
    assert!((cap.distance - 1.5).abs() < 1e-7);
    assert_close(cap.normal, -DVec3::Y, 1e-6);
}

#[test]
fn shape_cast_sphere_onto_box() {
    let world = world_with(vec![(
        Shape::cuboid(DVec3::new(2.0, 0.5, 2.0)),
        DVec3::ZERO,
        DQuat::IDENTITY,
    )]);
    let ball = Shape::sphere(0.25);
    let hit = world
        .shape_cast(
            &ball,
            DVec3::new(0.5, 3.0, 0.0),
            DQuat::IDENTITY,
            -DVec3::Y,
            10.0,
        )
        .expect("a valid query")
        .unwrap();
    assert!((hit.distance - 2.25).abs() < 1e-8, "{}", hit.distance);
    assert_close(hit.point, DVec3::new(0.5, 0.5, 0.0), 1e-8);
    assert_close(hit.normal, DVec3::Y, 1e-8);
    let tilted = Shape::cuboid(DVec3::splat(0.5));
    let corner_down = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_4);
    let hit = world
        .shape_cast(
            &tilted,
            DVec3::new(0.0, 3.0, 0.0),
            corner_down,
            -DVec3::Y,
            10.0,
        )
        .expect("a valid query")
        .unwrap();
    assert!((hit.distance - (2.5 - 0.5 * 2f64.sqrt())).abs() < 1e-8);
    assert!(
        world
            .shape_cast(
                &ball,
                DVec3::new(0.0, 3.0, 0.0),
                DQuat::IDENTITY,
                DVec3::Y,
                10.0
            )
            .expect("a valid query")
            .is_none()
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// The hit point is on the surface (GJK distance 0 from the shape, positive just before);
    /// a miss never passes through the shape.
    #[test]
    fn hit_points_lie_on_the_surface(kind in 0..5usize, size in 0.2..1.5f64, r in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64), aim in (-0.5..0.5f64, -0.5..0.5f64)) {
        let shape = match kind {
            0 => Shape::sphere(size),
            1 => Shape::cuboid(DVec3::new(size, 0.5 * size, 0.8 * size)),
            2 => Shape::capsule(size, 0.4 * size),
            3 => Shape::cylinder(size, 0.6 * size),
            _ => hull_shape(octahedron_hull(DVec3::new(size, 0.7 * size, 1.2 * size))),
        };
        let posed = PosedShape::new(&shape, DVec3::ZERO, DMat3::from_quat(rotation_from(DVec3::from(r))));
        let origin = DVec3::new(aim.0, aim.1, -5.0);
        let at = |t: f64| gjk_distance(&posed, &(origin + DVec3::Z * t)).distance;
        let Some(hit) = ray_cast_shape(&posed, origin, DVec3::Z, 10.0) else {
            for k in 0..=1000 {
                prop_assert!(at(k as f64 * 0.01) > 0.0);
            }
            return Ok(());
        };
        prop_assert!(at(hit.distance) < 1e-7);
        prop_assert!(at(hit.distance - 1e-5) > 0.0);
        prop_assert!((hit.normal.length() - 1.0).abs() < 1e-9);
        prop_assert!(hit.normal.z < 0.0);
    }
}

/// An L made of two boxes: a ray through the notch misses, one along the arm hits it.
#[test]
fn compounds_are_cast_against_part_by_part() {
    use rigid::physics::{Compound, CompoundPart, Pose};
    let part = |x: f64, y: f64| CompoundPart {
        pose: Pose::new(DVec3::new(x, y, 0.0), DQuat::IDENTITY),
        shape: Shape::cuboid(DVec3::splat(0.5)),
    };
    let l_shape = Compound::new(vec![part(0.0, 0.0), part(1.0, 0.0), part(0.0, 1.0)]).unwrap();
    let shape = Shape::Compound(std::sync::Arc::new(l_shape));
    let world = world_with(vec![(shape, DVec3::ZERO, DQuat::IDENTITY)]);
    // The notch is the empty unit cube centred at (1, 1, 0).
    assert!(
        world
            .ray_cast(DVec3::new(1.0, 1.0, -5.0), DVec3::Z, 10.0)
            .expect("a valid query")
            .is_none()
    );
    let hit = world
        .ray_cast(DVec3::new(1.0, 0.2, -5.0), DVec3::Z, 10.0)
        .expect("a valid query")
        .unwrap();
    assert!((hit.distance - 4.5).abs() < TOL);
    assert_close(hit.normal, -DVec3::Z, TOL);
    // A small ball dropped into the notch lands on the lower arm (top at y = 0.5).
    let ball = Shape::sphere(0.2);
    let drop = world
        .shape_cast(
            &ball,
            DVec3::new(1.0, 3.0, 0.0),
            DQuat::IDENTITY,
            -DVec3::Y,
            10.0,
        )
        .expect("a valid query")
        .unwrap();
    assert!((drop.distance - 2.3).abs() < 1e-8, "{}", drop.distance);
}

/// Values a query cannot answer for are typed errors, not hits: a NaN origin once returned
/// a hit at distance 0, and a shape of radius −1 a hit.
#[test]
fn bad_query_arguments_are_errors() {
    let mut world = World::default();
    world
        .add_body(BodyDesc::fixed(Shape::cuboid(DVec3::ONE)))
        .unwrap();
    let nan = DVec3::new(f64::NAN, 0.0, 0.0);
    let not_finite = |argument| Err(QueryError::NotFinite { argument });
    assert_eq!(world.ray_cast(nan, DVec3::X, 10.0), not_finite("origin"));
    assert_eq!(
        world.ray_cast(DVec3::Y * 5.0, nan, 10.0),
        not_finite("direction")
    );
    assert_eq!(
        world.ray_cast(DVec3::Y * 5.0, -DVec3::Y, f64::INFINITY),
        not_finite("max_distance")
    );
    assert_eq!(
        world.ray_cast(DVec3::Y * 5.0, -DVec3::Y, -1.0),
        Err(QueryError::NegativeDistance(-1.0))
    );
    assert_eq!(
        world.ray_cast(DVec3::Y * 5.0, DVec3::ZERO, 10.0),
        Err(QueryError::ZeroDirection)
    );
    let above = DVec3::Y * 5.0;
    let cast = |shape: &Shape, rotation| world.shape_cast(shape, above, rotation, -DVec3::Y, 10.0);
    let negative = Shape::Sphere { radius: -1.0 };
    assert!(matches!(
        cast(&negative, DQuat::IDENTITY),
        Err(QueryError::Shape(_))
    ));
    let ball = Shape::sphere(0.5);
    assert_eq!(
        cast(&ball, DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0)),
        Err(QueryError::ZeroRotation)
    );
    assert_eq!(
        cast(&ball, DQuat::from_xyzw(f64::NAN, 0.0, 0.0, 1.0)),
        not_finite("rotation")
    );
    // The same ball, validly cast, lands on the box top: 5 − 1 − 0.5 = 3.5 m down.
    let hit = cast(&ball, DQuat::IDENTITY).unwrap().expect("a hit");
    assert!((hit.distance - 3.5).abs() < 1e-6, "{}", hit.distance);
}
