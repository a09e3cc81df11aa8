//! Determinism: the same scene and the same commands at the same ticks give bit-identical
//! worlds, whether run twice, replayed from a recording file, or continued from a saved world.
//! Worlds are compared through their snapshot text, which spells every f64 exactly.

use std::path::PathBuf;

use glam::DVec3;
use rigid::physics::{BroadPhaseKind, Integrator, Pipeline};
use rigid::sim::{
    Command, FileCommands, MAX_RECORDING_TICKS, Recording, RecordingError, Simulation, SpawnKind,
};

/// A user session: spawns of every kind, pushes, live setting changes, a pipeline switch,
/// a single step while paused, a reset and a scene change.
fn session() -> Vec<(u64, Command)> {
    let mut commands = vec![
        (5, Command::SetGravity(DVec3::new(0.5, -9.0, 0.0))),
        (10, Command::SetFriction(0.3)),
        (12, Command::SetRestitution(0.6)),
        (20, Command::SetSubsteps(6)),
        (
            25,
            Command::SetBroadPhase(BroadPhaseKind::UniformGrid { cell_size: 1.0 }),
        ),
        (30, Command::SetIntegrator(Integrator::ExactRotation)),
        (40, Command::SetPipeline(Pipeline::Classic)),
        (70, Command::SetPipeline(Pipeline::Soft)),
        (80, Command::SetDt(1.0 / 90.0)),
        (90, Command::SetPaused(true)),
        (90, Command::StepOnce),
        (91, Command::SetPaused(false)),
        (100, Command::SetSleeping(false)),
        (150, Command::Reset),
        (160, Command::LoadScene("pyramid".into())),
    ];
    for (i, kind) in SpawnKind::ALL.into_iter().enumerate() {
        let tick = 2 + 7 * i as u64;
        let position = DVec3::new(0.4 * i as f64 - 0.8, 4.0 + i as f64, 0.2);
        commands.push((
            tick,
            Command::Spawn {
                kind,
                position,
                velocity: DVec3::new(0.0, -1.0, 0.5),
            },
        ));
        commands.push((
            tick + 30,
            Command::ApplyImpulse {
                body: 3 + i,
                impulse: DVec3::new(2.0, 1.0, -1.0),
                point: position,
            },
        ));
    }
    commands.sort_by_key(|(tick, _)| *tick);
    commands
}

/// Runs `scene` for `ticks` steps, applying each command when the tick count reaches it, as
/// the simulation thread would between two steps.
fn drive(scene: &str, commands: &[(u64, Command)], ticks: u64) -> Simulation {
    drive_watching(scene, commands, ticks, |_| {})
}

/// `drive`, handing the simulation to `watch` after every step.
fn drive_watching(
    scene: &str,
    commands: &[(u64, Command)],
    ticks: u64,
    mut watch: impl FnMut(&Simulation),
) -> Simulation {
    let mut sim = Simulation::new(scene).unwrap();
    let mut pending = commands.iter().peekable();
    while sim.ticks() < ticks {
        while let Some((_, command)) = pending.next_if(|(tick, _)| *tick <= sim.ticks()) {
            sim.apply(command.clone());
        }
        sim.step();
        watch(&sim);
    }
    sim
}

fn world_text(sim: &Simulation) -> String {
    sim.world().to_snapshot().to_ron()
}

/// A file in this test binary's scratch directory (cleaned by `cargo clean`).
fn scratch(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("determinism_{name}"))
}

#[test]
fn same_commands_give_bit_identical_worlds() {
    for scene in ["pachinko", "falling_box"] {
        let first = drive(scene, &session(), 150);
        let second = drive(scene, &session(), 150);
        assert_eq!(world_text(&first), world_text(&second), "{scene}");
        assert_eq!(first.world().bodies().len(), second.world().bodies().len());
    }
}

#[test]
fn a_different_command_gives_a_different_world() {
    // The comparison can see a difference: one push more changes the outcome.
    let mut commands = session();
    commands.push((
        60,
        Command::ApplyImpulse {
            body: 3,
            impulse: DVec3::new(0.0, 1e-6, 0.0),
            point: DVec3::new(-0.8, 4.0, 0.2),
        },
    ));
    commands.sort_by_key(|(tick, _)| *tick);
    let first = drive("falling_box", &session(), 120);
    let second = drive("falling_box", &commands, 120);
    assert_ne!(world_text(&first), world_text(&second));
}

