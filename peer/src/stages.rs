//! `--stages`: where our step's time goes on each stress scene, stage by stage, at our
//! defaults and at 4 substeps: the profile the side by side's missed targets are explained
//! by. One run per setting, with the world's stage timing on (`World::set_stage_timing`),
//! which reads the clock around each stage; the first step is left out, as in the timed
//! rows.

use rigid::physics::StageTimes;

use crate::Engine;
use crate::Options;
use crate::ours::Ours;
use crate::scenes;

/// The stage profile of the stress scenes in `names`, as a Markdown section.
pub fn report(names: &[&str], opts: &Options) -> String {
    let mut table = String::from(
        "| scene, sleeping | substeps | awake at end | broad phase | narrow phase | islands | \
         solve | integrate | checks | step |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for name in names {
        let stress = scenes::stress(name).expect("a stress scene's name");
        let scene = opts.cut(stress.scene);
        for substeps in [None, Some(4)] {
            eprintln!("{name}, substeps {substeps:?}: stage profile…");
            let mut ours = Ours::build(&scene, substeps);
            ours.world_mut().set_stage_timing(true);
            ours.step();
            let mut sum = StageTimes::default();
            for _ in 1..scene.steps {
                ours.step();
                sum += ours.world().stage_times();
            }
            let awake = (0..scene.bodies.len())
                .filter(|&i| !scene.bodies[i].fixed && !ours.is_sleeping(i))
                .count();
            let ms = sum.scaled(1e3 / (scene.steps - 1) as f64);
            let stages = [
                ms.broad_phase,
                ms.narrow_phase,
                ms.islands,
                ms.solve,
                ms.integrate,
                ms.checks,
                ms.total(),
            ];
            let cells: Vec<String> = stages.iter().map(|v| format!("{v:.3}")).collect();
            let substeps =
                substeps.unwrap_or(rigid::physics::World::default().settings.solver.substeps);
            let sleeping = if scene.sleeping { "on" } else { "off" };
            table.push_str(&format!(
                "| {name}, {sleeping} | {substeps} | {awake} | {} |\n",
                cells.join(" | ")
            ));
        }
    }
    format!(
        "### Where our step's time goes\n\n\
         Our engine alone, one run per setting, ms per step over every step but the first, \
         with the world's stage timing on (it reads the clock around each stage). Sleeping \
         as each scene sets it; awake dynamic bodies at the end.\n\n{table}"
    )
}
