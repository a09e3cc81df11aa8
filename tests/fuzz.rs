//! Fuzzing by property: garbage thrown at every way into the engine (the world API, saved
//! worlds, recordings) gives an error or a world that steps without panicking and without
//! non-finite state spreading. Scene files are fuzzed in `scene_files.rs`.
//!
//! The case count is bounded for CI; set `FUZZ_CASES` for a longer run by hand.

mod common;

use common::garble::{Edit, apply, edit_strategy, number};
use glam::{DQuat, DVec3};
use proptest::prelude::*;
use rigid::physics::{
    BodyDesc, EnvironmentForce, MAX_STEP, Material, Motion, Shape, StepError, World, WorldSnapshot,
};
use rigid::scene;
use rigid::sim::{FileCommands, Recording, Simulation};

fn cases(default: u32) -> u32 {
    std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn vector() -> impl Strategy<Value = DVec3> {
    (number(), number(), number()).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

fn shape() -> impl Strategy<Value = Result<Shape, String>> {
    prop_oneof![
        number().prop_map(|r| Ok(Shape::sphere(r))),
        vector().prop_map(|h| Ok(Shape::cuboid(h))),
        (number(), number()).prop_map(|(h, r)| Ok(Shape::capsule(h, r))),
        (number(), number()).prop_map(|(h, r)| Ok(Shape::cylinder(h, r))),
        // Point clouds: random, duplicated, flat, huge or tiny.
        prop::collection::vec(vector(), 0..12)
            .prop_map(|points| Shape::hull(&points).map_err(|e| e.to_string())),
        (vector(), 1..6usize)
            .prop_map(|(p, n)| Shape::hull(&vec![p; n]).map_err(|e| e.to_string())),
    ]
}

fn desc() -> impl Strategy<Value = Result<BodyDesc, String>> {
    let material =
        (number(), number(), number()).prop_map(|(density, restitution, friction)| Material {
            density,
            restitution,
            friction,
        });
    let motion = prop_oneof![Just(Motion::Dynamic), Just(Motion::Static)];
    let mass = prop::option::of(number());
    let rotation = (number(), number(), number(), number())
        .prop_map(|(x, y, z, w)| DQuat::from_xyzw(x, y, z, w));
    let state = (vector(), rotation, vector(), vector());
    (shape(), material, motion, mass, state).prop_map(
        |(shape, material, motion, mass, (position, rotation, velocity, angular_velocity))| {
            Ok(BodyDesc {
                name: "fuzzed".into(),
                shape: shape?,
                material,
                motion,
                mass,
                position,
                rotation,
                velocity,
                angular_velocity,
            })
        },
    )
}

/// A body that the world accepted and that then stepped stays finite, or is isolated and
/// reported; it never turns the other bodies non-finite.
fn assert_contained(world: &World) -> Result<(), TestCaseError> {
    for (index, body) in world.bodies().iter().enumerate() {
        let reported = world.faults().iter().any(|f| f.body.index() == index);
        prop_assert!(
            body.is_finite() || reported,
            "body {index} non-finite, not reported"
        );
    }
    Ok(())
}

fn snapshot_text() -> String {
    let mut world = scene::load("hulls").unwrap().build_world().unwrap();
    for _ in 0..30 {
        world.step(1.0 / 60.0);
    }
    world.to_snapshot().to_ron()
}

fn recording_text() -> String {
    let text = r#"(scene: "falling_box", ticks: 20, commands: [
        (tick: 2, command: Spawn(kind: Hull, position: (0.0, 4.0, 0.0), velocity: (0.0, 0.0, 0.0))),
        (tick: 5, command: SetGravity((0.0, -3.0, 1.0))),
        (tick: 9, command: ApplyImpulse(body: 2, impulse: (1.0, 2.0, 0.0), point: (0.0, 3.0, 0.0))),
        (tick: 12, command: SetSubsteps(4)),
        (tick: 15, command: LoadScene("bounce")),
    ])"#;
    assert!(Recording::from_ron(text, "seed").is_ok());
    text.to_owned()
}

fn garbled(text: &str, edits: &[Edit]) -> String {
    edits.iter().fold(text.to_owned(), |t, e| apply(&t, e))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(600)))]

    #[test]
    fn any_bodies_either_fail_validation_or_step_safely(
        descs in prop::collection::vec(desc(), 1..6),
        gravity in vector(),
        dt in number(),
    ) {
        let mut world = World::default();
        world.forces.push(EnvironmentForce::Gravity { acceleration: gravity });
        for desc in descs.into_iter().flatten() {
            if let Ok(id) = world.add_body(desc) {
                let body = world.body(id);
                prop_assert!(body.is_finite() && body.inv_mass.is_finite() && body.inv_mass >= 0.0);
            }
        }
        let acceptable = dt.is_finite() && dt.abs() <= MAX_STEP;
        match world.try_step(dt) {
            Ok(()) => prop_assert!(acceptable),
            Err(StepError::BadDt(_)) => prop_assert!(!acceptable),
            Err(e) => prop_assert!(false, "a world without joints refused a step: {e}"),
        }
        for _ in 0..3 {
            world.step(1.0 / 60.0);
        }
        assert_contained(&world)?;
    }

    #[test]
    fn garbled_saved_worlds_load_with_an_error_or_step_safely(
        edits in prop::collection::vec(edit_strategy(), 1..4),
    ) {
        let text = garbled(&snapshot_text(), &edits);
        match WorldSnapshot::from_ron(&text, "fuzz.ron") {
            Ok(snapshot) => {
                let mut world = World::from_snapshot(snapshot, "fuzz.ron").unwrap();
                for _ in 0..3 {
                    world.step(1.0 / 60.0);
                }
                assert_contained(&world)?;
            }
            Err(error) => prop_assert!(error.to_string().starts_with("fuzz.ron")),
        }
    }

    #[test]
    fn garbled_recordings_replay_or_are_refused(
        edits in prop::collection::vec(edit_strategy(), 1..4),
    ) {
        let text = garbled(&recording_text(), &edits);
        let Ok(recording) = Recording::from_ron(&text, "fuzz.ron") else {
            return Ok(());
        };
        // A recording may name any scene or file: that is an error, not a panic.
        if let Ok(mut sim) = Simulation::replaying(&recording, "fuzz.ron", FileCommands::Allow) {
            for _ in 0..recording.ticks.min(30) {
                sim.step();
            }
            assert_contained(sim.world())?;
        }
    }
}
