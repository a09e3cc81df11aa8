//! Step time against body count for each broad phase, on the rain workload (`rain`). The
//! clock runs over steps 30 to 90 (0.5 to 1.5 s at 1/60 s): the bodies are falling, landing
//! and piling up, all awake, so this is the busiest part of the run.

use std::time::Instant;

use rigid::physics::BroadPhaseKind;
use rigid::scene::rain_world;

pub const COUNTS: [usize; 7] = [100, 500, 1000, 2000, 5000, 10_000, 20_000];
/// Brute force is O(n²): beyond this it takes minutes per count.
pub const BRUTE_FORCE_LIMIT: usize = 5000;
const DT: f64 = 1.0 / 60.0;
const WARM_UP: usize = 30;
const TIMED: usize = 60;

pub const KINDS: [(&str, BroadPhaseKind); 3] = [
    ("sweep and prune", BroadPhaseKind::SweepAndPrune),
    (
        "uniform grid",
        BroadPhaseKind::UniformGrid { cell_size: 0.5 },
    ),
    ("brute force", BroadPhaseKind::BruteForce),
];

/// Median wall time of one step, s.
pub fn step_time(count: usize, kind: BroadPhaseKind) -> f64 {
    let mut world = rain_world(count, kind);
    for _ in 0..WARM_UP {
        world.step(DT);
    }
    let mut times: Vec<f64> = (0..TIMED)
        .map(|_| {
            let start = Instant::now();
            world.step(DT);
            start.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}
