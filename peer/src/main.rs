//! Side-by-side benchmark of our engine (`rigid`) against rapier3d on the same scenes: wall
//! time per step and error against a reference, printed as a Markdown section.
//!
//! Run: `CARGO_TARGET_DIR=/work/target-peer cargo run --release --manifest-path peer/Cargo.toml`
//! (every scene; `-- --help` lists the options: `--scene`, `--steps`, `--repeats`).

mod box3d;
mod ours;
mod overlap;
mod scenes;
mod stages;
mod stress;
mod theirs;

use std::time::Instant;

use glam::{DMat3, DVec3};

use crate::ours::Ours;
use crate::overlap::overlap;
use crate::scenes::{DT, GRAVITY, SceneDesc};
use crate::theirs::Theirs;

/// What the benchmark needs from an engine. Body `i` is `scene.bodies[i]` in both engines.
pub trait Engine {
    /// The engine's name, for progress lines.
    const NAME: &'static str;
    /// With `substeps` solver substeps (rapier: solver iterations), or the engine's default.
    fn build(scene: &SceneDesc, substeps: Option<u32>) -> Self;
    fn step(&mut self);
    /// Centre of mass, world.
    fn position(&self, i: usize) -> DVec3;
    /// Body axes in world axes.
    fn orientation(&self, i: usize) -> DMat3;
    fn velocity(&self, i: usize) -> DVec3;
    fn kinetic_energy(&self, i: usize) -> f64;
    fn mass(&self, i: usize) -> f64;
    fn is_sleeping(&self, i: usize) -> bool;
}

/// Timed runs per scene; the median is reported.
const REPEATS: usize = 5;

/// A pyramid run takes a tenth of a second, and a tenth of a second on this kind of shared
/// machine is at the mercy of its neighbours: its medians moved by up to 45 % between runs
/// at 5 repeats. More repeats cost little there.
const PYRAMID_REPEATS: usize = 31;

/// Builds the scene, runs all its steps and returns the engine as it ended and the wall time
/// per step in ms. Only the steps are timed, not the building.
fn run<E: Engine>(scene: &SceneDesc, substeps: Option<u32>) -> (E, f64) {
    let mut engine = E::build(scene, substeps);
    let start = Instant::now();
    for _ in 0..scene.steps {
        engine.step();
    }
    let ms = start.elapsed().as_secs_f64() * 1e3 / scene.steps as f64;
    (engine, ms)
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Both engines `repeats` times each, taking turns so that a load that comes and goes on the
/// machine falls on both alike, each with the substeps given (None: its default). Returns
/// each engine's last run (the runs are deterministic) and the median ms per step of each.
fn run_both_times(
    scene: &SceneDesc,
    ours_substeps: Option<u32>,
    theirs_substeps: Option<u32>,
    repeats: usize,
) -> ((Ours, f64), (Theirs, f64)) {
    let (mut ours_times, mut theirs_times) = (Vec::new(), Vec::new());
    let (mut ours_last, mut theirs_last) = (None, None);
    for _ in 0..repeats {
        let (engine, ms) = run::<Ours>(scene, ours_substeps);
        ours_times.push(ms);
        ours_last = Some(engine);
        let (engine, ms) = run::<Theirs>(scene, theirs_substeps);
        theirs_times.push(ms);
        theirs_last = Some(engine);
    }
    (
        (ours_last.expect("ran"), median(ours_times)),
        (theirs_last.expect("ran"), median(theirs_times)),
    )
}

/// A scene's simulated time, for the table ("10 s").
fn duration(scene: &SceneDesc) -> String {
    format!("{} s", (scene.steps as f64 * DT * 100.0).round() / 100.0)
}

/// One table row: times in ms per step, errors already formatted, and the error ratio when
/// the two errors are comparable numbers.
struct Row {
    scene: String,
    ours_ms: f64,
    theirs_ms: f64,
    ours_error: String,
    theirs_error: String,
    /// |our error| / |their error|, when both are numbers and theirs is not zero.
    error_ratio: Option<f64>,
}

fn ratio(ours: f64, theirs: f64) -> Option<f64> {
    (theirs != 0.0).then(|| ours.abs() / theirs.abs())
}

fn dynamic_bodies(scene: &SceneDesc) -> impl Iterator<Item = usize> + '_ {
    (0..scene.bodies.len()).filter(|&i| !scene.bodies[i].fixed)
}

