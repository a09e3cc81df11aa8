//! The headless runner, run as a separate process: its state output against the closed form of
//! semi-implicit Euler free fall, and its exit code and message on bad input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const G: f64 = 9.81;
const Y0: f64 = 10.0;

/// A file in this test binary's scratch directory (cleaned by `cargo clean`).
fn scratch(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("headless_{name}"))
}

fn write_scene(name: &str, text: &str) -> PathBuf {
    let path = scratch(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// One ball released at rest at (1, Y0, −2) in uniform gravity, plus a static floor that must
/// not appear in the output.
fn free_fall_scene(name: &str) -> PathBuf {
    write_scene(
        name,
        &format!(
            r#"Scene(
    name: "free_fall",
    settings: (dt: 0.01, integrator: Midpoint),
    forces: [Gravity(acceleration: (0.0, -{G}, 0.0))],
    bodies: [
        (name: "floor", shape: Cuboid(half_extents: (1.0, 0.1, 1.0)), position: (0.0, -50.0, 0.0),
         static: true),
        (name: "ball", shape: Sphere(radius: 0.1), position: (1.0, {Y0}, -2.0)),
    ],
)"#
        ),
    )
}

fn headless(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_headless"))
        .args(args)
        .output()
        .expect("run headless")
}

/// y_n = y0 − g h² n(n+1)/2: the velocity is updated first, then the position with it.
/// The world runs each step of `dt` as `substeps` substeps of dt / substeps.
fn euler_height(dt: f64, steps: u64) -> f64 {
    let substeps = rigid::physics::solver::soft::SoftSolverSettings::default().substeps as u64;
    let (h, n) = (dt / substeps as f64, steps * substeps);
    Y0 - G * h * h * (n * (n + 1)) as f64 / 2.0
}

fn csv_rows(path: &PathBuf) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "step,time,body,name,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz"
    );
    lines
        .map(|line| line.split(',').map(str::to_owned).collect())
        .collect()
}

#[test]
fn csv_free_fall_matches_semi_implicit_euler() {
    let scene = free_fall_scene("free_fall_csv.ron");
    let csv = scratch("free_fall.csv");
    let steps = 250;
    let output = headless(&[
        "--scene",
        scene.to_str().unwrap(),
        "--steps",
        &steps.to_string(),
        "--csv",
        csv.to_str().unwrap(),
        "--every",
        "7",
    ]);
    assert!(output.status.success(), "{output:?}");
    let rows = csv_rows(&csv);
    // Step 0, every 7th step, and the last one (250 is not a multiple of 7); the ball only.
    assert_eq!(rows.len(), 1 + 250 / 7 + 1);
    assert!(rows.iter().all(|row| row[2] == "1" && row[3] == "ball"));
    let last = rows.last().unwrap();
    let number = |i: usize| last[i].parse::<f64>().unwrap();
    assert_eq!(last[0], "250");
    assert!((number(1) - 2.5).abs() < 1e-12);
    assert!((number(5) - euler_height(0.01, steps)).abs() < 1e-9);
    assert!((number(4) - 1.0).abs() < 1e-12 && (number(6) + 2.0).abs() < 1e-12);
    assert!((number(12) + G * 0.01 * steps as f64).abs() < 1e-9);
    // Unrotated: the quaternion stays (0, 0, 0, 1).
    assert_eq!(&last[7..11], ["0", "0", "0", "1"]);
}

#[test]
fn json_output_with_dt_and_integrator_overrides() {
    let scene = free_fall_scene("free_fall_json.ron");
    let json = scratch("free_fall.jsonl");
    let (steps, h) = (120, 0.005);
    let output = headless(&[
        "--scene",
        scene.to_str().unwrap(),
        "--steps",
        &steps.to_string(),
        "--dt",
        &h.to_string(),
        "--integrator",
        "report_euler",
        "--json",
        json.to_str().unwrap(),
        "--every",
        "1000",
    ]);
    assert!(output.status.success(), "{output:?}");
    let stdout = String::from_utf8(output.stdout).unwrap();
    assert!(
        stdout.contains("integrator       report_euler, dt 0.005 s"),
        "{stdout}"
    );
    let text = std::fs::read_to_string(&json).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2);
    let last = lines[1];
    assert!(last.starts_with("{\"step\":120,"), "{last}");
    assert!(last.contains("\"name\":\"ball\""), "{last}");
    let position = last
        .split("\"position\":[")
        .nth(1)
        .and_then(|rest| rest.split(']').next())
        .unwrap();
    let y: f64 = position.split(',').nth(1).unwrap().parse().unwrap();
    assert!((y - euler_height(h, steps)).abs() < 1e-9, "{y}");
}

