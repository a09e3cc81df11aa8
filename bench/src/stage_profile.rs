//! Where a step's time goes, scene by scene: the mean of `World::stage_times` over the first
//! two simulated seconds of each built-in scene at its own dt.

use rigid::physics::StageTimes;
use rigid::scene;

const SECONDS: f64 = 2.0;

/// Mean stage times per step and the number of steps.
pub fn profile(name: &str) -> (StageTimes, usize) {
    let scene = scene::load(name).expect("built-in scene");
    let mut world = scene.build_world().expect("built-in scene builds");
    world.set_stage_timing(true);
    let steps = (SECONDS / scene.settings.dt).round() as usize;
    let mut sum = StageTimes::default();
    for _ in 0..steps {
        world.step(scene.settings.dt);
        sum += world.stage_times();
    }
    let mean = sum.scaled(1.0 / steps as f64);
    (mean, steps)
}
