//! Snapshots: a world saved to text and loaded again continues bit for bit like the world that
//! never stopped, in both pipelines, with sleeping and isolated bodies; bad snapshot files give
//! errors that name the file and the body.

use glam::{DMat3, DVec3};
use rigid::physics::{
    BodyDesc, EnvironmentForce, MAX_BODIES, Pipeline, Shape, SnapshotError, World, WorldSnapshot,
};
use rigid::scene;

const DT: f64 = 1.0 / 60.0;
const FILE: &str = "test.snapshot.ron";

fn scene_world(name: &str) -> World {
    scene::load(name).unwrap().build_world().unwrap()
}

fn run(world: &mut World, steps: usize) {
    for _ in 0..steps {
        world.step(DT);
    }
}

/// Saves `world` to text and loads it back.
fn round_trip(world: &World) -> World {
    let text = world.to_snapshot().to_ron();
    let snapshot = WorldSnapshot::from_ron(&text, FILE).unwrap();
    World::from_snapshot(snapshot, FILE).unwrap()
}

/// Stops `world` after `before` steps, restores a copy from text, runs both for `after`
/// more steps and requires identical text (so identical bits, signed zeros included).
fn assert_continues_identically(mut world: World, before: usize, after: usize) {
    run(&mut world, before);
    let mut restored = round_trip(&world);
    assert_eq!(
        restored.to_snapshot().to_ron(),
        world.to_snapshot().to_ron()
    );
    run(&mut world, after);
    run(&mut restored, after);
    assert_eq!(
        restored.to_snapshot().to_ron(),
        world.to_snapshot().to_ron()
    );
}

#[test]
fn soft_stack_continues_bit_for_bit_with_warm_starting() {
    let world = scene_world("stack");
    // Stopped while the boxes settle: warm-start impulses and proxies must carry over.
    assert_continues_identically(world, 20, 200);
}

#[test]
fn pyramid_continues_bit_for_bit_through_sleep() {
    let mut world = scene_world("pyramid");
    run(&mut world, 300);
    assert!(
        world.bodies().iter().any(|b| b.sleeping),
        "some boxes asleep by 5 s"
    );
    assert_continues_identically(world, 0, 120);
}

#[test]
fn classic_pipeline_continues_bit_for_bit() {
    let mut world = scene_world("bounce");
    world.settings.pipeline = Pipeline::Classic;
    assert_continues_identically(world, 30, 200);
}

#[test]
fn pachinko_continues_bit_for_bit_with_hulls_and_compounds() {
    assert_continues_identically(scene_world("pachinko"), 60, 120);
}

#[test]
fn isolated_non_finite_body_survives_the_round_trip() {
    let mut world = World::default();
    world.forces.push(EnvironmentForce::earth_gravity());
    let ball = world
        .add_body(BodyDesc::dynamic(Shape::sphere(0.5)).at(DVec3::Y * 3.0))
        .unwrap();
    world.step(DT);
    world.body_mut(ball).linear_momentum = DVec3::new(f64::NAN, 0.0, 0.0);
    world.step(DT);
    assert_eq!(world.faults().len(), 1);
    let restored = round_trip(&world);
    assert_eq!(restored.faults(), world.faults());
    assert!(restored.body(ball).linear_momentum.x.is_nan());
    assert_eq!(restored.time(), world.time());
}

fn edited(edit: impl FnOnce(&mut WorldSnapshot)) -> Result<WorldSnapshot, SnapshotError> {
    let mut world = scene_world("falling_box");
    run(&mut world, 10);
    let mut snapshot = world.to_snapshot();
    edit(&mut snapshot);
    WorldSnapshot::from_ron(&snapshot.to_ron(), FILE)
}

