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

/// Stage times summed over the timed steps.
#[derive(Default)]
struct Totals {
    broad_phase: f64,
    narrow_phase: f64,
    islands: f64,
    solve: f64,
    integrate: f64,
    checks: f64,
}

impl Totals {
    fn add(&mut self, t: StageTimes) {
        self.broad_phase += t.broad_phase;
        self.narrow_phase += t.narrow_phase;
        self.islands += t.islands;
        self.solve += t.solve;
        self.integrate += t.integrate;
        self.checks += t.checks;
    }

    /// Each stage and the whole, in ms per step over `steps` steps.
    fn per_step(&self, steps: usize) -> [f64; 7] {
        let stages = [
            self.broad_phase,
            self.narrow_phase,
            self.islands,
            self.solve,
            self.integrate,
            self.checks,
        ];
        let total: f64 = stages.iter().sum();
        let ms = |s: f64| s * 1e3 / steps as f64;
        [
            ms(stages[0]),
            ms(stages[1]),
            ms(stages[2]),
            ms(stages[3]),
            ms(stages[4]),
            ms(stages[5]),
            ms(total),
        ]
    }
}

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
            let mut totals = Totals::default();
            for _ in 1..scene.steps {
                ours.step();
                totals.add(ours.world().stage_times());
            }
            let awake = (0..scene.bodies.len())
                .filter(|&i| !scene.bodies[i].fixed && !ours.is_sleeping(i))
                .count();
            let ms = totals.per_step(scene.steps - 1);
            let cells: Vec<String> = ms.iter().map(|v| format!("{v:.3}")).collect();
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