#[test]
fn replaying_a_recording_file_reproduces_the_run() {
    let live = drive("falling_box", &session(), 240);
    let path = scratch("session.recording.ron");
    live.recording().save(&path).unwrap();
    let recording = Recording::load(&path).unwrap();
    assert_eq!(recording, live.recording());
    let mut replayed =
        Simulation::replaying(&recording, "recording", FileCommands::Refuse).unwrap();
    while replayed.ticks() < recording.ticks {
        replayed.step();
    }
    assert_eq!(replayed.world().time(), live.world().time());
    assert_eq!(world_text(&replayed), world_text(&live));
    // The scene change was replayed too: the pyramid has 210 boxes and a floor.
    assert!(replayed.world().bodies().len() > 200);
}

#[test]
fn bodies_leaving_the_world_leave_it_the_same_way_in_a_replay() {
    // Off the pachinko board's side with its tilted gravity: they fall past everything,
    // 20 m below the board they are taken out, at the same step in the replay.
    let commands: Vec<_> = (0..4)
        .map(|i| {
            let spawn = Command::Spawn {
                kind: SpawnKind::ALL[i],
                position: DVec3::new(2.0 + i as f64, 1.0, 0.5),
                velocity: DVec3::new(0.0, -8.0 * i as f64, 0.0),
            };
            (10 * i as u64, spawn)
        })
        .collect();
    let live = drive("pachinko", &commands, 1500);
    let left = |sim: &Simulation| sim.snapshot(web_time::Instant::now()).left_world;
    assert!(left(&live) >= 2, "only {} left", left(&live));
    let recording = live.recording();
    let mut replayed =
        Simulation::replaying(&recording, "recording", FileCommands::Refuse).unwrap();
    while replayed.ticks() < recording.ticks {
        replayed.step();
    }
    assert_eq!(left(&replayed), left(&live));
    assert_eq!(world_text(&replayed), world_text(&live));
}

#[test]
fn a_saved_world_continues_as_if_never_stopped() {
    let path = scratch("pachinko.world.ron");
    let mut spawned = session();
    spawned.retain(|(tick, _)| *tick < 100);
    let mut live = drive("pachinko", &spawned, 100);
    live.apply(Command::SaveWorld(path.clone()));
    let mut restored = Simulation::new("falling_box").unwrap();
    restored.apply(Command::LoadWorld(path));
    assert_eq!(restored.settings().dt, live.settings().dt);
    // The scene's material names come back with the world, so the panel edits the same sets.
    let materials = |sim: &Simulation| sim.snapshot(web_time::Instant::now()).materials;
    assert_eq!(materials(&restored), materials(&live));
    assert!(materials(&live).iter().any(|m| m.name == "steel"));
    for _ in 0..150 {
        live.step();
        restored.step();
    }
    assert_eq!(world_text(&restored), world_text(&live));
}

#[test]
fn bad_recordings_and_saved_worlds_are_reported() {
    let error = Recording::from_ron("(scene: \"x\", ticks: 1, commands: [], extra: 2)", "r.ron");
    assert!(error.unwrap_err().to_string().starts_with("r.ron"));
    let late = "(scene: \"x\", ticks: 1, commands: [(tick: 5, command: Reset)])";
    assert!(
        Recording::from_ron(late, "r.ron")
            .unwrap_err()
            .to_string()
            .contains("after the end")
    );

    // A recording of 10¹² ticks once replayed for ever; past the limit it is refused, naming
    // the field and the limit. The limit itself is accepted.
    let endless = "(scene: \"x\", ticks: 1000000000000, commands: [])";
    let error = Recording::from_ron(endless, "r.ron").unwrap_err();
    assert_eq!(
        error,
        RecordingError::TooLong {
            file: "r.ron".into(),
            ticks: 1_000_000_000_000
        }
    );
    let message = error.to_string();
    assert!(
        message.contains("'ticks'") && message.contains("MAX_RECORDING_TICKS"),
        "{message}"
    );
    let longest = format!("(scene: \"x\", ticks: {MAX_RECORDING_TICKS}, commands: [])");
    assert!(Recording::from_ron(&longest, "r.ron").is_ok());

    let path = scratch("garbage.world.ron");
    std::fs::write(
        &path,
        "(scene: \"pachinko\", dt: 0.01, hidden: [], world: 3)",
    )
    .unwrap();
    let mut sim = Simulation::new("falling_box").unwrap();
    let bodies = sim.world().bodies().len();
    sim.apply(Command::LoadWorld(path.clone()));
    let snapshot = sim.snapshot(std::time::Instant::now());
    let message = snapshot.message.expect("the failure is shown");
    assert!(message.contains("garbage.world.ron"), "{message}");
    assert_eq!(
        sim.world().bodies().len(),
        bodies,
        "the running world is kept"
    );
}

