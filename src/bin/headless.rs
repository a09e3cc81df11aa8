//! Runs a scene without a window: steps it, optionally writes every body's state per step as
//! CSV or JSON lines, and prints a summary with energy and momentum drift.
//!
//! `headless --scene pachinko --steps 2000 --csv out.csv --every 10`
//!
//! A run can start from a saved world (`--from-snapshot`), save its final world
//! (`--save-snapshot`), or replay a recording of a viewer session (`--replay`).
//!
//! Progress goes to stderr (`rigid::progress`): a bar when stderr is a terminal, otherwise a
//! line every `PROGRESS_INTERVAL` of wall time (a short run prints none).
//!
//! Exit codes: 0 on success, 2 on a bad scene, bad arguments, an unwritable output file or
//! an output that names an input file. A closed stdout is not an error.

use std::fs::File;
use std::io::{BufWriter, ErrorKind, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, ValueEnum};
use glam::{DQuat, DVec3};
use rigid::cli_arg::Utf8Text;
use rigid::physics::{Integrator, RigidBody, SnapshotError, World, WorldSnapshot, WorldTotals};
use rigid::progress::Progress;
use rigid::scene::{self, DEFAULT_SCENE, DT_RANGE};
use rigid::sim::{FileCommands, Recording, SavedWorld, Simulation};

#[derive(Parser, Debug)]
#[command(about = "Run a scene without a window and report energy and momentum")]
struct Args {
    /// A built-in scene name or a path to a .ron scene file.
    #[arg(long, default_value = DEFAULT_SCENE, value_parser = Utf8Text)]
    scene: String,
    /// Number of steps.
    #[arg(long, default_value_t = 1000)]
    steps: u64,
    /// Time step in seconds (default: the scene's).
    #[arg(long, allow_negative_numbers = true)]
    dt: Option<f64>,
    /// Integrator (default: the scene's).
    #[arg(long, value_enum)]
    integrator: Option<IntegratorArg>,
    /// Write per-step states as CSV to this file.
    #[arg(long, conflicts_with = "json")]
    csv: Option<PathBuf>,
    /// Write per-step states as JSON lines to this file.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write every K-th step (the initial and the final state are always written).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    every: u64,
    /// Start from this saved world (from --save-snapshot or the viewer's "Save world") instead
    /// of the scene's initial one; it runs at its own dt and keeps its scene's name.
    #[arg(long)]
    from_snapshot: Option<PathBuf>,
    /// Save the final world to this file, with its scene and dt (the viewer's "Load world"
    /// and --from-snapshot read it).
    #[arg(long)]
    save_snapshot: Option<PathBuf>,
    /// Replay a recording of a viewer session to its end (ignores --scene, --steps, --dt).
    #[arg(long, conflicts_with_all = ["from_snapshot", "csv", "json", "integrator"])]
    replay: Option<PathBuf>,
    /// Let --replay run the recording's commands that save or load files (SaveWorld,
    /// SaveRecording, LoadWorld, LoadScene of a file); without it such a recording is refused.
    #[arg(long, requires = "replay")]
    allow_file_commands: bool,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
#[value(rename_all = "snake_case")]
enum IntegratorArg {
    ReportEuler,
    ExactRotation,
    Midpoint,
}

impl From<IntegratorArg> for Integrator {
    fn from(arg: IntegratorArg) -> Self {
        match arg {
            IntegratorArg::ReportEuler => Integrator::ReportEuler,
            IntegratorArg::ExactRotation => Integrator::ExactRotation,
            IntegratorArg::Midpoint => Integrator::Midpoint,
        }
    }
}

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}

fn run(args: &Args) -> Result<(), String> {
    refuse_overwriting_inputs(args)?;
    if let Some(path) = &args.replay {
        return replay(args, path);
    }
    let start = match &args.from_snapshot {
        Some(path) => Start::from_saved(path, &args.scene)?,
        None => Start::from_scene(&args.scene)?,
    };
    let dt = args.dt.unwrap_or(start.dt);
    if !DT_RANGE.contains(&dt) {
        let (min, max) = DT_RANGE.into_inner();
        return Err(format!("--dt must lie in [{min}, {max}] s, got {dt}"));
    }
    let mut world = start.world;
    if let Some(integrator) = args.integrator {
        world.settings.integrator = integrator.into();
    }
    let mut output = StateWriter::open(args)?;

    let initial = world.totals();
    let started = Instant::now();
    output.write(&world)?;
    let mut progress = Progress::new("steps", args.steps);
    let mut faults = FaultLog::after(&world);
    for step in 1..=args.steps {
        scene::drive(&start.motions, &mut world, dt);
        world.step(dt);
        if step % args.every == 0 || step == args.steps {
            output.write(&world)?;
        }
        faults.report_new(&world, &progress);
        progress.update(step);
    }
    progress.finish();
    output.finish()?;
    let wall = started.elapsed().as_secs_f64();
    // Saved before the summary is printed, so that a closed stdout never costs the file.
    if let Some(path) = &args.save_snapshot {
        let saved = SavedWorld {
            scene: start.scene,
            dt,
            hidden: start.hidden,
            materials: start.materials,
            world: world.to_snapshot(),
        };
        saved.save(path)?;
    }
    print_summary(&start.label, &world, dt, wall, &initial)
}