// ---------------------------------------------------------------------------------------
// Scenes 1 and 2: time and health of larger scenes.

/// Largest distance any box has moved from where it started, m, and how many are asleep.
fn pyramid_result<E: Engine>(engine: &E, scene: &SceneDesc) -> (f64, usize, usize) {
    let drift = dynamic_bodies(scene)
        .map(|i| engine.position(i).distance(scene.bodies[i].position))
        .fold(0.0, f64::max);
    let asleep = dynamic_bodies(scene)
        .filter(|&i| engine.is_sleeping(i))
        .count();
    (drift, asleep, dynamic_bodies(scene).count())
}

fn pyramid_row(opts: &Options) -> Row {
    let scene = opts.cut(scenes::pyramid());
    let ((ours, ours_ms), (theirs, theirs_ms)) =
        run_both_times(&scene, None, None, opts.repeats(PYRAMID_REPEATS));
    let (ours_drift, ours_asleep, n) = pyramid_result(&ours, &scene);
    let (theirs_drift, theirs_asleep, _) = pyramid_result(&theirs, &scene);
    let cell =
        |drift: f64, asleep: usize| format!("drift {:.1} mm, {asleep}/{n} asleep", drift * 1e3);
    Row {
        scene: format!("pyramid, {n} boxes, {}", duration(&scene)),
        ours_ms,
        theirs_ms,
        ours_error: cell(ours_drift, ours_asleep),
        theirs_error: cell(theirs_drift, theirs_asleep),
        error_ratio: ratio(ours_drift, theirs_drift),
    }
}

/// Kinetic plus potential energy of the dynamic bodies, potential measured from the floor's
/// top (y = 0), J. Both engines' energies are summed by the same code.
fn total_energy<E: Engine>(engine: &E, scene: &SceneDesc) -> f64 {
    dynamic_bodies(scene)
        .map(|i| engine.kinetic_energy(i) + engine.mass(i) * GRAVITY * engine.position(i).y)
        .sum()
}

/// Bodies outside the bin, and the energy at the end over the energy at the start.
fn rain_result<E: Engine>(engine: &E, scene: &SceneDesc, bin: scenes::Bin) -> (usize, f64) {
    let escaped = dynamic_bodies(scene)
        .filter(|&i| !bin.holds(engine.position(i)))
        .count();
    // The start energy from this engine's own masses (a fresh build: all at rest).
    let start = total_energy(&E::build(scene, None), scene);
    (escaped, total_energy(engine, scene) / start)
}

fn rain_row(count: usize, opts: &Options) -> Row {
    let (scene, bin) = scenes::rain(count);
    let scene = opts.cut(scene);
    let ((ours, ours_ms), (theirs, theirs_ms)) =
        run_both_times(&scene, None, None, opts.repeats(REPEATS));
    let (ours_escaped, ours_energy) = rain_result(&ours, &scene, bin);
    let (theirs_escaped, theirs_energy) = rain_result(&theirs, &scene, bin);
    let (ours_overlap, theirs_overlap) = (overlap(&ours, &scene), overlap(&theirs, &scene));
    let cell = |escaped: usize, energy: f64, overlap: overlap::Overlap| {
        format!(
            "{escaped} escaped, E/E₀ {energy:.3}, overlap deepest {:.1} mm, mean {:.2} mm ({} pairs)",
            overlap.deepest * 1e3,
            overlap.mean * 1e3,
            overlap.pairs
        )
    };
    Row {
        scene: format!(
            "rain {count}, bin {w:.0} × {w:.0} × {h:.2} m, {}",
            duration(&scene),
            w = 2.0 * bin.half_width,
            h = bin.wall_height
        ),
        ours_ms,
        theirs_ms,
        ours_error: cell(ours_escaped, ours_energy, ours_overlap),
        theirs_error: cell(theirs_escaped, theirs_energy, theirs_overlap),
        error_ratio: ratio(ours_overlap.deepest, theirs_overlap.deepest),
    }
}

// ---------------------------------------------------------------------------------------
// Scene 3: small cases with analytic answers, run once each (they are deterministic).