/// Ticks at which the thread test compares worlds: the session resets at tick 150 (the
/// command is applied before the step that ends tick 151), so ticks up to 150 show the
/// scene under test and the later ones the pyramid it loads.
const CHECKPOINT_EVERY: u64 = 25;

/// Runs `work` in a rayon pool of `threads` threads.
fn on_threads<T: Send>(threads: usize, work: impl FnOnce() -> T + Send) -> T {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(work)
}

/// The session on `scene` with `threads` rayon threads: the world text at every checkpoint,
/// and the most contact manifolds any step before the reset found.
fn checkpoints(scene: &str, threads: usize) -> (Vec<(u64, String)>, usize) {
    let (mut texts, mut most_manifolds) = (vec![], 0);
    on_threads(threads, || {
        drive_watching(scene, &session(), 200, |sim| {
            if sim.ticks() <= 150 {
                most_manifolds = most_manifolds.max(sim.world().contacts().len());
            }
            if sim.ticks() % CHECKPOINT_EVERY == 0 {
                texts.push((sim.ticks(), world_text(sim)));
            }
        })
    });
    (texts, most_manifolds)
}

#[test]
fn the_number_of_threads_does_not_change_a_bit() {
    for scene in ["pachinko", "rain"] {
        let (single, most_manifolds) = checkpoints(scene, 1);
        assert_eq!(single.len(), 8, "ticks 25 to 200");
        // The narrow phase hands 64 pairs to a rayon task: the scene itself (not only the
        // pyramid loaded after the reset) must have given the threads several tasks to split.
        assert!(
            most_manifolds > 4 * 64,
            "{scene}: at most {most_manifolds} manifolds before the reset"
        );
        for threads in [2, 3, 8] {
            let (other, _) = checkpoints(scene, threads);
            assert_eq!(other.len(), single.len());
            for ((tick, expected), (_, got)) in single.iter().zip(&other) {
                assert!(
                    got == expected,
                    "{scene} with {threads} threads differs at tick {tick}"
                );
            }
        }
    }
}

/// The state of every body after `steps` of a rain of `count` bodies on `threads` threads,
/// and how many contact points the last step solved.
fn rain_state(count: usize, steps: usize, threads: usize) -> (Vec<[f64; 12]>, usize) {
    on_threads(threads, || {
        let mut world = rigid::scene::rain_world(count, Default::default());
        for _ in 0..steps {
            world.step(1.0 / 60.0);
        }
        let points = world.contacts().iter().map(|m| m.contacts.len()).sum();
        let state = world
            .bodies()
            .iter()
            .map(|b| {
                let (p, l, a, r) = (
                    b.position,
                    b.linear_momentum,
                    b.angular_momentum,
                    b.orientation,
                );
                [
                    p.x, p.y, p.z, l.x, l.y, l.z, a.x, a.y, a.z, r.x_axis.x, r.y_axis.y, r.z_axis.z,
                ]
            })
            .collect();
        (state, points)
    })
}

/// A pile big enough for the contact solve to be coloured and spread over the threads
/// (`physics::solver::contact_colors`) ends bit for bit where it does on one thread.
#[test]
fn the_parallel_contact_solve_does_not_change_a_bit() {
    let (single, points) = rain_state(1000, 120, 1);
    assert!(
        points >= rigid::physics::solver::contact_colors::MIN_COLORED_CONTACTS,
        "only {points} contact points: the solve was not coloured"
    );
    for threads in [2, 4] {
        let (other, _) = rain_state(1000, 120, threads);
        assert!(other == single, "{threads} threads differ");
    }
}

/// The same pile with 100 of its bodies joined in pairs by rods: the joints are solved in
/// order before the coloured contacts, so the threads still change no bit.
#[test]
fn joints_in_a_parallel_solve_do_not_change_a_bit() {
    let state = |threads: usize| {
        on_threads(threads, || {
            let mut world = rigid::scene::rain_world(1000, Default::default());
            let dynamic: Vec<usize> = (0..world.bodies().len())
                .filter(|&i| world.bodies()[i].is_dynamic())
                .take(200)
                .collect();
            for pair in dynamic.chunks(2) {
                let (a, b) = (world.id_at(pair[0]).unwrap(), world.id_at(pair[1]).unwrap());
                let (pa, pb) = (world.body(a).position, world.body(b).position);
                let rod = rigid::physics::JointDesc::distance(a, b, pa, pb);
                world.add_joint(rod).unwrap();
            }
            for _ in 0..120 {
                world.step(1.0 / 60.0);
            }
            world.to_snapshot().to_ron()
        })
    };
    let single = state(1);
    for threads in [2, 4] {
        assert!(state(threads) == single, "{threads} threads differ");
    }
}