/// Refuses outputs that name an input file (the same file, however spelled): writing them
/// would destroy what the run reads. Saving over the snapshot a run resumes from is allowed,
/// since that file is only read before the run starts and is replaced whole.
fn refuse_overwriting_inputs(args: &Args) -> Result<(), String> {
    let scene = (scene::find_builtin(&args.scene).is_none()).then(|| Path::new(&args.scene));
    let inputs = [
        ("--scene", scene),
        ("--from-snapshot", args.from_snapshot.as_deref()),
        ("--replay", args.replay.as_deref()),
    ];
    let outputs = [
        ("--csv", args.csv.as_deref()),
        ("--json", args.json.as_deref()),
        ("--save-snapshot", args.save_snapshot.as_deref()),
    ];
    for (output_flag, output) in outputs {
        for (input_flag, input) in inputs {
            let (Some(output), Some(input)) = (output, input) else {
                continue;
            };
            let resumes_in_place =
                output_flag == "--save-snapshot" && input_flag == "--from-snapshot";
            if !resumes_in_place && same_file(output, input) {
                return Err(format!(
                    "{output_flag} {} is the {input_flag} file: refusing to overwrite an input",
                    output.display()
                ));
            }
        }
    }
    Ok(())
}

/// Both exist and resolve to the same path (an output that does not exist yet is no input).
fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// The world a run starts from, with what its saved world carries beside it.
struct Start {
    world: World,
    /// The built-in scene name or scene file path, as a saved world records it.
    scene: String,
    /// How the summary names the scene.
    label: String,
    /// The step to run at unless --dt says otherwise, s.
    dt: f64,
    hidden: Vec<bool>,
    materials: Vec<String>,
    /// The scripts of the scene's kinematic bodies, driven before each step.
    motions: Vec<scene::ScriptedMotion>,
}

impl Start {
    fn from_scene(name: &str) -> Result<Start, String> {
        if let Some(note) = scene::shadowed_file_note(name) {
            eprintln!("note: {note}");
        }
        let scene = scene::load(name).map_err(|error| error.to_string())?;
        Ok(Start {
            world: scene.build_world().map_err(|error| error.to_string())?,
            scene: name.to_string(),
            label: format!("{} ({})", scene.name, scene.origin),
            dt: scene.settings.dt,
            hidden: scene.hidden_bodies(),
            materials: scene.material_names(),
            motions: scene
                .scripted_motions()
                .map_err(|error| error.to_string())?,
        })
    }

    /// A world saved by --save-snapshot or the viewer's "Save world", which carry their scene
    /// and dt; or a bare world snapshot, as older builds wrote, which carries neither: the
    /// scene `scene` (--scene) supplies them, with a note.
    fn from_saved(path: &Path, scene: &str) -> Result<Start, String> {
        let file = path.display().to_string();
        let saved = match SavedWorld::load(path) {
            Ok(saved) => saved,
            Err(saved_error) => {
                let snapshot = match WorldSnapshot::load(path) {
                    Ok(snapshot) => snapshot,
                    // Text that is not even a bare snapshot: the saved world's error says
                    // more, since that is what this build writes.
                    Err(SnapshotError::Unreadable { .. }) => return Err(saved_error),
                    Err(error) => return Err(error.to_string()),
                };
                let dt = scene::load(scene)
                    .map_err(|error| error.to_string())?
                    .settings
                    .dt;
                eprintln!(
                    "note: {file} holds no scene or dt (written by an older build); \
                     taking them from --scene {scene}"
                );
                SavedWorld {
                    scene: scene.to_string(),
                    dt,
                    hidden: Vec::new(),
                    materials: Vec::new(),
                    world: snapshot,
                }
            }
        };
        Ok(Start {
            world: World::from_snapshot(saved.world, &file).map_err(|error| error.to_string())?,
            label: format!("{} (resumed from {file})", saved.scene),
            motions: saved_motions(&saved.scene),
            scene: saved.scene,
            dt: saved.dt,
            hidden: saved.hidden,
            materials: saved.materials,
        })
    }
}

