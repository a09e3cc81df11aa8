//! Hostile inputs whose per-step memory or time once grew without bound: every list a step
//! keeps is bounded by a world setting or a documented limit, going over a budget is
//! reported, and shapes whose cost explodes are refused with the limit named.

use std::sync::Arc;

use glam::DVec3;
use rigid::physics::collision::broad_phase::UniformGrid;
use rigid::physics::{
    AddBodyError, BodyDesc, BodyError, BroadPhaseKind, Compound, CompoundPart, DEFAULT_MAX_PAIRS,
    MAX_COMPOUND_PARTS, Pose, Shape, ShapeError, World, WorldSettings,
};

/// 10 000 spheres created at one point overlap pairwise: 5·10⁷ pairs, for which the narrow
/// phase once reserved 18 GB. The step keeps `max_pairs` of them and reports the rest,
/// with every broad phase.
#[test]
fn spheres_at_one_point_keep_at_most_the_pair_budget() {
    let kinds = [
        BroadPhaseKind::SweepAndPrune,
        BroadPhaseKind::UniformGrid { cell_size: 1.0 },
        BroadPhaseKind::BruteForce,
    ];
    for kind in kinds {
        let max_pairs = 50_000;
        let mut world = World::new(WorldSettings {
            broad_phase: kind,
            max_pairs,
            ..WorldSettings::default()
        });
        let count = if kind == BroadPhaseKind::BruteForce {
            2_000
        } else {
            10_000
        };
        for _ in 0..count {
            world
                .add_body(BodyDesc::dynamic(Shape::sphere(0.5)))
                .unwrap();
        }
        world.step(1.0 / 60.0);
        assert_eq!(world.pair_count(), max_pairs, "{kind:?}");
        assert!(world.contacts().len() <= max_pairs, "{kind:?}");
        let fault = world.pair_budget_fault().expect("the budget fault");
        assert_eq!(
            (fault.step, fault.max_pairs, fault.steps_over),
            (0, max_pairs, 1)
        );
        world.step(1.0 / 60.0);
        assert_eq!(world.pair_budget_fault().unwrap().steps_over, 2, "{kind:?}");
        assert!(world.bodies().iter().all(|b| b.is_finite()), "{kind:?}");
    }
}

/// Pairs within the budget are all kept and no fault is reported; the default budget is
/// the documented one.
#[test]
fn a_scene_within_the_budget_reports_nothing() {
    assert_eq!(WorldSettings::default().max_pairs, DEFAULT_MAX_PAIRS);
    let mut world = World::default();
    // 100 spheres at one point: 4950 pairs.
    for _ in 0..100 {
        world
            .add_body(BodyDesc::dynamic(Shape::sphere(0.5)))
            .unwrap();
    }
    world.step(1.0 / 60.0);
    assert_eq!(world.pair_count(), 4950);
    assert!(world.pair_budget_fault().is_none());
}

/// A body at 3e8 m/s in a grid of 1 m cells has a box about 10⁷ cells on a side, 10²¹
/// cells in all: the product of the three counts wrapped in i64 and the grid tried to fill
/// them. It is now kept aside, and the grid holds at most 64 cells per box.
#[test]
fn a_body_at_light_speed_in_a_grid_world_takes_few_cells() {
    let mut world = World::new(WorldSettings {
        broad_phase: BroadPhaseKind::UniformGrid { cell_size: 1.0 },
        ..WorldSettings::default()
    });
    world
        .add_body(BodyDesc::dynamic(Shape::sphere(0.5)).with_velocity(DVec3::new(3e8, 1e8, -2e8)))
        .unwrap();
    for i in 0..10 {
        let at = DVec3::new(3.0 * i as f64, 0.0, 0.0);
        world
            .add_body(BodyDesc::dynamic(Shape::sphere(0.5)).at(at))
            .unwrap();
    }
    for _ in 0..3 {
        world.step(1.0 / 60.0);
    }
    let proxies = world.broad_phase_proxies();
    let boxes = proxies.iter().map(|p| &p.aabb);
    let cells = UniformGrid::new(1.0).occupied_cells(boxes);
    // Each of the ten slow spheres covers at most 2 × 2 × 2 cells; the fast one none.
    assert!(cells.len() <= 80, "{} cells", cells.len());
    assert!(world.bodies().iter().all(|b| b.is_finite()));
}

/// A compound of more than `MAX_COMPOUND_PARTS` parts is refused by `Compound::new` and,
/// built by hand, by `World::add_body`, naming the body.
#[test]
fn compounds_past_the_part_limit_are_refused() {
    let parts = |count: usize| {
        (0..count)
            .map(|i| CompoundPart {
                pose: Pose::new(DVec3::X * i as f64, glam::DQuat::IDENTITY),
                shape: Shape::sphere(0.4),
            })
            .collect::<Vec<_>>()
    };
    let too_many = MAX_COMPOUND_PARTS + 1;
    assert_eq!(
        Compound::new(parts(too_many)),
        Err(ShapeError::TooManyParts(too_many))
    );
    assert!(Compound::new(parts(MAX_COMPOUND_PARTS)).is_ok());
    let by_hand = Shape::Compound(Arc::new(Compound {
        parts: parts(too_many),
    }));
    let error = World::default()
        .add_body(BodyDesc::dynamic(by_hand).named("rake"))
        .unwrap_err();
    assert_eq!(
        error,
        AddBodyError::Invalid(BodyError::Shape {
            body: "rake".into(),
            source: ShapeError::TooManyParts(too_many),
        })
    );
    assert!(error.to_string().contains("'rake'"), "{error}");
    assert!(error.to_string().contains("MAX_COMPOUND_PARTS"), "{error}");
}
