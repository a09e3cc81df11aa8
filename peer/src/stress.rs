//! The stress scenes (`scenes::STRESS`): large stacks, piles and a grid of joints, four of
//! them Box3D's benchmarks. Each runs at both engines' defaults and at equal substeps (our 4
//! substeps against rapier's 4 solver iterations, its default, and Box3D's 4 substeps), the
//! engines taking turns, and reports the median ms per step with the same error figures
//! measured the same way for both engines.
//!
//! Times here leave out the first step, as Box3D's benchmark program does (the first step
//! builds the broad phase and every contact from scratch), so that all three engines time
//! the same steps.

use std::time::Instant;

use crate::box3d::{self, Box3d};
use crate::overlap::{Overlap, overlap};
use crate::scenes::{self, SceneDesc, Stress, StressKind};
use crate::{Engine, Options, median, ratio};

/// Builds the scene, takes its first step untimed, then times the rest. Returns the engine
/// as it ended and the ms per timed step.
fn run_timed<E: Engine>(scene: &SceneDesc, substeps: Option<u32>) -> (E, f64) {
    let built = Instant::now();
    let mut engine = E::build(scene, substeps);
    let first = Instant::now();
    engine.step();
    let start = Instant::now();
    for _ in 1..scene.steps {
        engine.step();
    }
    let ms = start.elapsed().as_secs_f64() * 1e3 / (scene.steps - 1) as f64;
    eprintln!(
        "    {}: built in {:.0} ms, first step {:.1} ms, then {ms:.3} ms/step",
        E::NAME,
        (first - built).as_secs_f64() * 1e3,
        (start - first).as_secs_f64() * 1e3
    );
    (engine, ms)
}

