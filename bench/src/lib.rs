//! Benchmarks: run time against error on reference cases with analytic answers.
//!
//! Each case builds a world, runs it for a fixed simulated time at a given dt and integrator,
//! and returns the error against the analytic answer together with the wall time. Run with
//! `cargo run --release -p rigid-bench`.

pub mod contact_cases;
pub mod idle_bodies;
pub mod integrators;
pub mod scaling;
pub mod stage_profile;
pub mod stress;
pub mod svg_plot;

use std::time::Instant;

use glam::DVec3;

use rigid::physics::{BodyId, World};

/// The steps every work-precision sweep runs, s: 1/30 halved five times.
pub const DTS: [f64; 6] = [
    1.0 / 30.0,
    1.0 / 60.0,
    1.0 / 120.0,
    1.0 / 240.0,
    1.0 / 480.0,
    1.0 / 960.0,
];

/// One measured configuration of one case.
#[derive(Clone, Debug)]
pub struct Measurement {
    pub case: &'static str,
    pub config: String,
    pub dt: f64,
    pub error: f64,
    /// Median wall time per simulated second, in microseconds.
    pub micros_per_sim_second: f64,
}

/// Largest distance any of `bodies` moved from `start`, m.
pub fn worst_drift(world: &World, bodies: &[BodyId], start: &[DVec3]) -> f64 {
    bodies
        .iter()
        .zip(start)
        .map(|(&id, s)| world.body(id).position.distance(*s))
        .fold(0.0, f64::max)
}

/// Runs `work` `repeats` times and returns its result and the median wall time in seconds.
pub fn median_time<T>(repeats: usize, mut work: impl FnMut() -> T) -> (T, f64) {
    let mut times = Vec::with_capacity(repeats);
    let mut result = None;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        result = Some(work());
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    (result.expect("ran at least once"), times[times.len() / 2])
}

/// The items no other beats on both cost and error, cheapest first. `cost_error` gives an
/// item's (cost, error); lower is better in both.
pub fn pareto_front<T>(items: &[T], cost_error: impl Fn(&T) -> (f64, f64)) -> Vec<&T> {
    let dominates = |q: (f64, f64), p: (f64, f64)| q.0 <= p.0 && q.1 <= p.1 && q != p;
    let mut front: Vec<&T> = items
        .iter()
        .filter(|p| {
            !items
                .iter()
                .any(|q| dominates(cost_error(q), cost_error(p)))
        })
        .collect();
    front.sort_by(|a, b| cost_error(a).0.total_cmp(&cost_error(b).0));
    front
}

/// A Markdown table of measurements.
pub fn markdown_table(rows: &[Measurement], error_label: &str) -> String {
    // Norms are written |x|: escape the bars so they do not end table cells.
    let error_label = error_label.replace('|', "\\|");
    let mut out = format!(
        "| case | integrator | dt | {error_label} | µs per simulated s (median) |\n|---|---|---|---|---|\n"
    );
    for row in rows {
        out += &format!(
            "| {} | {} | 1/{:.0} | {:.3e} | {:.1} |\n",
            row.case,
            row.config,
            1.0 / row.dt,
            row.error,
            row.micros_per_sim_second
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pareto_front_keeps_what_nothing_beats_on_both_cheapest_first() {
        let points = [(4.0, 1.0), (2.0, 3.0), (3.0, 2.0), (1.0, 3.0), (2.0, 2.0)];
        let front = pareto_front(&points, |&p| p);
        assert_eq!(front, [&(1.0, 3.0), &(2.0, 2.0), &(4.0, 1.0)]);
    }
}