#[test]
fn summary_reports_counts_energy_and_momentum() {
    let scene = free_fall_scene("free_fall_summary.ron");
    let output = headless(&["--scene", scene.to_str().unwrap(), "--steps", "100"]);
    assert!(output.status.success(), "{output:?}");
    let stdout = String::from_utf8(output.stdout).unwrap();
    for expected in [
        "bodies           2 (1 dynamic)",
        "steps            100, simulated 1.000000 s",
        "energy K+U       initial",
        "energy drift",
        "linear momentum  initial [0, 0, 0], final",
        "angular momentum initial",
    ] {
        assert!(
            stdout.contains(expected),
            "missing {expected:?} in:\n{stdout}"
        );
    }
}

#[test]
fn built_in_scene_runs_by_name() {
    let output = headless(&["--scene", "stack", "--steps", "10"]);
    assert!(output.status.success(), "{output:?}");
    let stdout = String::from_utf8(output.stdout).unwrap();
    assert!(
        stdout.contains("bodies           11 (10 dynamic)"),
        "{stdout}"
    );
}

#[test]
fn bad_scene_file_exits_2_with_the_message_on_stderr() {
    let scene = write_scene(
        "bad.ron",
        r#"Scene(name: "bad", bodies: [(name: "crate_3", shape: Cuboid(half_extents: (-1.0, 1.0, 1.0)))])"#,
    );
    let output = headless(&["--scene", scene.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8(output.stderr).unwrap();
    let expected = format!(
        "{}: body 'crate_3' field 'shape.half_extents.x': must be positive, got -1",
        scene.display()
    );
    assert!(stderr.contains(&expected), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(output.stdout.is_empty());
}

#[test]
fn unknown_scene_and_bad_dt_exit_2() {
    let output = headless(&["--scene", "no_such_scene"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        String::from_utf8(output.stderr)
            .unwrap()
            .contains("no_such_scene")
    );
    let output = headless(&["--dt", "NaN"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8(output.stderr).unwrap().contains("--dt"));
}

#[test]
fn unwritable_output_exits_2() {
    let output = headless(&["--steps", "1", "--csv", "/nonexistent/dir/out.csv"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        String::from_utf8(output.stderr)
            .unwrap()
            .contains("/nonexistent/dir/out.csv")
    );
}

fn run_ok(args: &[&str]) {
    let out = headless(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn read(path: &PathBuf) -> String {
    std::fs::read_to_string(path).unwrap()
}

/// The world of a file written by --save-snapshot, as snapshot text.
fn saved_world_text(path: &Path) -> String {
    rigid::sim::SavedWorld::load(path).unwrap().world.to_ron()
}

#[test]
fn separate_processes_agree_bit_for_bit_and_resume_from_snapshots() {
    let [whole, again, half, resumed] =
        ["whole", "again", "half", "resumed"].map(|n| scratch(&format!("{n}.snapshot.ron")));
    let s = |p: &PathBuf| p.to_str().unwrap().to_owned();
    let run = ["--scene", "pachinko", "--steps"];
    run_ok(&[&run[..], &["200", "--save-snapshot", &s(&whole)]].concat());
    run_ok(&[&run[..], &["200", "--save-snapshot", &s(&again)]].concat());
    assert_eq!(read(&whole), read(&again));
    run_ok(&[&run[..], &["100", "--save-snapshot", &s(&half)]].concat());
    let from = [
        "--from-snapshot",
        &s(&half),
        "--save-snapshot",
        &s(&resumed),
    ];
    run_ok(&[&run[..], &["100"], &from[..]].concat());
    assert_eq!(read(&resumed), read(&whole));
    assert_ne!(read(&half), read(&whole));
}

#[test]
fn replay_in_another_process_matches_the_live_run() {
    use glam::DVec3;
    use rigid::sim::{Command as SimCommand, Simulation, SpawnKind};
    let mut live = Simulation::new("falling_box").unwrap();
    for tick in 0..180 {
        if tick % 20 == 5 {
            live.apply(SimCommand::Spawn {
                kind: SpawnKind::ALL[(tick / 20) % 5],
                position: DVec3::new(0.1 * tick as f64 / 20.0, 5.0, 0.0),
                velocity: DVec3::ZERO,
            });
        }
        if tick == 90 {
            live.apply(SimCommand::SetGravity(DVec3::new(1.0, -5.0, 0.0)));
        }
        live.step();
    }
    let recording = scratch("live.recording.ron");
    live.recording().save(&recording).unwrap();
    let replayed = scratch("replayed.snapshot.ron");
    run_ok(&[
        "--replay",
        recording.to_str().unwrap(),
        "--save-snapshot",
        replayed.to_str().unwrap(),
    ]);
    assert_eq!(
        saved_world_text(&replayed),
        live.world().to_snapshot().to_ron()
    );
}

#[test]
fn bad_snapshot_file_is_a_clear_error() {
    let path = write_scene("bad.snapshot.ron", "(format: 2, time: NaN)");
    let out = headless(&["--from-snapshot", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("bad.snapshot.ron"), "{stderr}");
}

#[test]
fn a_device_or_directory_as_input_is_refused() {
    for path in ["/dev/zero", "/"] {
        let out = headless(&["--scene", path, "--steps", "1"]);
        assert_eq!(out.status.code(), Some(2), "{path}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("not a regular file"), "{path}: {stderr}");
    }
}

#[test]
fn a_world_saved_by_the_viewer_continues_headless_at_its_own_dt() {
    use rigid::sim::{Command as SimCommand, Simulation};
    let saved = scratch("viewer.world.ron");
    let mut live = Simulation::new("pachinko").unwrap();
    for _ in 0..60 {
        live.step();
    }
    live.apply(SimCommand::SaveWorld(saved.clone()));
    for _ in 0..60 {
        live.step();
    }
    let out = scratch("continued.snapshot.ron");
    let from = saved.to_str().unwrap();
    run_ok(&[
        "--scene",
        "pachinko",
        "--from-snapshot",
        from,
        "--steps",
        "60",
        "--save-snapshot",
        out.to_str().unwrap(),
    ]);
    assert_eq!(saved_world_text(&out), live.world().to_snapshot().to_ron());
}

/// A recording of falling_box whose command 1 is `command` (RON), after a harmless one.
fn recording_with(name: &str, command: &str) -> PathBuf {
    write_scene(
        name,
        &format!(
            r#"(scene: "falling_box", ticks: 20, commands: [
    (tick: 2, command: SetPaused(false)),
    (tick: 5, command: {command}),
])"#
        ),
    )
}

#[test]
fn replay_never_writes_files_unless_allowed() {
    let victim = scratch("victim.txt");
    std::fs::write(&victim, "precious").unwrap();
    let recording = recording_with(
        "writes.recording.ron",
        &format!("SaveWorld({:?})", victim.to_str().unwrap()),
    );
    let out = headless(&["--replay", recording.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let expected = format!(
        "{}: command 1 (SaveWorld, tick 5) would access the file '{}'",
        recording.display(),
        victim.display()
    );
    assert!(stderr.contains(&expected), "{stderr}");
    assert!(stderr.contains("--allow-file-commands"), "{stderr}");
    assert_eq!(read(&victim), "precious");

    // The same recording with the user's permission saves the world where it says.
    run_ok(&[
        "--replay",
        recording.to_str().unwrap(),
        "--allow-file-commands",
    ]);
    let saved = rigid::sim::SavedWorld::load(&victim).unwrap();
    assert_eq!(saved.scene, "falling_box");
}

#[test]
fn replay_refuses_load_world_and_scene_files_unless_allowed() {
    let scene = free_fall_scene("replayed_scene.ron");
    for (name, command) in [
        (
            "loads_world.recording.ron",
            "LoadWorld(\"/etc/passwd\")".to_owned(),
        ),
        (
            "loads_scene.recording.ron",
            format!("LoadScene({:?})", scene.to_str().unwrap()),
        ),
        (
            "saves_recording.recording.ron",
            "SaveRecording(\"x.ron\")".to_owned(),
        ),
    ] {
        let recording = recording_with(name, &command);
        let out = headless(&["--replay", recording.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "{command}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("command 1 ("), "{stderr}");
        assert!(stderr.contains("would access the file"), "{stderr}");
    }
    // A built-in scene is no file: replaying a change to it needs no permission.
    let recording = recording_with("loads_builtin.recording.ron", "LoadScene(\"stack\")");
    run_ok(&["--replay", recording.to_str().unwrap()]);
}

#[test]
fn a_recorded_non_finite_dt_is_an_error_naming_the_command() {
    use rigid::sim::{Recording, RecordingError};
    for dt in ["NaN", "inf", "-0.01", "0.0", "1e300"] {
        let recording = recording_with("bad_dt.recording.ron", &format!("SetDt({dt})"));
        let out = headless(&["--replay", recording.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "{dt}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        let expected = format!(
            "{}: command 1 (SetDt, tick 5): dt must lie in",
            recording.display()
        );
        assert!(stderr.contains(&expected), "{dt}: {stderr}");
        assert!(out.stdout.is_empty(), "{dt}");

        let error = Recording::load(&recording).unwrap_err();
        assert!(
            matches!(
                error,
                RecordingError::BadCommand {
                    index: 1,
                    tick: 5,
                    command: "SetDt",
                    ..
                }
            ),
            "{error:?}"
        );
    }
}

#[test]
fn a_live_non_finite_dt_is_refused_and_the_world_keeps_moving() {
    use rigid::sim::{Command as SimCommand, Simulation};
    let mut sim = Simulation::new("falling_box").unwrap();
    let dt = sim.settings().dt;
    sim.apply(SimCommand::SetDt(f64::NAN));
    assert_eq!(sim.settings().dt, dt);
    let before = sim.world().time();
    sim.step();
    assert_eq!(sim.world().time(), before + dt);
    assert!(
        sim.recording().commands.is_empty(),
        "a refused command is not recorded"
    );
}

#[test]
fn an_output_naming_an_input_file_is_refused_before_anything_is_written() {
    let scene = free_fall_scene("input_scene.ron");
    let original = read(&scene);
    // The same file, spelled another way.
    let dir = scene.parent().unwrap();
    let respelled = dir.join(".").join(scene.file_name().unwrap());
    for flag in ["--csv", "--json", "--save-snapshot"] {
        let out = headless(&[
            "--scene",
            scene.to_str().unwrap(),
            "--steps",
            "3",
            flag,
            respelled.to_str().unwrap(),
        ]);
        assert_eq!(out.status.code(), Some(2), "{flag}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(&format!("{flag} ")), "{stderr}");
        assert!(stderr.contains("is the --scene file"), "{stderr}");
        assert_eq!(read(&scene), original, "{flag} overwrote the scene");
    }

    let snapshot = scratch("input.snapshot.ron");
    run_ok(&[
        "--steps",
        "2",
        "--save-snapshot",
        snapshot.to_str().unwrap(),
    ]);
    let saved = read(&snapshot);
    let out = headless(&[
        "--from-snapshot",
        snapshot.to_str().unwrap(),
        "--csv",
        snapshot.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("is the --from-snapshot file"));
    assert_eq!(read(&snapshot), saved);
    // Resuming in place replaces the snapshot by the continued world.
    run_ok(&[
        "--from-snapshot",
        snapshot.to_str().unwrap(),
        "--steps",
        "2",
        "--save-snapshot",
        snapshot.to_str().unwrap(),
    ]);
    assert_ne!(read(&snapshot), saved);
}

#[test]
fn a_resumed_snapshot_keeps_its_dt_and_scene() {
    let [whole, half, resumed] =
        ["whole_dt", "half_dt", "resumed_dt"].map(|n| scratch(&format!("{n}.snapshot.ron")));
    let s = |p: &PathBuf| p.to_str().unwrap().to_owned();
    let run = ["--scene", "pachinko", "--dt", "0.005", "--steps"];
    run_ok(&[&run[..], &["100", "--save-snapshot", &s(&whole)]].concat());
    run_ok(&[&run[..], &["50", "--save-snapshot", &s(&half)]].concat());
    // Neither --scene nor --dt: both come from the snapshot.
    let out = headless(&[
        "--from-snapshot",
        &s(&half),
        "--steps",
        "50",
        "--save-snapshot",
        &s(&resumed),
    ]);
    assert!(out.status.success(), "{out:?}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("scene            pachinko (resumed from"),
        "{stdout}"
    );
    assert!(stdout.contains(", dt 0.005 s"), "{stdout}");
    assert_eq!(read(&resumed), read(&whole));
    let saved = rigid::sim::SavedWorld::load(&resumed).unwrap();
    assert_eq!((saved.scene.as_str(), saved.dt), ("pachinko", 0.005));
    assert_eq!(saved.world.steps, 100);
}

#[test]
fn a_bare_snapshot_from_an_older_build_still_resumes_with_a_note() {
    let bare = scratch("bare.snapshot.ron");
    let world = rigid::scene::load("stack").unwrap().build_world().unwrap();
    std::fs::write(&bare, world.to_snapshot().to_ron()).unwrap();
    let out = headless(&[
        "--scene",
        "stack",
        "--from-snapshot",
        bare.to_str().unwrap(),
        "--steps",
        "3",
    ]);
    assert!(out.status.success(), "{out:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("holds no scene or dt"), "{stderr}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("scene            stack (resumed from"),
        "{stdout}"
    );
}

#[test]
fn a_closed_stdout_costs_neither_the_snapshot_nor_a_panic() {
    use std::process::Stdio;
    let snapshot = scratch("piped.snapshot.ron");
    let _ = std::fs::remove_file(&snapshot);
    let mut child = Command::new(env!("CARGO_BIN_EXE_headless"))
        .args(["--scene", "pachinko", "--steps", "300", "--save-snapshot"])
        .arg(&snapshot)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run headless");
    // The reader goes away long before the 300 steps are done, as `| true` does.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let saved = rigid::sim::SavedWorld::load(&snapshot).unwrap();
    assert_eq!(saved.world.steps, 300);
}

#[test]
fn a_negative_dt_reaches_the_validator() {
    let out = headless(&["--dt", "-0.01", "--steps", "1"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--dt must lie in [0.000001, 0.1] s, got -0.01"),
        "{stderr}"
    );
}

#[test]
fn a_local_file_named_like_a_built_in_scene_is_noted() {
    let dir = scratch("shadowing");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(free_fall_scene("shadow_source.ron"), dir.join("stack")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_headless"))
        .args(["--scene", "stack", "--steps", "1"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("note: 'stack' is the built-in scene; the file 'stack' here is not read (name it ./stack to load it)"),
        "{stderr}"
    );
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("scene            stack (scenes/stack.ron)")
    );
    // Spelled as a path, the file is what runs.
    let out = Command::new(env!("CARGO_BIN_EXE_headless"))
        .args(["--scene", "./stack", "--steps", "1"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    assert!(out.stderr.is_empty(), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("scene            free_fall (./stack)"));
}

/// 1 500 spheres created at one point make 1 124 250 pairs, more than the default pair
/// budget: the run keeps going and says on stderr that pairs were left out.
#[test]
fn a_step_over_the_pair_budget_is_reported() {
    let scene = write_scene(
        "pile_at_one_point.ron",
        r#"Scene(
    name: "pile",
    settings: (dt: 0.01),
    bodies: [
        (name: "ball", shape: Sphere(radius: 0.5),
         repeat: Grid(count: (1500, 1, 1), spacing: (0.0, 0.0, 0.0))),
    ],
)"#,
    );
    let output = headless(&["--scene", scene.to_str().unwrap(), "--steps", "1"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning: 1 step(s) found more than max_pairs (1000000) candidate pairs"),
        "{stderr}"
    );
}

/// A ball at 1e150 m/s (finite, with a finite energy) meets the floor: the world isolates
/// it, and the run says so on stderr, naming the body, the step and the reason, and counts
/// it in the summary. Before, the body silently dropped out of the CSV.
#[test]
fn each_fault_is_printed_with_its_body_step_and_reason_and_counted() {
    let scene = write_scene(
        "bullet.ron",
        r#"Scene(
    name: "bullet",
    settings: (dt: 0.01),
    bodies: [
        (name: "floor", shape: Cuboid(half_extents: (1.0, 0.1, 1.0)), static: true),
        (name: "calm", shape: Sphere(radius: 0.1), position: (5.0, 1.0, 0.0)),
        (name: "bullet", shape: Sphere(radius: 0.1), position: (0.0, 1.0, 0.0),
         velocity: (0.0, -1e150, 0.0)),
    ],
)"#,
    );
    let output = headless(&["--scene", scene.to_str().unwrap(), "--steps", "3"]);
    let (stdout, stderr) = (
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr),
    );
    assert!(output.status.success(), "{stderr}");
    let faults: Vec<&str> = stderr.lines().filter(|l| l.starts_with("fault:")).collect();
    assert_eq!(
        faults,
        [
            "fault: step 0 (t = 0 s): body 2 'bullet' isolated: it met another body at a \
             speed or spin over 1e15 (or a coordinate over 1e100), beyond what a contact can \
             compute"
        ],
        "{stderr}"
    );
    assert!(
        stdout.contains("faults           1 bodies isolated"),
        "{stdout}"
    );
}

/// A scene path that is not UTF-8 is refused naming the argument; before, the message
/// named none ("invalid UTF-8 was detected in one or more arguments").
#[cfg(unix)]
#[test]
fn a_non_utf8_scene_path_names_its_argument() {
    use std::os::unix::ffi::OsStrExt;
    let path = std::ffi::OsStr::from_bytes(b"scene-\xff.ron");
    let output = Command::new(env!("CARGO_BIN_EXE_headless"))
        .arg("--scene")
        .arg(path)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--scene <SCENE> is not valid UTF-8: 'scene-\u{fffd}.ron'"),
        "{stderr}"
    );
}