/// Builds the scene and runs it, calling `observe` after every step. Returns the engine as
/// it ended and the ms per step (the steps alone are timed).
fn run_observed<E: Engine>(scene: &SceneDesc, mut observe: impl FnMut(&E)) -> (E, f64) {
    let mut engine = E::build(scene, None);
    let mut seconds = 0.0;
    for _ in 0..scene.steps {
        let start = Instant::now();
        engine.step();
        seconds += start.elapsed().as_secs_f64();
        observe(&engine);
    }
    (engine, seconds * 1e3 / scene.steps as f64)
}

/// Signed relative error, and a cell showing the value with it.
fn relative(value: f64, exact: f64, unit: &str) -> (f64, String) {
    let error = (value - exact) / exact;
    (
        error,
        format!("{value:.4} {unit} ({:+.3} %)", error * 100.0),
    )
}

/// C2: heights of the ball's bottom at the first three apexes. An apex is the highest
/// sampled height of a rise (from the step the ball moves up to the step it stops rising);
/// sampling at dt misses the true top by at most g·dt²/8 = 0.34 mm.
fn bounce_apexes<E: Engine>(scene: &SceneDesc, radius: f64) -> (Vec<f64>, f64) {
    let mut apexes = Vec::new();
    let mut rising_max: Option<f64> = None;
    let (_, ms) = run_observed::<E>(scene, |engine| {
        let height = engine.position(1).y - radius;
        let vy = engine.velocity(1).y;
        match rising_max {
            _ if vy > 0.0 => rising_max = Some(rising_max.map_or(height, |m| m.max(height))),
            Some(top) => {
                apexes.push(top.max(height));
                rising_max = None;
            }
            None => {}
        }
    });
    (apexes, ms)
}

fn bounce_rows(opts: &Options) -> Vec<Row> {
    const DROP: f64 = 5.0;
    const RESTITUTION: f64 = 0.8;
    let scene = opts.cut(scenes::bounce(DROP, RESTITUTION));
    let (ours, ours_ms) = bounce_apexes::<Ours>(&scene, 0.5);
    let (theirs, theirs_ms) = bounce_apexes::<Theirs>(&scene, 0.5);
    (1..=3)
        .map(|k| {
            let exact = DROP * RESTITUTION.powi(2 * k as i32);
            let cell = |apexes: &[f64]| match apexes.get(k - 1) {
                Some(&h) => relative(h, exact, "m"),
                None => (f64::NAN, "no apex".to_owned()),
            };
            let (ours_error, ours_cell) = cell(&ours);
            let (theirs_error, theirs_cell) = cell(&theirs);
            Row {
                scene: format!("C2 bounce apex {k} (exact {exact:.4} m)"),
                ours_ms,
                theirs_ms,
                ours_error: ours_cell,
                theirs_error: theirs_cell,
                error_ratio: ratio(ours_error, theirs_error).filter(|r| r.is_finite()),
            }
        })
        .collect()
}

fn slide_row(opts: &Options) -> Row {
    const SPEED: f64 = 5.0;
    const MU: f64 = 0.5;
    let scene = opts.cut(scenes::slide(SPEED));
    let exact = SPEED * SPEED / (2.0 * MU * GRAVITY);
    let distance = |position: DVec3, speed: f64| {
        let (error, cell) = relative(position.x - scene.bodies[1].position.x, exact, "m");
        // A box still moving at the end has not stopped: say so rather than hide it.
        let cell = if speed > 1e-3 {
            format!("{cell}, still moving at {speed:.3} m/s")
        } else {
            cell
        };
        (error, cell)
    };
    let (ours, ours_ms) = run_observed::<Ours>(&scene, |_| {});
    let (theirs, theirs_ms) = run_observed::<Theirs>(&scene, |_| {});
    let (ours_error, ours_cell) = distance(ours.position(1), ours.velocity(1).length());
    let (theirs_error, theirs_cell) = distance(theirs.position(1), theirs.velocity(1).length());
    Row {
        scene: format!("C4 slide, stopping distance (exact {exact:.4} m)"),
        ours_ms,
        theirs_ms,
        ours_error: ours_cell,
        theirs_error: theirs_cell,
        error_ratio: ratio(ours_error, theirs_error),
    }
}

