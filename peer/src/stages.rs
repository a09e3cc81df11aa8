//! `--stages`: where our step's time goes on each stress scene, stage by stage, at our
//! defaults and at 4 substeps: the profile the side by side's missed targets are explained
//! by. One run per setting, with the world's stage timing on (`World::set_stage_timing`),
//! which reads the clock around each stage; the first step is left out, as in the timed
//! rows. A second table splits each run into windows of `WINDOW` steps: a pile's cost
//! grows as it gathers. With `BOX3D_DIR` set (see `box3d`), Box3D's benchmark program runs
//! each of its scenes once more with its own profile per step on (`-s`), and that table
//! gives its windows too.

use std::ops::Range;

use rigid::physics::StageTimes;

use crate::Engine;
use crate::Options;
use crate::box3d::{self, Box3d, StepProfile};
use crate::ours::Ours;
use crate::scenes;
use crate::stress;

/// Steps per row of the table by window.
const WINDOW: usize = 100;

/// One run's stage times: over the whole run and per window, ms per step, with the awake
/// dynamic bodies at the end of each.
struct Profile {
    whole: (StageTimes, usize),
    windows: Vec<(Range<usize>, StageTimes, usize)>,
}

/// The stage profile of the stress scenes in `names`, as a Markdown section.
pub fn report(names: &[&str], opts: &Options) -> String {
    let mut table = String::from(
        "| scene, sleeping | substeps | awake at end | broad phase | narrow phase | islands | \
         solve | integrate | checks | step |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut by_window = String::from(
        "| scene, sleeping | substeps | steps | awake at end | broad phase | narrow phase | \
         solve | integrate | step |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    let box3d = Box3d::locate();
    for name in names {
        let stress = scenes::stress(name).expect("a stress scene's name");
        let scene = opts.cut(stress.scene);
        let sleeping = if scene.sleeping { "on" } else { "off" };
        for (_, substeps, _, _) in stress::settings() {
            eprintln!("{name}, substeps {substeps:?}: stage profile…");
            let profile = profile(&scene, substeps);
            let substeps =
                substeps.unwrap_or(rigid::physics::World::default().settings.solver.substeps);
            let (ms, awake) = profile.whole;
            let stages = [
                ms.broad_phase,
                ms.narrow_phase,
                ms.islands,
                ms.solve,
                ms.integrate,
                ms.checks,
                ms.total(),
            ];
            table.push_str(&format!(
                "| {name}, {sleeping} | {substeps} | {awake} | {} |\n",
                cells(&stages)
            ));
            for (steps, ms, awake) in profile.windows {
                let stages = [
                    ms.broad_phase,
                    ms.narrow_phase,
                    ms.solve,
                    ms.integrate,
                    ms.total(),
                ];
                by_window.push_str(&format!(
                    "| {name}, {sleeping} | {substeps} | {}–{} | {awake} | {} |\n",
                    steps.start,
                    steps.end - 1,
                    cells(&stages)
                ));
            }
        }
        if let (Some(theirs), Box3d::Ready(exe)) = (stress.box3d, &box3d) {
            eprintln!("{name}: Box3D's profile…");
            match box3d::profile(exe, theirs) {
                Ok(steps) => by_window.push_str(&box3d_windows(name, &steps)),
                Err(e) => eprintln!("    Box3D's profile of {name} left out: {e}"),
            }
        }
    }
    format!(
        "### Where our step's time goes\n\n\
         Our engine alone, one run per setting, ms per step over every step but the first, \
         with the world's stage timing on (it reads the clock around each stage). Sleeping \
         as each scene sets it; awake dynamic bodies at the end.\n\n{table}\n\
         By window of {WINDOW} steps (the first window leaves out step 0), from the same \
         runs. Box3D's rows, where it ran, are its own profile of one more run of its \
         program (`-s`, 4 substeps, its own step count): its pairs' update as the broad \
         phase, its collide stage as the narrow phase, and its solver stage, which \
         integrates the bodies too, as the solve.\n\n{by_window}"
    )
}

/// Box3D's profile of scene `name` as rows of the table by window.
fn box3d_windows(name: &str, steps: &[StepProfile]) -> String {
    let mut rows = String::new();
    for range in windows(steps.len()) {
        let window = &steps[range.clone()];
        let mean = |part: fn(&StepProfile) -> f64| {
            window.iter().map(part).sum::<f64>() / window.len() as f64
        };
        let stages = [
            mean(|p| p.pairs),
            mean(|p| p.collide),
            mean(|p| p.constraints),
        ];
        rows.push_str(&format!(
            "| {name}, Box3D | 4 | {}–{} | | {} | | {:.3} |\n",
            range.start,
            range.end - 1,
            cells(&stages),
            mean(|p| p.step)
        ));
    }
    rows
}

/// The windows of a run of `steps` steps, for ours and Box3D's alike: step 0 (untimed in
/// Box3D's program, left out in ours) is in none; then up to each multiple of `WINDOW`,
/// the last cut at the run's end.
fn windows(steps: usize) -> impl Iterator<Item = Range<usize>> {
    let starts = std::iter::once(1).chain((WINDOW..steps).step_by(WINDOW));
    starts
        .map(move |start| start..((start / WINDOW + 1) * WINDOW).min(steps))
        .filter(|range| !range.is_empty())
}

fn cells(values: &[f64]) -> String {
    let cells: Vec<String> = values.iter().map(|v| format!("{v:.3}")).collect();
    cells.join(" | ")
}

/// Runs `scene` with the stage timing on, at our defaults or at `substeps`.
fn profile(scene: &scenes::SceneDesc, substeps: Option<u32>) -> Profile {
    let mut ours = Ours::build(scene, substeps);
    ours.world_mut().set_stage_timing(true);
    ours.step();
    let awake = |ours: &Ours| {
        (0..scene.bodies.len())
            .filter(|&i| !scene.bodies[i].fixed && !ours.is_sleeping(i))
            .count()
    };
    let (mut sum, mut by_window) = (StageTimes::default(), Vec::new());
    for range in windows(scene.steps) {
        let mut window = StageTimes::default();
        for _ in range.clone() {
            ours.step();
            window += ours.world().stage_times();
        }
        sum += window;
        let per_step = window.scaled(1e3 / range.len() as f64);
        by_window.push((range, per_step, awake(&ours)));
    }
    Profile {
        whole: (sum.scaled(1e3 / (scene.steps - 1) as f64), awake(&ours)),
        windows: by_window,
    }
}