#[test]
fn bad_snapshots_are_refused_with_the_file_and_body_named() {
    let error = edited(|s| s.bodies[2].position.y = f64::NAN).unwrap_err();
    let text = error.to_string();
    assert!(text.starts_with(FILE) && text.contains("body 2"), "{text}");
    assert!(text.contains("not finite"), "{text}");

    let error = edited(|s| s.bodies[1].shape = Shape::sphere(-1.0)).unwrap_err();
    assert!(error.to_string().contains("body 1"), "{error}");

    let error = edited(|s| s.bodies[2].orientation.x_axis.x = 1e308).unwrap_err();
    assert!(error.to_string().contains("not a rotation"), "{error}");

    let error = edited(|s| s.bodies[2].inv_mass = -2.0).unwrap_err();
    assert!(error.to_string().contains("field 'inv_mass'"), "{error}");

    let error = edited(|s| {
        s.bodies.pop();
    })
    .unwrap_err();
    assert!(
        matches!(error, SnapshotError::Inconsistent { .. }),
        "{error}"
    );
    let text = error.to_string();
    assert!(
        text.ends_with("bodies: 2 listed, but the broad phase holds 3 (a body is missing)"),
        "{text}"
    );

    let error = edited(|s| s.settings.solver.substeps = 4_000_000_000).unwrap_err();
    assert!(error.to_string().contains("solver.substeps"), "{error}");

    let error = edited(|s| s.settings.solver.deep_overlap = -1.0).unwrap_err();
    assert!(
        error
            .to_string()
            .contains("solver.deep_overlap must be finite and non-negative, got -1"),
        "{error}"
    );

    let error = edited(|s| s.settings.classic.theta = -1.0).unwrap_err();
    assert!(error.to_string().contains("classic.theta"), "{error}");

    let error = edited(|s| {
        s.forces[0] = EnvironmentForce::LinearDrag {
            coefficient: f64::NAN,
        }
    })
    .unwrap_err();
    assert!(error.to_string().contains("force"), "{error}");

    let error = edited(|s| s.format = 99).unwrap_err();
    assert!(
        matches!(error, SnapshotError::Format { found: 99, .. }),
        "{error}"
    );

    let error = WorldSnapshot::from_ron("(format: 2, nonsense: 3)", FILE).unwrap_err();
    assert!(matches!(error, SnapshotError::Unreadable { .. }), "{error}");
}

#[test]
fn a_snapshot_with_more_bodies_than_a_world_holds_is_refused() {
    let mut world = scene_world("falling_box");
    run(&mut world, 10);
    let mut snapshot = world.to_snapshot();
    let body = snapshot.bodies[1].clone();
    snapshot.bodies.resize(MAX_BODIES, body);
    // As a snapshot from before generations: no list to keep the length of.
    snapshot.generations.clear();
    assert_eq!(snapshot.check(FILE), Ok(()), "the limit itself is accepted");
    snapshot.bodies.push(snapshot.bodies[1].clone());
    let error = snapshot.check(FILE).unwrap_err();
    assert!(
        matches!(error, SnapshotError::Inconsistent { .. }),
        "{error}"
    );
    let text = error.to_string();
    assert!(
        text.starts_with(FILE) && text.contains("100001 bodies"),
        "{text}"
    );
}

#[test]
fn missing_snapshot_file_is_an_error_naming_it() {
    let error = WorldSnapshot::load(std::path::Path::new("/nonexistent/world.ron")).unwrap_err();
    assert!(
        error.to_string().starts_with("/nonexistent/world.ron"),
        "{error}"
    );
}

/// The body, field and message of a snapshot refused for one of its bodies.
fn body_error(error: SnapshotError) -> (usize, String, String, String) {
    let text = error.to_string();
    assert!(text.starts_with(FILE), "{text}");
    match error {
        SnapshotError::Body {
            index,
            name,
            field,
            message,
            ..
        } => (index, name, field, message),
        other => panic!("not a body error: {other}"),
    }
}

#[test]
fn a_snapshot_is_validated_as_strictly_as_a_scene() {
    type Edit = fn(&mut WorldSnapshot);
    let cases: [(Edit, usize, &str, &str); 12] = [
        (
            |s| s.bodies[2].material.restitution = 5.0,
            2,
            "material.restitution",
            "must lie in [0, 1], got 5",
        ),
        (
            |s| s.bodies[2].material.friction = f64::NAN,
            2,
            "material.friction",
            "must be finite",
        ),
        (
            |s| s.bodies[0].material.friction = -5.0,
            0,
            "material.friction",
            "must lie in [0, 10], got -5",
        ),
        (
            |s| s.bodies[2].material.density = 0.0,
            2,
            "material.density",
            "must be positive, got 0",
        ),
        (
            |s| s.bodies[2].inv_mass = 0.0,
            2,
            "inv_mass",
            "must be positive and finite on a dynamic body, got 0",
        ),
        (
            |s| s.bodies[0].inv_mass = 1.0,
            0,
            "inv_mass",
            "must be 0 on a static body, got 1",
        ),
        (
            |s| s.bodies[2].inv_inertia_local.y_axis.y *= -1.0,
            2,
            "inv_inertia_local",
            "must be symmetric positive definite",
        ),
        (
            |s| s.bodies[2].inv_inertia_local.x_axis.y += 1.0,
            2,
            "inv_inertia_local",
            "must be symmetric positive definite",
        ),
        (
            |s| s.bodies[2].inv_inertia_world *= 2.0,
            2,
            "inv_inertia_world",
            "must be R I⁻¹ Rᵀ",
        ),
        (
            |s| s.bodies[1].inv_inertia_local = DMat3::IDENTITY,
            1,
            "inv_inertia_local",
            "must be zero on a static body",
        ),
        // Finite momenta whose energy is beyond `MAX_BODY_ENERGY` (1e303 J), as a scene's.
        (
            |s| s.bodies[2].linear_momentum.x = 1e200,
            2,
            "linear_momentum",
            "gives a kinetic energy or momentum above 1e303",
        ),
        (
            |s| s.bodies[2].angular_momentum.z = 1e304,
            2,
            "angular_momentum",
            "gives a kinetic energy or momentum above 1e303",
        ),
    ];
    for (edit, index, field, message) in cases {
        let (found_index, name, found_field, found_message) = body_error(edited(edit).unwrap_err());
        assert_eq!(
            (found_index, found_field.as_str()),
            (index, field),
            "{found_message}"
        );
        assert_eq!(name, ["platform", "cube", "box"][index]);
        assert!(
            found_message.starts_with(message),
            "{field}: {found_message}"
        );
    }
}

