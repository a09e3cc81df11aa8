//! Microbenchmarks of the detection stages: GJK, EPA, contact manifolds, the broad phase and
//! the idle-body tree. `cargo bench --no-default-features --bench micro`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{DMat3, DQuat, DVec3};
use rigid::physics::collision::broad_phase::{AabbTree, SplitBroadPhase, SweepAndPrune};
use rigid::physics::geometry::epa::signed_distance;
use rigid::physics::{
    Aabb, BroadPhase, BroadPhaseKind, PosedShape, Proxy, Shape, generate_contacts, gjk_distance,
    penetration,
};

fn posed(shape: &Shape, at: DVec3, turn: DVec3) -> PosedShape<'_> {
    PosedShape::new(shape, at, DMat3::from_quat(DQuat::from_scaled_axis(turn)))
}

/// Points on a sphere of radius 0.5, for a hull of `n` points.
fn hull_points(n: usize) -> Vec<DVec3> {
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let angle = 2.399963 * i as f64; // golden angle: evenly spread
            let ring = (1.0 - z * z).sqrt();
            DVec3::new(ring * angle.cos(), z, ring * angle.sin()) * 0.5
        })
        .collect()
}

/// A uniform number in [0, 1) from a linear congruential generator.
fn uniform(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

/// `count` placements of two copies of `shape` (of radius 0.5) at random turns and
/// directions whose surfaces lie from 2 cm into each other to 1.5 cm apart: the touching
/// pairs of a pile, which mostly need the full separating-axis search.
fn touching_poses(shape: &Shape, count: usize) -> Vec<(PosedShape<'_>, PosedShape<'_>)> {
    let mut state = 7u64;
    let mut poses = Vec::with_capacity(count);
    while poses.len() < count {
        let mut turn = || DVec3::new(uniform(&mut state), uniform(&mut state), 0.5) * 4.0;
        let (turn_a, turn_b, direction) = (turn(), turn(), turn().normalize());
        let distance = 0.5 + 0.6 * uniform(&mut state);
        let a = posed(shape, DVec3::new(1.0, 5.0, -3.0), turn_a);
        let b = posed(shape, a.origin + direction * distance, turn_b);
        if (-0.02..0.015).contains(&signed_distance(&a, &b).distance) {
            poses.push((a, b));
        }
    }
    poses
}

fn narrow(c: &mut Criterion) {
    let cube = Shape::cuboid(DVec3::splat(0.5));
    let hull = Shape::hull(&hull_points(32)).expect("valid hull");
    let capsule = Shape::capsule(0.4, 0.2);
    let apart = (
        posed(&cube, DVec3::ZERO, DVec3::ZERO),
        posed(&cube, DVec3::new(1.3, 0.4, 0.2), DVec3::new(0.3, 0.5, 0.1)),
    );
    let overlapping = (
        posed(&cube, DVec3::ZERO, DVec3::ZERO),
        posed(&cube, DVec3::new(0.9, 0.3, 0.1), DVec3::new(0.3, 0.5, 0.1)),
    );
    let hulls = (
        posed(&hull, DVec3::ZERO, DVec3::ZERO),
        posed(&hull, DVec3::new(0.95, 0.1, 0.0), DVec3::new(0.2, 0.1, 0.4)),
    );
    let capsule_on_box = (
        posed(&cube, DVec3::ZERO, DVec3::ZERO),
        posed(
            &capsule,
            DVec3::new(0.1, 0.69, 0.0),
            DVec3::new(0.0, 0.0, 1.5),
        ),
    );
    // Tilted by 0.3 rad, the lowest rim point 0.1207 m below the centre: 2 mm into the
    // cube's top face (y = 0.5), so the cores overlap and EPA measures the depth.
    let cylinder = Shape::cylinder(0.08, 0.15);
    let cylinder_on_box = (
        posed(&cube, DVec3::ZERO, DVec3::ZERO),
        posed(
            &cylinder,
            DVec3::new(0.1, 0.6187, 0.0),
            DVec3::new(0.0, 0.0, 0.3),
        ),
    );
    // 0.17 m apart, beyond the 0.02 m margin: the pair is dropped once GJK proves it
    // (converging on that distance takes GJK 22 iterations).
    let cylinders_apart = (
        posed(&cylinder, DVec3::ZERO, DVec3::new(0.4, 0.0, 0.2)),
        posed(
            &cylinder,
            DVec3::new(0.0, 0.26, 0.4),
            DVec3::new(0.0, 0.7, 1.1),
        ),
    );
    c.bench_function("gjk distance, boxes apart", |b| {
        b.iter(|| gjk_distance(black_box(&apart.0), black_box(&apart.1)))
    });
    c.bench_function("epa penetration, boxes overlapping", |b| {
        b.iter(|| penetration(black_box(&overlapping.0), black_box(&overlapping.1)))
    });
    c.bench_function("manifold, box on box (SAT + clipping)", |b| {
        b.iter(|| generate_contacts(black_box(&overlapping.0), black_box(&overlapping.1), 0.02))
    });
    c.bench_function("manifold, 32-point hulls", |b| {
        b.iter(|| generate_contacts(black_box(&hulls.0), black_box(&hulls.1), 0.02))
    });
    let touching = touching_poses(&hull, 500);
    c.bench_function("manifold, 32-point hulls, 500 touching placements", |b| {
        b.iter(|| {
            (touching.iter())
                .map(|(a, b2)| generate_contacts(black_box(a), black_box(b2), 0.02).len())
                .sum::<usize>()
        })
    });
    c.bench_function("manifold, capsule lying on a box", |b| {
        b.iter(|| {
            let (a, b2) = &capsule_on_box;
            generate_contacts(black_box(a), black_box(b2), 0.02)
        })
    });
    c.bench_function("manifold, cylinder tilted into a box (GJK + EPA)", |b| {
        b.iter(|| {
            let (a, b2) = &cylinder_on_box;
            generate_contacts(black_box(a), black_box(b2), 0.02)
        })
    });
    c.bench_function("manifold, cylinders out of reach (none)", |b| {
        b.iter(|| {
            let (a, b2) = &cylinders_apart;
            generate_contacts(black_box(a), black_box(b2), 0.02)
        })
    });
}

/// `count` unit-ish boxes scattered over a cube of side `spread`, a third of them idle.
fn proxies(count: usize, spread: f64) -> Vec<Proxy> {
    let mut state = 12345u64;
    let mut next = move || uniform(&mut state);
    (0..count)
        .map(|i| {
            let at = DVec3::new(next(), next(), next()) * spread;
            Proxy {
                aabb: Aabb::from_center_half_extents(at, DVec3::splat(0.3)),
                active: i % 3 != 0,
            }
        })
        .collect()
}

fn broad(c: &mut Criterion) {
    let boxes = proxies(2000, 40.0);
    let awake: Vec<u32> = (0..boxes.len() as u32)
        .filter(|&i| boxes[i as usize].active)
        .collect();
    c.bench_function("sweep and prune, 2000 boxes", |b| {
        let (mut sap, mut pairs) = (SweepAndPrune::default(), Vec::new());
        b.iter(|| sap.fill_pairs(black_box(&boxes), &mut pairs))
    });
    c.bench_function("split broad phase, 2000 boxes, idle tree kept", |b| {
        let (mut split, mut pairs) = (
            SplitBroadPhase::new(BroadPhaseKind::SweepAndPrune),
            Vec::new(),
        );
        split.fill_pairs(&boxes, &awake, true, &mut pairs);
        b.iter(|| split.fill_pairs(black_box(&boxes), &awake, false, &mut pairs))
    });
    let idle: Vec<(Aabb, u32)> = boxes.iter().map(|p| p.aabb).zip(0..).collect();
    c.bench_function("aabb tree build, 2000 boxes", |b| {
        let mut tree = AabbTree::default();
        b.iter(|| tree.rebuild(black_box(&idle).iter().copied()))
    });
    let tree = AabbTree::build(idle);
    let query = Aabb::from_center_half_extents(DVec3::splat(20.0), DVec3::splat(1.0));
    c.bench_function("aabb tree query, 2000 boxes", |b| {
        b.iter(|| {
            let mut hits = 0;
            tree.query(black_box(&query), |_| hits += 1);
            hits
        })
    });
}

criterion_group!(benches, narrow, broad);
criterion_main!(benches);