fn roll_row(opts: &Options) -> Row {
    let scene = opts.cut(scenes::roll(ROLL_SPEED));
    let exact = rolled_speed();
    let (ours, ours_ms) = run_observed::<Ours>(&scene, |_| {});
    let (theirs, theirs_ms) = run_observed::<Theirs>(&scene, |_| {});
    let (ours_error, ours_cell) = relative(rolling_speed(&ours), exact, "m/s");
    let (theirs_error, theirs_cell) = relative(rolling_speed(&theirs), exact, "m/s");
    Row {
        scene: format!("C6 rolling, final speed (exact {exact:.4} m/s)"),
        ours_ms,
        theirs_ms,
        ours_error: ours_cell,
        theirs_error: theirs_cell,
        error_ratio: ratio(ours_error, theirs_error),
    }
}

// ---------------------------------------------------------------------------------------
// Work against error: both engines over their substeps.

/// Our substeps (default 8) and rapier's solver iterations (default 4), run in pairs taking
/// turns: each engine from below its default to well above it.
const SWEEP: &[(u32, u32)] = &[(3, 2), (4, 4), (5, 6), (6, 8), (8, 12)];

/// The rain of 4000 takes half a minute a run: our 4 substeps against rapier's default,
/// three runs each.
const LARGE_SWEEP: &[(u32, u32)] = &[(4, 4)];
const LARGE_REPEATS: usize = 3;

/// What a sweep measures as the error of a run.
#[derive(Clone, Copy)]
enum SweepError {
    /// The pyramid's worst drift, m.
    Drift,
    /// The deepest overlap of two bodies at the end, m.
    DeepestOverlap,
    /// C6: |final speed / (5/7 v0) − 1| of a ball launched sliding at `ROLL_SPEED`.
    RollingSpeed,
}

/// C6's launch speed, m/s.
const ROLL_SPEED: f64 = 3.0;

/// C6's exact answer: a ball launched sliding at v0 rolls at 5/7 v0.
fn rolled_speed() -> f64 {
    5.0 / 7.0 * ROLL_SPEED
}

/// C6: the ball's speed along the floor.
fn rolling_speed<E: Engine>(engine: &E) -> f64 {
    let v = engine.velocity(1);
    DVec3::new(v.x, 0.0, v.z).length()
}

impl SweepError {
    fn of<E: Engine>(self, engine: &E, scene: &SceneDesc) -> f64 {
        match self {
            SweepError::Drift => pyramid_result(engine, scene).0,
            SweepError::DeepestOverlap => overlap(engine, scene).deepest,
            SweepError::RollingSpeed => (rolling_speed(engine) / rolled_speed() - 1.0).abs(),
        }
    }

    fn name(self) -> &'static str {
        match self {
            SweepError::Drift => "worst drift",
            SweepError::DeepestOverlap => "deepest overlap",
            SweepError::RollingSpeed => "final speed off by",
        }
    }

    fn show(self, error: f64) -> String {
        match self {
            SweepError::Drift | SweepError::DeepestOverlap => format!("{:.1} mm", error * 1e3),
            SweepError::RollingSpeed => format!("{:.4} %", error * 1e2),
        }
    }
}

/// One engine at one setting: median ms per step and the error, m.
struct Setting {
    substeps: u32,
    ms: f64,
    error: f64,
}

struct Sweep {
    scene: String,
    error: SweepError,
    ours: Vec<Setting>,
    theirs: Vec<Setting>,
}

fn sweep(
    scene_name: &str,
    scene: &SceneDesc,
    error: SweepError,
    settings: &[(u32, u32)],
    repeats: usize,
) -> Sweep {
    let (mut ours, mut theirs) = (Vec::new(), Vec::new());
    for &(our_substeps, their_iterations) in settings {
        let ((o, o_ms), (t, t_ms)) =
            run_both_times(scene, Some(our_substeps), Some(their_iterations), repeats);
        ours.push(Setting {
            substeps: our_substeps,
            ms: o_ms,
            error: error.of(&o, scene),
        });
        theirs.push(Setting {
            substeps: their_iterations,
            ms: t_ms,
            error: error.of(&t, scene),
        });
    }
    Sweep {
        scene: scene_name.to_owned(),
        error,
        ours,
        theirs,
    }
}