/// The larger of two errors, NaN if either is (which `f64::max` would hide).
fn worst(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// The largest separation of any joint's two anchors where the run ended, each carried by
/// its body as the engine reports the body's pose: None for a scene without joints.
fn separation<E: Engine>(engine: &E, scene: &SceneDesc) -> Option<f64> {
    let anchor = |joint: &scenes::JointDesc, i: usize| {
        engine.position(i) + engine.orientation(i) * joint.local_anchor(&scene.bodies, i)
    };
    let gaps = scene
        .joints
        .iter()
        .map(|j| anchor(j, j.a).distance(anchor(j, j.b)));
    (!scene.joints.is_empty()).then(|| gaps.fold(0.0, worst))
}

/// What one engine's run of a stress scene came to.
struct Figures {
    /// Stacks: the largest distance any box moved from its start, m.
    drift: Option<f64>,
    /// Stacks with an apex: its final sideways (x, z) displacement, m.
    apex_sideways: Option<f64>,
    /// Smash: boxes (every dynamic body but the ball) that moved more than 0.5 m.
    knocked: Option<usize>,
    /// Scenes with joints: the largest distance between a joint's anchor on one body and its
    /// anchor on the other, m.
    separation: Option<f64>,
    overlap: Overlap,
    /// Bodies that left the scene's region or whose position is not finite.
    lost: usize,
    /// Dynamic bodies not asleep at the end.
    awake: usize,
    dynamic: usize,
}

fn figures<E: Engine>(engine: &E, stress: &Stress) -> Figures {
    let scene = &stress.scene;
    let dynamic: Vec<usize> = (0..scene.bodies.len())
        .filter(|&i| !scene.bodies[i].fixed)
        .collect();
    let moved = |i: usize| engine.position(i).distance(scene.bodies[i].position);
    let (mut drift, mut apex_sideways, mut knocked) = (None, None, None);
    match stress.kind {
        StressKind::Stack { apex } => {
            drift = Some(dynamic.iter().map(|&i| moved(i)).fold(0.0, worst));
            apex_sideways = apex.map(|i| {
                let d = engine.position(i) - scene.bodies[i].position;
                d.x.hypot(d.z)
            });
        }
        StressKind::Smash { ball } => {
            knocked = Some(
                dynamic
                    .iter()
                    .filter(|&&i| i != ball && (moved(i).is_nan() || moved(i) > 0.5))
                    .count(),
            );
        }
        StressKind::Pile => {}
    }
    let measured = Instant::now();
    let overlap = overlap(engine, scene);
    eprintln!(
        "    {}: overlap measured in {:.2} s",
        E::NAME,
        measured.elapsed().as_secs_f64()
    );
    Figures {
        drift,
        apex_sideways,
        knocked,
        separation: separation(engine, scene),
        overlap,
        lost: dynamic
            .iter()
            .filter(|&&i| !stress.region.holds(engine.position(i)))
            .count(),
        awake: dynamic.iter().filter(|&&i| !engine.is_sleeping(i)).count(),
        dynamic: dynamic.len(),
    }
}

impl Figures {
    fn cell(&self) -> String {
        let mut parts = Vec::new();
        if let Some(drift) = self.drift {
            parts.push(format!("drift {:.1} mm", drift * 1e3));
        }
        if let Some(apex) = self.apex_sideways {
            parts.push(format!("apex sideways {:.1} mm", apex * 1e3));
        }
        if let Some(knocked) = self.knocked {
            parts.push(format!("{knocked} boxes moved > 0.5 m"));
        }
        if let Some(separation) = self.separation {
            parts.push(format!("joint separation max {:.2} mm", separation * 1e3));
        }
        parts.push(format!(
            "overlap deepest {:.1} mm, mean {:.2} mm ({} pairs)",
            self.overlap.deepest * 1e3,
            self.overlap.mean * 1e3,
            self.overlap.pairs
        ));
        parts.push(format!("{} lost", self.lost));
        parts.push(format!("{}/{} awake", self.awake, self.dynamic));
        parts.join(", ")
    }

    /// The error the ratio column compares: the joints' separation where there are joints,
    /// else a stack's drift, else the deepest overlap.
    fn error(&self) -> f64 {
        self.separation
            .or(self.drift)
            .unwrap_or(self.overlap.deepest)
    }
}

/// Box3D's times for one scene: the median ms per step over its runs, or why there is none.
enum Box3dTime {
    /// Not one of Box3D's scenes.
    NotItsScene,
    NotRun,
    Failed(String),
    Ran {
        ms: f64,
        steps: usize,
        runs: usize,
        counters: String,
    },
}

struct StressRow {
    title: String,
    steps: usize,
    sleeping: bool,
    setting: String,
    ours_ms: f64,
    theirs_ms: f64,
    ours: Figures,
    theirs: Figures,
}

/// The two settings each scene runs at: (label, our substeps, rapier's iterations, whether
/// Box3D takes turns in it). Box3D's benchmark program always runs 4 substeps, so it runs in
/// the equal-substeps pass.
pub(crate) fn settings() -> [(String, Option<u32>, Option<u32>, bool); 2] {
    let ours_default = rigid::physics::World::default().settings.solver.substeps;
    let theirs_default = crate::theirs::parameters(None).num_solver_iterations;
    [
        (
            format!("defaults (ours {ours_default} substeps, rapier {theirs_default} iterations)"),
            None,
            None,
            false,
        ),
        (
            "equal: 4 substeps (ours 4, rapier 4 iterations, Box3D 4)".to_owned(),
            Some(4),
            Some(4),
            true,
        ),
    ]
}

/// Runs one stress scene at both settings. Returns its rows and Box3D's time.
fn run_scene(stress: &Stress, opts: &Options, box3d: &Box3d) -> (Vec<StressRow>, Box3dTime) {
    let scene = &stress.scene;
    let repeats = opts.repeats(stress.repeats);
    let mut rows = Vec::new();
    let mut box3d_times = Vec::new();
    let mut box3d_steps = 0;
    let mut box3d_counters = String::new();
    let mut box3d_error = None;
    for (setting, ours_substeps, theirs_iterations, with_box3d) in settings() {
        let (mut ours_times, mut theirs_times) = (Vec::new(), Vec::new());
        let (mut ours_last, mut theirs_last) = (None, None);
        for repeat in 0..repeats {
            eprintln!(
                "  {} — {setting}: run {}/{repeats}",
                stress.name,
                repeat + 1
            );
            let (engine, ms) = run_timed::<crate::ours::Ours>(scene, ours_substeps);
            ours_times.push(ms);
            ours_last = Some(engine);
            let (engine, ms) = run_timed::<crate::theirs::Theirs>(scene, theirs_iterations);
            theirs_times.push(ms);
            theirs_last = Some(engine);
            if let (true, Some(name), Box3d::Ready(exe), None) =
                (with_box3d, stress.box3d, box3d, &box3d_error)
            {
                match box3d::run(exe, name) {
                    Ok(run) => {
                        eprintln!(
                            "    Box3D {name}: {:.4} ms/step over {} steps",
                            run.ms_per_step,
                            run.steps - 1
                        );
                        box3d_times.push(run.ms_per_step);
                        box3d_steps = run.steps;
                        box3d_counters = run.counters;
                    }
                    Err(e) => box3d_error = Some(e),
                }
            }
        }
        let (ours, theirs) = (ours_last.expect("ran"), theirs_last.expect("ran"));
        rows.push(StressRow {
            title: stress.title.clone(),
            steps: scene.steps,
            sleeping: scene.sleeping,
            setting,
            ours_ms: median(ours_times),
            theirs_ms: median(theirs_times),
            ours: figures(&ours, stress),
            theirs: figures(&theirs, stress),
        });
    }
    let box3d_time = match (stress.box3d, box3d, box3d_error) {
        (None, _, _) => Box3dTime::NotItsScene,
        (Some(_), _, Some(e)) => Box3dTime::Failed(e),
        (Some(_), Box3d::Ready(_), None) => Box3dTime::Ran {
            runs: box3d_times.len(),
            ms: median(box3d_times),
            steps: box3d_steps,
            counters: box3d_counters,
        },
        (Some(_), Box3d::Missing(e), None) => Box3dTime::Failed(e.clone()),
        (Some(_), Box3d::NotSet, None) => Box3dTime::NotRun,
    };
    (rows, box3d_time)
}

/// The section of the report on the stress scenes in `names`.
pub fn report(names: &[&str], opts: &Options) -> String {
    let box3d = Box3d::locate();
    let mut table = String::from(
        "| scene | steps, sleeping | setting | ours ms/step | rapier ms/step | ours / rapier | \
         Box3D ms/step | ours / Box3D | our figures | rapier figures | error ratio |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut box3d_notes = Vec::new();
    let mut repeats_used = Vec::new();
    for name in names {
        let mut stress = scenes::stress(name).expect("a stress scene's name");
        repeats_used.push(format!("{name} {}", stress.repeats));
        stress.scene = opts.cut(stress.scene);
        eprintln!("{name}…");
        let (rows, box3d_time) = run_scene(&stress, opts, &box3d);
        for row in rows {
            let (box3d_cell, box3d_ratio) = match &box3d_time {
                Box3dTime::NotItsScene => ("—".to_owned(), "—".to_owned()),
                Box3dTime::NotRun => ("not run".to_owned(), "—".to_owned()),
                Box3dTime::Failed(_) => ("failed".to_owned(), "—".to_owned()),
                Box3dTime::Ran { ms, steps, .. } => {
                    let cell = if *steps == row.steps {
                        format!("{ms:.4}")
                    } else {
                        format!("{ms:.4} (its {steps} steps)")
                    };
                    (cell, format!("{:.2}", row.ours_ms / ms))
                }
            };
            let error_ratio = ratio(row.ours.error(), row.theirs.error())
                .filter(|r| r.is_finite())
                .map_or("—".to_owned(), |r| format!("{r:.2}"));
            table += &format!(
                "| {} | {}, sleeping {} | {} | {:.4} | {:.4} | {:.2} | {box3d_cell} | {box3d_ratio} \
                 | {} | {} | {error_ratio} |\n",
                row.title,
                row.steps,
                if row.sleeping { "on" } else { "off" },
                row.setting,
                row.ours_ms,
                row.theirs_ms,
                row.ours_ms / row.theirs_ms,
                row.ours.cell(),
                row.theirs.cell(),
            );
        }
        match box3d_time {
            Box3dTime::NotItsScene => {}
            Box3dTime::NotRun => {}
            Box3dTime::Failed(e) => box3d_notes.push(format!("- Box3D on {name} failed: {e}")),
            Box3dTime::Ran {
                ms,
                steps,
                runs,
                counters,
            } => {
                let mut note = format!(
                    "- Box3D on {name}: {ms:.4} ms/step, median of {runs} run(s) of its {steps} \
                     steps (the first untimed); it reported `{counters}`."
                );
                if steps != stress.scene.steps {
                    note += &format!(
                        " Our engines ran {} steps here (`--steps` or `--long`), Box3D its own \
                         {steps}: the ratio is not like for like.",
                        stress.scene.steps
                    );
                }
                box3d_notes.push(note);
            }
        }
    }
    let box3d_line = match &box3d {
        Box3d::NotSet => format!(
            "- **Box3D was not run** (BOX3D_DIR is not set): to compare with it, {}.",
            box3d::HOW_TO_ENABLE
        ),
        Box3d::Missing(e) => format!("- **Box3D was not run**: {e}; {}.", box3d::HOW_TO_ENABLE),
        Box3d::Ready(exe) => format!(
            "- Box3D: its benchmark program `{}`, run as `-t=1 -b=<scene> -r=1` (one thread, \
             one run per call) in turn with our engines' runs at equal substeps; its default \
             build: f32, 4-wide SIMD (SSE2 on x86-64), continuous collision on; dt 1/60, 4 \
             substeps, gravity 10 m/s² (ours and rapier 9.81), its own material defaults \
             (friction 0.6, no restitution), which the scenes here copy.",
            exe.display()
        ),
    };
    box3d_notes.insert(0, box3d_line);
    let repeats = match opts.repeats {
        Some(n) => format!("{n} runs of each engine at each setting, from `--repeats`"),
        None => repeats_used.join(", "),
    };
    let smoke = match opts.steps {
        Some(n) => format!(
            "\n**Smoke run: every scene cut to at most {n} steps (`--steps`); these are not \
             results.**\n"
        ),
        None => String::new(),
    };
    format!(
        "### Stress scenes\n{smoke}\n\
         Large stacks, piles and a grid of joints, four of them Box3D's benchmarks \
         (`shared/benchmarks.c` of erincatto/box3d: `large_pyramid`, `many_pyramids`, \
         `convex_pile`, `joint_grid`, rebuilt from its description in `peer/src/scenes.rs`; \
         joints are ball joints, ours and rapier's impulse joints at its defaults with contacts \
         between the joined bodies off, as ours), each at both engines' defaults and at equal \
         substeps. Times: ms per step over all steps but the first (as Box3D's program times \
         them), median of the runs with the engines taking turns ({repeats}). \
         Figures, measured the same way for both engines on the poses each reports: drift, \
         the largest distance any box moved from its start (stacks; `large_pyramid` and \
         pyramid20 also the apex box's final sideways displacement); the joint separation, the \
         largest distance at the end between a joint's anchor carried by one body and by the \
         other (scenes with joints); the overlap at the end (as in the rain rows, leaving out \
         joined pairs); bodies lost (centre outside the scene's region, i.e. off the \
         floor or more than 1 m below its top, out of the bin for hull_rain, more than 10 m out \
         of the box of the start for joint_grid, or not finite); \
         and the dynamic bodies awake at the end. The error ratio is ours / rapier's, of the \
         joint separation where there are joints, of the drift for stacks and of the deepest \
         overlap otherwise. Sleeping is as each row says, \
         with each engine's own thresholds; with it off, no body of either engine sleeps.\n\n\
         {}\n\n{table}",
        box3d_notes.join("\n")
    )
}
