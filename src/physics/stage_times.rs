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
    /// The whole step, s.
    pub fn total(&self) -> f64 {
        self.broad_phase
            + self.narrow_phase
            + self.islands
            + self.solve
            + self.integrate
            + self.checks
    }

    /// Every stage times `factor` (a sum over steps into a mean, or seconds into ms).
    pub fn scaled(&self, factor: f64) -> StageTimes {
        StageTimes {
            broad_phase: self.broad_phase * factor,
            narrow_phase: self.narrow_phase * factor,
            islands: self.islands * factor,
            solve: self.solve * factor,
            integrate: self.integrate * factor,
            checks: self.checks * factor,
        }
    }
}

/// Stage by stage, to sum steps.
impl std::ops::AddAssign for StageTimes {
    fn add_assign(&mut self, other: StageTimes) {
        self.broad_phase += other.broad_phase;
        self.narrow_phase += other.narrow_phase;
        self.islands += other.islands;
        self.solve += other.solve;
        self.integrate += other.integrate;
        self.checks += other.checks;
    }
}

/// Runs `stage` and, when `on`, adds the wall time it took to `seconds`. Off by default in a
/// world: reading the clock at every stage costs a small scene a noticeable share of its
/// step.
#[inline(always)]
pub(crate) fn timed<R>(on: bool, seconds: &mut f64, stage: impl FnOnce() -> R) -> R {
    #[cfg(not(target_arch = "wasm32"))]
    if on {
        let start = Instant::now();
        let result = stage();
        *seconds += start.elapsed().as_secs_f64();
        return result;
    }
    let _ = (on, seconds);
    stage()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two steps summed and halved give their mean, stage by stage, and the total follows.
    #[test]
    fn summed_steps_scale_into_their_mean() {
        let step = |k: f64| StageTimes {
            broad_phase: k,
            narrow_phase: 2.0 * k,
            islands: 3.0 * k,
            solve: 4.0 * k,
            integrate: 5.0 * k,
            checks: 6.0 * k,
        };
        let mut sum = StageTimes::default();
        sum += step(1.0);
        sum += step(3.0);
        let mean = sum.scaled(0.5);
        assert_eq!(mean, step(2.0));
        assert_eq!(mean.total(), 21.0 * 2.0);
    }
}