#[test]
fn negative_drag_and_a_wrapping_step_count_are_refused() {
    let error = edited(|s| {
        s.forces
            .push(EnvironmentForce::QuadraticDrag { coefficient: -0.5 })
    })
    .unwrap_err();
    let text = error.to_string();
    assert!(
        matches!(error, SnapshotError::Inconsistent { .. }),
        "{text}"
    );
    assert!(
        text.starts_with(FILE) && text.contains("forces[1]"),
        "{text}"
    );
    assert!(text.contains("not negative"), "{text}");

    let error = edited(|s| s.steps = u64::MAX).unwrap_err();
    let text = error.to_string();
    assert!(
        matches!(error, SnapshotError::Inconsistent { .. }),
        "{text}"
    );
    assert!(
        text.contains(&format!(
            "steps must be at most 9007199254740992 (2^53), got {}",
            u64::MAX
        )),
        "{text}"
    );
    // The limit itself still steps on.
    let snapshot = edited(|s| s.steps = 1 << 53).unwrap();
    let mut world = World::from_snapshot(snapshot, FILE).unwrap();
    world.step(DT);
    assert_eq!(world.step_count(), (1 << 53) + 1);
}

/// A snapshot's forces meet the scene's limits: gravity of 1e12 m/s² or wind of 1e300 m/s
/// is refused with the force and field named.
#[test]
fn forces_beyond_their_limits_are_refused_in_a_snapshot() {
    let gravity = EnvironmentForce::Gravity {
        acceleration: DVec3::new(0.0, -1e12, 0.0),
    };
    let wind = EnvironmentForce::Wind {
        velocity: DVec3::new(1e300, 0.0, 0.0),
        coefficient: 1.0,
    };
    for (force, field) in [
        (gravity, "forces[1].acceleration"),
        (wind, "forces[1].velocity"),
    ] {
        let text = edited(|s| s.forces.push(force)).unwrap_err().to_string();
        assert!(text.starts_with(FILE) && text.contains(field), "{text}");
        assert!(text.contains("at most"), "{text}");
    }
}

/// Generations survive a snapshot: a removed body's id is refused in the restored world too,
/// the restored world reuses the same slot as the original, and a snapshot written before
/// generations (no `generations` field) still loads, with its removed bodies' ids refused.
#[test]
fn generations_survive_a_snapshot_and_older_snapshots_still_load() {
    let mut world = scene_world("stack");
    run(&mut world, 5);
    let removed = world.id_at(3).unwrap();
    world.remove_body(removed).unwrap();
    let mut restored = round_trip(&world);
    assert!(restored.get_body(removed).is_none());
    let ball = || BodyDesc::dynamic(Shape::sphere(0.2)).at(DVec3::new(3.0, 1.0, 0.0));
    let (a, b) = (
        world.add_body(ball()).unwrap(),
        restored.add_body(ball()).unwrap(),
    );
    assert_eq!((a, a.index()), (b, removed.index()));
    run(&mut world, 30);
    run(&mut restored, 30);
    assert_eq!(world.to_snapshot(), restored.to_snapshot());

    let mut old = world.to_snapshot();
    old.generations.clear();
    let text = old.to_ron();
    let old: String = (text.lines())
        .filter(|line| !line.trim_start().starts_with("generations:"))
        .map(|line| format!("{line}\n"))
        .collect();
    assert!(!old.contains("generations") && text.contains("generations"));
    let older = World::from_snapshot(WorldSnapshot::from_ron(&old, FILE).unwrap(), FILE).unwrap();
    assert_eq!(older.bodies().len(), world.bodies().len());

    let error = edited(|s| s.generations.push(0)).unwrap_err().to_string();
    assert!(
        error.starts_with(FILE) && error.contains("generations"),
        "{error}"
    );
}
