//! Where a step's time goes: wall time of each stage of the last step, for the viewer's
//! counters and the benchmark's stage profile, measured only while the world is asked to
//! (`World::set_stage_timing`). On the web (wasm32 without a clock in std) every time
//! reads 0.

#[cfg(not(target_arch = "wasm32"))]
use web_time::Instant;

/// Seconds spent in each stage of the last step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// Proxies and pair finding.
    pub broad_phase: f64,
    /// Contact manifolds of the pairs.
    pub narrow_phase: f64,
    /// Islands, sleeping and waking.
    pub islands: f64,
    /// Contact impulses (either pipeline); with `classic`, its forces and integration too,
    /// which its event loop interleaves with the impulses.
    pub solve: f64,
    /// Forces and integration of the awake bodies (with `soft`, summed over its substeps).
    pub integrate: f64,
    /// Checks for non-finite state, before and after.
    pub checks: f64,
}

impl StageTimes {
    pub fn total(&self) -> f64 {
        self.broad_phase
            + self.narrow_phase
            + self.islands
            + self.solve
            + self.integrate
            + self.checks
    }
}

/// Laps of a clock: each `lap` returns the seconds since the previous one, or 0 when the
/// clock was started off. A step reads the clock about five times per substep, which is
/// a quarter of a two-body step's time: it is read only when someone asked for the times.
pub struct Stopwatch {
    #[cfg(not(target_arch = "wasm32"))]
    last: Option<Instant>,
}

impl Stopwatch {
    /// A clock that runs when `on`, and otherwise reads 0 at every lap.
    #[cfg_attr(target_arch = "wasm32", allow(unused_variables))]
    pub fn start(on: bool) -> Self {
        Stopwatch {
            #[cfg(not(target_arch = "wasm32"))]
            last: on.then(Instant::now),
        }
    }

    #[cfg(not(target_arch = "wasm32"))]
    pub fn lap(&mut self) -> f64 {
        let Some(last) = &mut self.last else {
            return 0.0;
        };
        let now = Instant::now();
        let seconds = (now - *last).as_secs_f64();
        *last = now;
        seconds
    }

    #[cfg(target_arch = "wasm32")]
    pub fn lap(&mut self) -> f64 {
        0.0
    }
}
