//! Fuzzing by property: garbage thrown at every way into the engine (the world API, saved
//! worlds, recordings) gives an error or a world that steps without panicking and without
//! non-finite state spreading. Scene text is generated here with any sizes, body counts,
//! speeds and forces; hand-edited scene files are fuzzed in `scene_files.rs`, and saved
//! worlds here both as garbled text and with single numbers replaced.
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

/// A speed from rest to far beyond `MAX_CONTACT_SPEED`, or whose energy overflows.
fn speed() -> impl Strategy<Value = f64> {
    prop_oneof![
        24 => -50.0..50.0f64,
        1 => Just(1e16),
        1 => Just(1e30),
        1 => Just(1e150),
        1 => Just(-1e160),
        1 => number(),
    ]
}

/// Grid counts: a handful of bodies, or now and then more than a world holds (refused
/// before building).
fn counts() -> impl Strategy<Value = (u64, u64, u64)> {
    prop_oneof![
        16 => (1..6u64, 1..6u64, 1..6u64),
        1 => (300..2000u64, 300..2000u64, 1..3u64),
    ]
}

/// Scene text with generated sizes, counts, velocities and forces, every number written
/// as RON spells it (NaN and inf included).
fn generated_scene() -> impl Strategy<Value = String> {
    let size = prop_oneof![16 => 0.05..1.0f64, 1 => number()];
    let body = (
        counts(),
        size,
        -2.0..2.0f64,
        (speed(), speed(), speed()),
        speed(),
    );
    // Mostly forces a scene may hold, so that most cases build and step.
    let force = || prop_oneof![16 => -20.0..20.0f64, 1 => speed()];
    let forces = (
        force(),
        force(),
        prop_oneof![16 => 0.0..5.0f64, 1 => number()],
    );
    (prop::collection::vec(body, 1..4), forces).prop_map(|(bodies, (gravity, wind, drag))| {
        let bodies: Vec<String> = bodies
            .iter()
            .map(|((nx, ny, nz), size, spacing, (vx, vy, vz), spin)| {
                format!(
                    "(shape: Sphere(radius: {}), position: (0.0, 2.0, 0.0), \
                     velocity: ({}, {}, {}), angular_velocity: (0.0, {}, 0.0), \
                     repeat: Grid(count: ({nx}, {ny}, {nz}), spacing: ({}, 1.0, 1.0))),",
                    ron(size.abs()),
                    ron(*vx),
                    ron(*vy),
                    ron(*vz),
                    ron(*spin),
                    ron(*spacing)
                )
            })
            .collect();
        format!(
            "Scene(name: \"generated\", forces: [Gravity(acceleration: (0.0, {}, 0.0)), \
             Wind(velocity: ({}, 0.0, 0.0), coefficient: 0.1), LinearDrag(coefficient: {})], \
             bodies: [(shape: Cuboid(half_extents: (5.0, 0.1, 5.0)), static: true), {}])",
            ron(gravity),
            ron(wind),
            ron(drag),
            bodies.join(" ")
        )
    })
}

/// A number as RON reads it back.
fn ron(x: f64) -> String {
    if x.is_nan() {
        "NaN".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf".into() } else { "-inf".into() }
    } else {
        format!("{x:e}")
    }
}

/// Replaces the `which`-th number of `text` (modulo their count) by `value`, as a hand
/// edit of a snapshot would.
fn with_number_replaced(text: &str, which: usize, value: f64) -> String {
    let is_number_char = |c: char| c.is_ascii_digit() || matches!(c, '.' | '-' | 'e' | '+');
    let mut spans = Vec::new();
    let mut start = None;
    for (i, c) in text.char_indices() {
        let begins = c.is_ascii_digit() || c == '-';
        match start {
            None if begins && !text[..i].ends_with(|p: char| p.is_alphanumeric() || p == '_') => {
                start = Some(i)
            }
            Some(s) if !is_number_char(c) => {
                spans.push((s, i));
                start = None;
            }
            _ => {}
        }
    }
    let Some(&(from, to)) = spans.get(which % spans.len().max(1)) else {
        return text.to_owned();
    };
    format!("{}{}{}", &text[..from], ron(value), &text[to..])
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
    fn generated_scenes_of_any_size_and_speed_load_with_an_error_or_step_safely(
        text in generated_scene(),
    ) {
        let built = scene::parse(&text, "fuzz.ron").and_then(|s| s.build_world());
        match built {
            Ok(mut world) => {
                prop_assert!(world.totals().kinetic_energy.is_finite());
                for _ in 0..3 {
                    world.step(1.0 / 60.0);
                }
                assert_contained(&world)?;
            }
            Err(error) => prop_assert!(error.to_string().starts_with("fuzz.ron"), "{error}"),
        }
    }

    #[test]
    fn hand_edited_snapshot_numbers_load_with_an_error_or_step_safely(
        edits in prop::collection::vec((any::<usize>(), speed()), 1..4),
    ) {
        let text = edits
            .iter()
            .fold(snapshot_text(), |t, &(which, value)| with_number_replaced(&t, which, value));
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