fn sweep_table(sweeps: &[Sweep]) -> String {
    let mut out = String::from(
        "| scene | engine | substeps (rapier: solver iterations) | ms/step | error |\n\
         |---|---|---|---|---|\n",
    );
    for sweep in sweeps {
        for (engine, settings) in [("ours", &sweep.ours), ("rapier", &sweep.theirs)] {
            for s in settings {
                out += &format!(
                    "| {} | {engine} | {} | {:.4} | {} {} |\n",
                    sweep.scene,
                    s.substeps,
                    s.ms,
                    sweep.error.name(),
                    sweep.error.show(s.error)
                );
            }
        }
    }
    out
}

/// For each of rapier's settings, our fastest setting at equal or lower error, and the
/// ratio of the times.
fn sweep_verdicts(sweeps: &[Sweep]) -> String {
    let mut out = String::new();
    for sweep in sweeps {
        for theirs in &sweep.theirs {
            let ours = (sweep.ours.iter())
                .filter(|o| o.error <= theirs.error)
                .min_by(|x, y| x.ms.total_cmp(&y.ms));
            let verdict = match ours {
                Some(o) => format!(
                    "our fastest at equal or lower error is {} substeps ({}, {:.4} \
                     ms/step): time ratio {:.2}",
                    o.substeps,
                    sweep.error.show(o.error),
                    o.ms,
                    o.ms / theirs.ms
                ),
                None => "no setting of ours tried is as accurate".to_owned(),
            };
            out += &format!(
                "- {}, rapier at {} iterations ({} {}, {:.4} ms/step): {verdict}.\n",
                sweep.scene,
                theirs.substeps,
                sweep.error.name(),
                sweep.error.show(theirs.error),
                theirs.ms
            );
        }
    }
    out
}

// ---------------------------------------------------------------------------------------
// Report.

/// The version of a package as resolved in this crate's lock file.
fn locked_version(package: &str) -> &'static str {
    let lock = include_str!("../Cargo.lock");
    let header = format!("name = \"{package}\"\nversion = \"");
    lock.find(&header)
        .map(|at| {
            let rest = &lock[at + header.len()..];
            &rest[..rest.find('"').unwrap_or(0)]
        })
        .unwrap_or("unknown")
}

fn details(opts: &Options) -> String {
    let (repeats, pyramid_repeats) = (opts.repeats(REPEATS), opts.repeats(PYRAMID_REPEATS));
    let ours = rigid::physics::World::default().settings;
    let solver = ours.solver;
    let sleep = ours.sleep;
    let p = theirs::parameters(None);
    let rayon_threads = std::env::var("RAYON_NUM_THREADS").unwrap_or_default();
    format!(
        "- Same bodies in both engines, built from one description in `peer/src/scenes.rs`; \
         dt = 1/{:.0} s, gravity {GRAVITY} m/s².\n\
         - rapier3d: crate `rapier3d-f64` {} (f64, as ours), default features (single-threaded: \
         no `parallel`), stepped through `PhysicsWorld::step`.\n\
         - Ours: `rigid` {}, f64, run with RAYON_NUM_THREADS={rayon_threads} so that both \
         engines use one core.\n\
         - Our settings (defaults): pipeline {:?}, {} substeps, contact {} Hz, damping ratio {}, \
         push-out at most {} m/s, no bounce below {} m/s, integrator {:?}; sleeping {} \
         (below {} m/s for {} s). A pair takes the smaller restitution and the geometric mean \
         of the frictions.\n\
         - rapier settings (`IntegrationParameters::default()` with dt): {} solver iterations \
         (substeps), {} internal PGS iteration(s), {} stabilization iteration(s), contacts \
         {} Hz / damping ratio {} ({} Hz against fixed bodies), warm start {}, friction model \
         {:?}, allowed linear error {} m, prediction distance {} m, max corrective velocity {} \
         m/s, CCD off (not enabled on any body); sleeping on (rapier's default thresholds: \
         0.05 m/s, 0.5 rad/s, for 0.5 s). Its default combine rule for both coefficients is \
         the average; every collider here is set to `{:?}` for restitution and `{:?}` for \
         friction, which is what ours does, so mixed pairs get the same coefficients. In the \
         C2, C4 and C6 cases both bodies have the same values, so any rule gives the same.\n\
         - Times: wall time of the steps only (not the building), ms per step, median of \
         {repeats} runs with the two engines taking turns ({pyramid_repeats} for the pyramid, \
         whose runs are short); the C cases run once each. Errors: \
         pyramid, the largest distance any box moved from its start; rain, bodies whose centre \
         left the bin (should be 0), the energy left at the end (kinetic + m g y above the \
         floor) over the energy at the start (no exact answer: it only must not exceed 1), and \
         the overlap of the bodies at the end, measured the same way for both (our signed \
         distance on the poses each engine reports; its deepest is the error compared); C \
         cases, signed relative error against the analytic answer. Ratios are ours / rapier's, \
         of times and of |errors|: above 1 means we are slower or less accurate.\n",
        1.0 / DT,
        locked_version("rapier3d-f64"),
        locked_version("rigid"),
        ours.pipeline,
        solver.substeps,
        solver.contact_hertz,
        solver.damping_ratio,
        solver.max_push_out,
        solver.restitution_threshold,
        ours.integrator,
        if sleep.enabled { "on" } else { "off" },
        sleep.sleep_speed,
        sleep.time_to_sleep,
        p.num_solver_iterations,
        p.num_internal_pgs_iterations,
        p.num_internal_stabilization_iterations,
        p.contact_softness.natural_frequency,
        p.contact_softness.damping_ratio,
        p.static_contact_softness.natural_frequency,
        p.warmstart_coefficient,
        p.friction_model,
        p.normalized_allowed_linear_error,
        p.normalized_prediction_distance,
        p.normalized_max_corrective_velocity,
        theirs::RESTITUTION_RULE,
        theirs::FRICTION_RULE,
    )
}