/// A resumed world's scripts come from its scene, when that still loads; they go on from
/// the world's time.
fn saved_motions(scene: &str) -> Vec<scene::ScriptedMotion> {
    let loaded = scene::load(scene).ok();
    loaded
        .and_then(|scene| scene.scripted_motions().ok())
        .unwrap_or_default()
}

/// Runs a recording through the same `Simulation` the viewer uses, to its last tick.
fn replay(args: &Args, path: &Path) -> Result<(), String> {
    let recording = Recording::load(path).map_err(|error| error.to_string())?;
    let scene = scene::load(&recording.scene).map_err(|error| error.to_string())?;
    let files = if args.allow_file_commands {
        FileCommands::Allow
    } else {
        FileCommands::Refuse
    };
    let file = path.display().to_string();
    let mut sim =
        Simulation::replaying(&recording, &file, files).map_err(|error| error.to_string())?;
    let initial = sim.world().totals();
    let started = Instant::now();
    let mut progress = Progress::new("ticks", recording.ticks);
    let mut faults = FaultLog::after(sim.world());
    while sim.ticks() < recording.ticks {
        sim.step();
        faults.report_new(sim.world(), &progress);
        progress.update(sim.ticks());
    }
    progress.finish();
    let wall = started.elapsed().as_secs_f64();
    if let Some(path) = &args.save_snapshot {
        sim.saved_world().save(path)?;
    }
    let label = format!("{} ({})", scene.name, scene.origin);
    print_summary(&label, sim.world(), sim.settings().dt, wall, &initial)
}

/// Prints each fault as the step that caught it reports it: an isolated body drops out of
/// the CSV, and without a word the reader could not tell why.
struct FaultLog {
    /// Faults already printed, or present when the run started (a resumed world's).
    reported: usize,
}

impl FaultLog {
    fn after(world: &World) -> Self {
        FaultLog {
            reported: world.faults().len(),
        }
    }

    fn report_new(&mut self, world: &World, progress: &Progress) {
        for fault in &world.faults()[self.reported..] {
            progress.println(&format!(
                "fault: step {} (t = {} s): body {} '{}' isolated: {}",
                fault.step,
                fault.time,
                fault.body.index(),
                fault.name,
                fault.reason
            ));
        }
        self.reported = world.faults().len();
    }
}

enum Format {
    Csv,
    JsonLines,
}

/// Per-step states of the dynamic bodies (static ones never move). Positions are centres of
/// mass; rotations are quaternions (x, y, z, w).
struct StateWriter {
    out: Option<(BufWriter<File>, Format, PathBuf)>,
}

impl StateWriter {
    fn open(args: &Args) -> Result<Self, String> {
        let target = match (&args.csv, &args.json) {
            (Some(path), _) => Some((path.clone(), Format::Csv)),
            (None, Some(path)) => Some((path.clone(), Format::JsonLines)),
            (None, None) => None,
        };
        let Some((path, format)) = target else {
            return Ok(StateWriter { out: None });
        };
        let file = File::create(&path)
            .map_err(|error| format!("{}: cannot create: {error}", path.display()))?;
        let mut writer = StateWriter {
            out: Some((BufWriter::new(file), format, path)),
        };
        if let Some((out, Format::Csv, _)) = &mut writer.out {
            let header = "step,time,body,name,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz";
            writeln!(out, "{header}").map_err(|error| error.to_string())?;
        }
        Ok(writer)
    }

    fn write(&mut self, world: &World) -> Result<(), String> {
        let Some((out, format, path)) = &mut self.out else {
            return Ok(());
        };
        for (index, body) in world.bodies().iter().enumerate() {
            if !body.is_dynamic() {
                continue;
            }
            let row = match format {
                Format::Csv => csv_row(world, index, body),
                Format::JsonLines => json_line(world, index, body),
            };
            writeln!(out, "{row}")
                .map_err(|error| format!("{}: cannot write: {error}", path.display()))?;
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), String> {
        match &mut self.out {
            Some((out, _, path)) => out
                .flush()
                .map_err(|error| format!("{}: cannot write: {error}", path.display())),
            None => Ok(()),
        }
    }
}

/// Floats are written with Rust's shortest round-trip formatting, so values read back exactly.
fn csv_row(world: &World, index: usize, body: &RigidBody) -> String {
    let q = body.rotation();
    let numbers: Vec<String> = [body.position, body.velocity(), body.angular_velocity()]
        .iter()
        .flat_map(|v| v.to_array())
        .map(|x| x.to_string())
        .collect();
    format!(
        "{},{},{index},{},{},{},{},{},{},{},{}",
        world.step_count(),
        world.time(),
        csv_field(&body.name),
        numbers[..3].join(","),
        q.x,
        q.y,
        q.z,
        q.w,
        numbers[3..6].join(","),
        numbers[6..].join(",")
    )
}

fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}

