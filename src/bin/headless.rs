//! Runs a scene without a window: steps it, optionally writes every body's state per step as
//! CSV or JSON lines, and prints a summary with energy and momentum drift.
//!
//! `headless --scene pachinko --steps 2000 --csv out.csv --every 10`
//!
//! A run can start from a saved world (`--from-snapshot`), save its final world
//! (`--save-snapshot`), or replay a recording of a viewer session (`--replay`).
//!
//! Exit codes: 0 on success, 2 on a bad scene, bad arguments or an unwritable output file.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, ValueEnum};
use glam::{DQuat, DVec3};
use rigid::physics::{Integrator, RigidBody, World, WorldSnapshot, WorldTotals};
use rigid::scene::{self, DEFAULT_SCENE, DT_RANGE, Scene};
use rigid::sim::{Recording, SavedWorld, Simulation};

#[derive(Parser, Debug)]
#[command(about = "Run a scene without a window and report energy and momentum")]
struct Args {
    /// A built-in scene name or a path to a .ron scene file.
    #[arg(long, default_value = DEFAULT_SCENE)]
    scene: String,
    /// Number of steps.
    #[arg(long, default_value_t = 1000)]
    steps: u64,
    /// Time step in seconds (default: the scene's).
    #[arg(long)]
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
    /// of the scene's initial one.
    #[arg(long)]
    from_snapshot: Option<PathBuf>,
    /// Save the final world to this file.
    #[arg(long)]
    save_snapshot: Option<PathBuf>,
    /// Replay a recording of a viewer session to its end (ignores --scene, --steps, --dt).
    #[arg(long, conflicts_with_all = ["from_snapshot", "csv", "json", "integrator"])]
    replay: Option<PathBuf>,
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
    if let Some(path) = &args.replay {
        return replay(args, path);
    }
    let scene = scene::load(&args.scene).map_err(|error| error.to_string())?;
    let start = match &args.from_snapshot {
        Some(path) => Some(load_saved(path)?),
        None => None,
    };
    let saved_dt = start.as_ref().and_then(|(_, dt)| *dt);
    let dt = args.dt.or(saved_dt).unwrap_or(scene.settings.dt);
    if !DT_RANGE.contains(&dt) {
        let (min, max) = DT_RANGE.into_inner();
        return Err(format!("--dt must lie in [{min}, {max}] s, got {dt}"));
    }
    let mut world = match (start, &args.from_snapshot) {
        (Some((snapshot, _)), Some(path)) => {
            World::from_snapshot(snapshot, &path.display().to_string())
                .map_err(|error| error.to_string())?
        }
        _ => scene.build_world().map_err(|error| error.to_string())?,
    };
    if let Some(integrator) = args.integrator {
        world.settings.integrator = integrator.into();
    }
    let mut output = StateWriter::open(args)?;

    let initial = world.totals();
    let started = Instant::now();
    output.write(&world)?;
    for step in 1..=args.steps {
        world.step(dt);
        if step % args.every == 0 || step == args.steps {
            output.write(&world)?;
        }
    }
    output.finish()?;
    let wall = started.elapsed().as_secs_f64();
    print_summary(&scene, &world, dt, wall, &initial);
    save_snapshot(args, &world)
}

/// A world saved by `--save-snapshot`, or by the viewer's "Save world" (which also knows the
/// step it ran at).
fn load_saved(path: &Path) -> Result<(WorldSnapshot, Option<f64>), String> {
    match WorldSnapshot::load(path) {
        Ok(snapshot) => Ok((snapshot, None)),
        Err(error) => match SavedWorld::load(path) {
            Ok(saved) => Ok((saved.world, Some(saved.dt))),
            Err(_) => Err(error.to_string()),
        },
    }
}

/// Runs a recording through the same `Simulation` the viewer uses, to its last tick.
fn replay(args: &Args, path: &Path) -> Result<(), String> {
    let recording = Recording::load(path)?;
    let scene = scene::load(&recording.scene).map_err(|error| error.to_string())?;
    let mut sim = Simulation::replaying(&recording)?;
    let initial = sim.world().totals();
    let started = Instant::now();
    while sim.ticks() < recording.ticks {
        sim.step();
    }
    let wall = started.elapsed().as_secs_f64();
    print_summary(&scene, sim.world(), sim.settings().dt, wall, &initial);
    save_snapshot(args, sim.world())
}

fn save_snapshot(args: &Args, world: &World) -> Result<(), String> {
    match &args.save_snapshot {
        Some(path) => world.to_snapshot().save(path).map_err(|e| e.to_string()),
        None => Ok(()),
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

fn print_summary(scene: &Scene, world: &World, dt: f64, wall: f64, initial: &WorldTotals) {
    let last = world.totals();
    let dynamic = world.bodies().iter().filter(|b| b.is_dynamic()).count();
    let simulated = world.time();
    let e0 = initial.kinetic_energy + initial.potential_energy;
    let e1 = last.kinetic_energy + last.potential_energy;
    println!("scene            {} ({})", scene.name, scene.origin);
    println!(
        "bodies           {} ({dynamic} dynamic)",
        world.bodies().len()
    );
    println!(
        "integrator       {}, dt {dt} s",
        world.settings.integrator.name()
    );
    println!(
        "steps            {}, simulated {simulated:.6} s, wall {wall:.6} s ({:.1}x real time)",
        world.step_count(),
        simulated / wall.max(1e-9)
    );
    println!(
        "energy K+U       initial {e0:.9e} J ({:.6e} + {:.6e}), final {e1:.9e} J ({:.6e} + {:.6e})",
        initial.kinetic_energy,
        initial.potential_energy,
        last.kinetic_energy,
        last.potential_energy
    );
    println!("energy drift     {}", drift(e0, e1));
    println!(
        "linear momentum  initial {}, final {} kg·m/s",
        initial.linear_momentum, last.linear_momentum
    );
    println!(
        "angular momentum initial {}, final {} kg·m²/s",
        initial.angular_momentum, last.angular_momentum
    );
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