fn table(rows: &[Row]) -> String {
    let mut out = String::from(
        "| scene | ours ms/step | rapier ms/step | time ratio | our error | rapier error | error ratio |\n\
         |---|---|---|---|---|---|---|\n",
    );
    for row in rows {
        let error_ratio = row
            .error_ratio
            .map_or("—".to_owned(), |r| format!("{r:.2}"));
        out += &format!(
            "| {} | {:.4} | {:.4} | {:.2} | {} | {} | {} |\n",
            row.scene,
            row.ours_ms,
            row.theirs_ms,
            row.ours_ms / row.theirs_ms,
            row.ours_error,
            row.theirs_error,
            error_ratio,
        );
    }
    out
}

/// Plain sentences on where we lose and where we win, read off the rows.
fn notes(rows: &[Row]) -> String {
    let list = |pick: &dyn Fn(&Row) -> Option<f64>| {
        let items: Vec<String> = rows
            .iter()
            .filter_map(|row| pick(row).map(|r| format!("{} (×{r:.2})", row.scene)))
            .collect();
        if items.is_empty() {
            "none".to_owned()
        } else {
            items.join("; ")
        }
    };
    let time = |row: &Row| row.ours_ms / row.theirs_ms;
    // Timing noise on a shared machine is a few per cent: only a 5 % gap counts.
    let slower = list(&|row| Some(time(row)).filter(|&r| r > 1.05));
    let faster = list(&|row| Some(1.0 / time(row)).filter(|&r| r > 1.05));
    let worse = list(&|row| row.error_ratio.filter(|&r| r > 1.0));
    let better = list(&|row| row.error_ratio.filter(|&r| r < 1.0).map(|r| 1.0 / r));
    format!(
        "- We are slower (ours / rapier's time) on: {slower}.\n\
         - We are faster (rapier's / ours) on: {faster}.\n\
         - We are less accurate (our |error| / rapier's) on: {worse}.\n\
         - We are more accurate (rapier's |error| / ours) on: {better}.\n\
         - The C cases are two-body scenes: their times measure per-step overhead, not \
         contact solving at scale.\n"
    )
}

/// The old scenes (the report's first table and its sweeps), by name.
const OLD: &[&str] = &[
    "pyramid", "rain1000", "rain4000", "bounce", "slide", "roll", "sweeps",
];