fn json_line(world: &World, index: usize, body: &RigidBody) -> String {
    format!(
        "{{\"step\":{},\"time\":{},\"body\":{index},\"name\":{},\"position\":{},\"rotation\":{},\"velocity\":{},\"angular_velocity\":{}}}",
        world.step_count(),
        json_number(world.time()),
        json_string(&body.name),
        json_vec(body.position),
        json_quat(body.rotation()),
        json_vec(body.velocity()),
        json_vec(body.angular_velocity()),
    )
}

/// JSON has no NaN or infinity: a diverged state is written as null.
fn json_number(x: f64) -> String {
    if x.is_finite() {
        x.to_string()
    } else {
        "null".to_owned()
    }
}

fn json_vec(v: DVec3) -> String {
    format!(
        "[{},{},{}]",
        json_number(v.x),
        json_number(v.y),
        json_number(v.z)
    )
}

fn json_quat(q: DQuat) -> String {
    format!(
        "[{},{},{},{}]",
        json_number(q.x),
        json_number(q.y),
        json_number(q.z),
        json_number(q.w)
    )
}

fn json_string(text: &str) -> String {
    let mut quoted = String::from('"');
    for c in text.chars() {
        match c {
            '"' => quoted.push_str("\\\""),
            '\\' => quoted.push_str("\\\\"),
            c if (c as u32) < 0x20 => quoted.push_str(&format!("\\u{:04x}", c as u32)),
            c => quoted.push(c),
        }
    }
    quoted.push('"');
    quoted
}

/// Prints the summary. A reader that went away (`| head`, `| true`) is no error: the run's
/// files are written by then, and there is no one left to tell.
fn print_summary(
    label: &str,
    world: &World,
    dt: f64,
    wall: f64,
    initial: &WorldTotals,
) -> Result<(), String> {
    // On stderr, as the summary on stdout may be read by a script.
    if let Some(fault) = world.pair_budget_fault() {
        eprintln!(
            "warning: {} step(s) found more than max_pairs ({}) candidate pairs and left the \
             rest without contacts, the last at step {}",
            fault.steps_over, fault.max_pairs, fault.step
        );
    }
    let text = summary(label, world, dt, wall, initial);
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(error) if error.kind() != ErrorKind::BrokenPipe => {
            Err(format!("cannot write to stdout: {error}"))
        }
        _ => Ok(()),
    }
}

fn summary(label: &str, world: &World, dt: f64, wall: f64, initial: &WorldTotals) -> String {
    let last = world.totals();
    let dynamic = world.bodies().iter().filter(|b| b.is_dynamic()).count();
    let simulated = world.time();
    let e0 = initial.kinetic_energy + initial.potential_energy;
    let e1 = last.kinetic_energy + last.potential_energy;
    let lines = [
        format!("scene            {label}"),
        format!(
            "bodies           {} ({dynamic} dynamic)",
            world.bodies().len()
        ),
        format!(
            "integrator       {}, dt {dt} s",
            world.settings.integrator.name()
        ),
        format!(
            "steps            {}, simulated {simulated:.6} s, wall {wall:.6} s ({:.1}x real time)",
            world.step_count(),
            simulated / wall.max(1e-9)
        ),
        format!(
            "energy K+U       initial {e0:.9e} J ({:.6e} + {:.6e}), final {e1:.9e} J ({:.6e} + {:.6e})",
            initial.kinetic_energy,
            initial.potential_energy,
            last.kinetic_energy,
            last.potential_energy
        ),
        format!("energy drift     {}", drift(e0, e1)),
        format!(
            "faults           {} bodies isolated (non-finite or beyond contact range)",
            world.faults().len()
        ),
        format!(
            "linear momentum  initial {}, final {} kg·m/s",
            initial.linear_momentum, last.linear_momentum
        ),
        format!(
            "angular momentum initial {}, final {} kg·m²/s",
            initial.angular_momentum, last.angular_momentum
        ),
    ];
    lines.iter().map(|line| format!("{line}\n")).collect()
}

/// Relative when the initial energy is not (close to) zero; potential energy is measured from
/// the origin, so a scene can start at E = 0 and a relative figure would mean nothing.
fn drift(e0: f64, e1: f64) -> String {
    if e0.abs() > 1e-12 {
        format!("{:.3e} (relative)", (e1 - e0) / e0.abs())
    } else {
        format!("{:.3e} J (absolute; initial energy is 0)", e1 - e0)
    }
}
