//! Bounding boxes and the three broad phases against brute force on random scenes.

mod common;

use common::*;
use glam::{DMat3, DVec3};
use proptest::prelude::*;
use rigid::physics::collision::broad_phase::{
    BruteForce, SplitBroadPhase, SweepAndPrune, UniformGrid,
};
use rigid::physics::{
    Aabb, BroadPhase, BroadPhaseKind, Motion, PosedShape, Proxy, Shape, SupportMap,
};

fn vec3(range: std::ops::Range<f64>) -> impl Strategy<Value = DVec3> {
    (range.clone(), range.clone(), range).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

fn shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        (0.05..2.0f64).prop_map(Shape::sphere),
        vec3(0.05..2.0).prop_map(Shape::cuboid),
        (0.05..2.0f64, 0.05..2.0f64).prop_map(|(h, r)| Shape::capsule(h, r)),
        (0.05..2.0f64, 0.05..2.0f64).prop_map(|(h, r)| Shape::cylinder(h, r)),
        vec3(0.05..2.0).prop_map(|h| hull_shape(octahedron_hull(h))),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// The box is tight: each face touches the shape (the support along that axis), and it
    /// holds the support points in many directions.
    #[test]
    fn aabb_is_tight_at_any_orientation(shape in shape(), origin in vec3(-5.0..5.0), r in vec3(-1.0..1.0)) {
        let rotation = DMat3::from_quat(rotation_from(r));
        let aabb = Aabb::of_shape(&shape, origin, rotation);
        let posed = PosedShape::new(&shape, origin, rotation);
        for axis in 0..3 {
            let dir = DVec3::AXES[axis];
            prop_assert!((posed.support(dir)[axis] - aabb.max[axis]).abs() < 1e-12);
            prop_assert!((posed.support(-dir)[axis] - aabb.min[axis]).abs() < 1e-12);
        }
        for k in 0..200 {
            let t = k as f64 * 0.7;
            let dir = DVec3::new(t.sin() * (0.3 * t).cos(), t.cos(), (1.3 * t).sin());
            prop_assert!(aabb.fattened(1e-12).contains_point(posed.support(dir)));
        }
    }
}

#[derive(Clone, Debug)]
struct Scene {
    boxes: Vec<(DVec3, DVec3, bool)>,
}

impl Scene {
    fn proxies(&self) -> Vec<Proxy> {
        self.boxes
            .iter()
            .map(|&(center, half, active)| Proxy {
                aabb: Aabb::from_center_half_extents(center, half),
                active,
            })
            .collect()
    }
}

fn scene() -> impl Strategy<Value = Scene> {
    let body = (vec3(-10.0..10.0), vec3(0.05..2.0), any::<bool>());
    let ground = (
        Just(DVec3::new(0.0, -10.0, 0.0)),
        Just(DVec3::new(50.0, 0.5, 50.0)),
        Just(false),
    );
    (prop::collection::vec(body, 0..80), prop::option::of(ground)).prop_map(
        |(mut boxes, ground)| {
            boxes.extend(ground);
            Scene { boxes }
        },
    )
}

fn moves(count: usize) -> impl Strategy<Value = Vec<DVec3>> {
    prop::collection::vec(vec3(-0.3..0.3), count)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100))]

    /// Every implementation returns exactly the brute-force pairs, before and after every
    /// body moves a little (the sweep and prune keeps its order between calls), and after the
    /// scene is squashed into a column (the sweep and prune changes axis).
    #[test]
    fn implementations_agree_with_brute_force(
        (scene, steps) in scene().prop_flat_map(|s| {
            let n = s.boxes.len();
            (Just(s), prop::collection::vec(moves(n), 1..4))
        }),
        cell_size in 0.5..6.0f64,
    ) {
        let mut scene = scene;
        let mut grid = UniformGrid::new(cell_size);
        let mut sweep = SweepAndPrune::default();
        let mut split = SplitBroadPhase::new(BroadPhaseKind::SweepAndPrune);
        let squash = |c: DVec3| DVec3::new(0.05 * c.x, 20.0 * c.y, 0.05 * c.z);
        // One list for every implementation and step: each must replace what it holds.
        let mut found = Vec::new();
        let moves = steps.iter().map(|offsets| Some(offsets.as_slice()));
        for step in std::iter::once(None).chain(moves).chain([None]) {
            match step {
                Some(offsets) => {
                    for (b, offset) in scene.boxes.iter_mut().zip(offsets) {
                        b.0 += *offset;
                    }
                }
                None => scene.boxes.iter_mut().for_each(|b| b.0 = squash(b.0)),
            }
            let proxies = scene.proxies();
            let expected = BruteForce.find_pairs(&proxies);
            for pair in &expected {
                prop_assert!(proxies[pair.a.index()].active || proxies[pair.b.index()].active);
            }
            grid.fill_pairs(&proxies, &mut found);
            prop_assert_eq!(&found, &expected);
            sweep.fill_pairs(&proxies, &mut found);
            prop_assert_eq!(&found, &expected);
            let awake: Vec<u32> = (0..proxies.len() as u32).filter(|&i| proxies[i as usize].active).collect();
            split.fill_pairs(&proxies, &awake, true, &mut found);
            prop_assert_eq!(&found, &expected);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100))]

    /// The world's split broad phase keeps its tree of idle boxes while only awake boxes
    /// move, and still finds exactly the brute-force pairs.
    #[test]
    fn split_broad_phase_keeps_idle_boxes_between_steps(
        (scene, steps) in scene().prop_flat_map(|s| {
            let n = s.boxes.len();
            (Just(s), prop::collection::vec(moves(n), 1..5))
        }),
        kind in prop_oneof![
            Just(BroadPhaseKind::SweepAndPrune),
            Just(BroadPhaseKind::BruteForce),
            (0.5..4.0f64).prop_map(|cell_size| BroadPhaseKind::UniformGrid { cell_size }),
        ],
    ) {
        let mut scene = scene;
        let mut split = SplitBroadPhase::new(kind);
        let mut found = Vec::new();
        for (step, offsets) in steps.iter().enumerate() {
            let proxies = scene.proxies();
            let awake: Vec<u32> = (0..proxies.len() as u32).filter(|&i| proxies[i as usize].active).collect();
            split.fill_pairs(&proxies, &awake, step == 0, &mut found);
            prop_assert_eq!(&found, &BruteForce.find_pairs(&proxies));
            for (b, offset) in scene.boxes.iter_mut().zip(offsets).filter(|(b, _)| b.2) {
                b.0 += *offset;
            }
        }
    }
}