const USAGE: &str = "\
Usage: peer-bench [--scene NAME]... [--steps N] [--long N] [--repeats N] [--stages] [--list]

  --scene NAME   run only these scenes (repeat it, or give a comma-separated list);
                 NAME is a scene, or `old`, `stress` or `all` (the default: every scene)
  --steps N      cut every scene to at most N steps (at least 2), for smoke runs
  --long N       run every scene N steps instead of its own (at least 2), to see what
                 stacks do after a benchmark's window; Box3D still runs its own steps
  --repeats N    timed runs of each engine per setting, instead of each scene's own
  --stages       instead of the side by side, our engine's stage profile on each chosen
                 stress scene, at our defaults and at 4 substeps
  --list         list the scenes and exit

Box3D's benchmark program also runs, on large_pyramid, many_pyramids and convex_pile, when
BOX3D_DIR names a Box3D checkout built with cmake (see peer/src/box3d.rs).";

/// The command line.
struct Options {
    /// The scenes to run, in the report's order.
    scenes: Vec<&'static str>,
    steps: Option<usize>,
    /// Steps every scene runs instead of its own (`--long`).
    long: Option<usize>,
    repeats: Option<usize>,
    /// Print our stage profile of the stress scenes instead (`--stages`).
    stages: bool,
}

impl Options {
    fn parse(args: impl Iterator<Item = String>) -> Result<Options, String> {
        let mut wanted: Vec<String> = Vec::new();
        let (mut steps, mut long, mut repeats) = (None, None, None);
        let mut stages = false;
        let mut args = args.peekable();
        let number = |flag: &str, value: Option<String>, least: usize| {
            value
                .as_deref()
                .and_then(|v| v.parse::<usize>().ok())
                .filter(|&n| n >= least)
                .ok_or(format!("{flag} needs a whole number of at least {least}"))
        };
        while let Some(arg) = args.next() {
            let (flag, inline) = match arg.split_once('=') {
                Some((flag, value)) => (flag.to_owned(), Some(value.to_owned())),
                None => (arg.clone(), None),
            };
            let mut value = || inline.clone().or_else(|| args.next());
            match flag.as_str() {
                "--scene" | "-s" => {
                    let list = value().ok_or("--scene needs a name")?;
                    wanted.extend(list.split(',').map(str::to_owned));
                }
                "--steps" => steps = Some(number("--steps", value(), 2)?),
                "--long" => long = Some(number("--long", value(), 2)?),
                "--repeats" => repeats = Some(number("--repeats", value(), 1)?),
                "--stages" => stages = true,
                "--list" => {
                    println!(
                        "old: {}\nstress: {}",
                        OLD.join(" "),
                        scenes::STRESS.join(" ")
                    );
                    std::process::exit(0);
                }
                "--help" | "-h" => {
                    println!("{USAGE}");
                    std::process::exit(0);
                }
                _ => return Err(format!("unknown argument `{arg}`\n\n{USAGE}")),
            }
        }
        if wanted.is_empty() {
            wanted.push("all".to_owned());
        }
        let all: Vec<&'static str> = OLD.iter().chain(scenes::STRESS).copied().collect();
        let mut chosen = Vec::new();
        for name in &wanted {
            let group: Vec<&'static str> = match name.as_str() {
                "all" => all.clone(),
                "old" => OLD.to_vec(),
                "stress" | "new" => scenes::STRESS.to_vec(),
                other => match all.iter().find(|&&n| n == other) {
                    Some(&n) => vec![n],
                    None => {
                        return Err(format!(
                            "no scene `{other}`: the scenes are {} (or old, stress, all)",
                            all.join(", ")
                        ));
                    }
                },
            };
            chosen.extend(group);
        }
        // The report's order, each once.
        let scenes = all.into_iter().filter(|n| chosen.contains(n)).collect();
        Ok(Options {
            scenes,
            steps,
            long,
            repeats,
            stages,
        })
    }

    fn has(&self, name: &str) -> bool {
        self.scenes.contains(&name)
    }

    /// `default` timed runs unless `--repeats` said otherwise.
    fn repeats(&self, default: usize) -> usize {
        self.repeats.unwrap_or(default)
    }

    /// The scene run `--long` steps instead of its own, then cut to `--steps` if that is
    /// fewer.
    fn cut(&self, scene: SceneDesc) -> SceneDesc {
        let own = self.long.unwrap_or(scene.steps);
        let steps = self.steps.map_or(own, |n| n.min(own));
        SceneDesc { steps, ..scene }
    }
}

