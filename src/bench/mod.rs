//! Benchmarks: run time against error on reference cases with analytic answers.
//!
//! Each case builds a world, runs it for a fixed simulated time at a given dt and integrator,
//! and returns the error against the analytic answer together with the wall time. Run with
//! `cargo run --release --bin bench`.

pub mod contact_cases;
pub mod idle_bodies;
pub mod integrators;
pub mod rain;
pub mod scaling;
pub mod stage_profile;
pub mod stress;
pub mod svg_plot;

use std::time::Instant;

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

/// A Markdown table of measurements.
pub fn markdown_table(rows: &[Measurement], error_label: &str) -> String {
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