#[test]
fn static_and_sleeping_pairs_are_skipped() {
    // Three overlapping boxes: two inactive (static or asleep), one active.
    let proxy = |x: f64, active| Proxy {
        aabb: Aabb::from_center_half_extents(DVec3::new(x, 0.0, 0.0), DVec3::ONE),
        active,
    };
    let proxies = [proxy(0.0, false), proxy(1.0, false), proxy(2.0, true)];
    for kind in [
        BroadPhaseKind::BruteForce,
        BroadPhaseKind::UniformGrid { cell_size: 1.0 },
        BroadPhaseKind::SweepAndPrune,
    ] {
        let pairs = kind.create().find_pairs(&proxies);
        let ids: Vec<(u32, u32)> = pairs.iter().map(|p| (p.a.0, p.b.0)).collect();
        assert_eq!(ids, vec![(0, 2), (1, 2)], "{kind:?}");
    }
}

#[test]
fn proxies_of_bodies_use_motion() {
    let floor = body(
        Shape::cuboid(DVec3::new(5.0, 0.5, 5.0)),
        DVec3::ZERO,
        Default::default(),
        Motion::Static,
    );
    let ball = body(
        Shape::sphere(0.5),
        DVec3::Y,
        Default::default(),
        Motion::Dynamic,
    );
    let proxies = [Proxy::of_body(&floor, 0.01), Proxy::of_body(&ball, 0.01)];
    assert!(!proxies[0].active && proxies[1].active);
    assert!((proxies[1].aabb.min.y - 0.49).abs() < 1e-12);
    assert_eq!(SweepAndPrune::default().find_pairs(&proxies).len(), 1);
}

#[test]
fn swept_box_holds_both_ends() {
    let aabb = Aabb::from_center_half_extents(DVec3::ZERO, DVec3::splat(0.01));
    let swept = aabb.swept(DVec3::new(5.0, -1.0, 0.0));
    assert_eq!(swept.min, DVec3::new(-0.01, -1.01, -0.01));
    assert_eq!(swept.max, DVec3::new(5.01, 0.01, 0.01));
}

/// Boxes with a NaN bound (of either sign, on any axis, in the minimum or the maximum)
/// and empty boxes pair with nothing, and do not hide any pair of the others from the
/// sweep, wherever they sort.
#[test]
fn boxes_with_nan_bounds_pair_with_nothing() {
    let mut proxies = Vec::new();
    for k in 0..60 {
        let t = k as f64;
        let center = DVec3::new((t * 0.37).sin() * 3.0, (t * 0.23).cos() * 3.0, t * 0.05);
        proxies.push(Proxy {
            aabb: Aabb::from_center_half_extents(center, DVec3::splat(0.6)),
            active: k % 3 != 0,
        });
    }
    for k in 0..12 {
        let mut aabb = Aabb::from_center_half_extents(DVec3::splat(0.1 * k as f64), DVec3::ONE);
        let nan = if k % 2 == 0 { f64::NAN } else { -f64::NAN };
        match k % 4 {
            0 | 1 => aabb.min[k % 3] = nan,
            _ => aabb.max[k % 3] = nan,
        }
        proxies.insert(5 * k, Proxy { aabb, active: true });
    }
    proxies.insert(
        7,
        Proxy {
            aabb: Aabb {
                min: DVec3::INFINITY,
                max: DVec3::NEG_INFINITY,
            },
            active: true,
        },
    );
    let expected = BruteForce.find_pairs(&proxies);
    assert!(expected.len() > 20, "only {} pairs", expected.len());
    let mut sweep = SweepAndPrune::default();
    for _ in 0..2 {
        assert_eq!(sweep.find_pairs(&proxies), expected);
    }
}