fn main() {
    let opts = match Options::parse(std::env::args().skip(1)) {
        Ok(opts) => opts,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    // Our narrow phase spreads over rayon's threads; rapier here runs on one thread. Unless
    // told otherwise, ours gets one thread too, so the times compare like with like.
    if std::env::var_os("RAYON_NUM_THREADS").is_none() {
        // SAFETY: nothing else runs yet: no thread can read the environment meanwhile.
        unsafe { std::env::set_var("RAYON_NUM_THREADS", "1") };
    }
    if opts.stages {
        let names: Vec<&str> = scenes::STRESS
            .iter()
            .copied()
            .filter(|n| opts.has(n))
            .collect();
        println!("{}", stages::report(&names, &opts));
        return;
    }
    // Progress goes to stderr, so that stdout stays the Markdown section alone.
    let mut rows = Vec::new();
    if opts.has("pyramid") {
        eprintln!("pyramid…");
        rows.push(pyramid_row(&opts));
    }
    for (name, count) in [("rain1000", 1000), ("rain4000", 4000)] {
        if opts.has(name) {
            eprintln!("rain {count}…");
            rows.push(rain_row(count, &opts));
        }
    }
    if opts.has("bounce") {
        eprintln!("C2…");
        rows.extend(bounce_rows(&opts));
    }
    if opts.has("slide") {
        eprintln!("C4…");
        rows.push(slide_row(&opts));
    }
    if opts.has("roll") {
        eprintln!("C6…");
        rows.push(roll_row(&opts));
    }
    let sweeps = if opts.has("sweeps") {
        eprintln!("sweeps…");
        vec![
            sweep(
                "pyramid",
                &opts.cut(scenes::pyramid()),
                SweepError::Drift,
                SWEEP,
                opts.repeats(PYRAMID_REPEATS),
            ),
            sweep(
                "rain 1000",
                &opts.cut(scenes::rain(1000).0),
                SweepError::DeepestOverlap,
                SWEEP,
                opts.repeats(REPEATS),
            ),
            sweep(
                "rain 4000",
                &opts.cut(scenes::rain(4000).0),
                SweepError::DeepestOverlap,
                LARGE_SWEEP,
                opts.repeats(LARGE_REPEATS),
            ),
            sweep(
                "C6 rolling",
                &opts.cut(scenes::roll(ROLL_SPEED)),
                SweepError::RollingSpeed,
                SWEEP,
                opts.repeats(PYRAMID_REPEATS),
            ),
        ]
    } else {
        Vec::new()
    };
    let stress: Vec<&str> = scenes::STRESS
        .iter()
        .copied()
        .filter(|n| opts.has(n))
        .collect();
    let stress = (!stress.is_empty()).then(|| stress::report(&stress, &opts));

    println!("## Side by side with rapier3d\n");
    if let Some(n) = opts.steps {
        println!(
            "**Smoke run: every scene cut to at most {n} steps (`--steps`); these are not results.**\n"
        );
    }
    if let Some(n) = opts.long {
        println!("**Long run: every scene ran {n} steps (`--long`) instead of its own.**\n");
    }
    println!("{}", details(&opts));
    if !rows.is_empty() {
        println!("{}", table(&rows));
        println!("{}", notes(&rows));
    }
    if !sweeps.is_empty() {
        let (repeats, pyramid_repeats, large_repeats) = (
            opts.repeats(REPEATS),
            opts.repeats(PYRAMID_REPEATS),
            opts.repeats(LARGE_REPEATS),
        );
        println!("### Work against error over the substeps\n");
        println!(
            "Both engines over their substeps, in pairs taking turns as above ({repeats} runs \
             each, the pyramid and C6 {pyramid_repeats}; the rain of 4000 {large_repeats}, at one \
             pair of settings). Our spring stiffness \
             stays at its default, capped at a fifth of the substep rate. The errors are the \
             table's: the pyramid's worst drift, the rain's deepest overlap, C6's relative error \
             of the final speed.\n"
        );
        println!("{}", sweep_table(&sweeps));
        println!("{}", sweep_verdicts(&sweeps));
    }
    if let Some(stress) = stress {
        println!("{stress}");
    }
}
