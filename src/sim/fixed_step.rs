//! The fixed-dt clock both drivers share (the native thread and the browser's frame loop):
//! wall time, scaled by the time scale, fills an accumulator that is spent in steps of
//! exactly `dt`. Only how the driver waits between batches differs.

use std::panic::{self, AssertUnwindSafe};

use web_time::{Duration, Instant};

use crate::sim::simulation::Simulation;

/// Most steps taken in one batch: when the machine cannot keep up, simulated time slows
/// down instead of the loop falling further and further behind.
const MAX_STEPS_PER_BATCH: u32 = 64;

/// How long a driver may wait when there is nothing to step (paused or time scale 0).
pub const IDLE_WAIT: Duration = Duration::from_millis(50);

/// Turns wall time into a whole number of fixed steps; see the module.
pub struct FixedStepClock {
    accumulator: f64,
    last: Instant,
}

/// What one batch did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Batch {
    /// Fixed steps taken in the batch.
    pub steps: u32,
    /// A step panicked: the simulation is stopped with the message (see `guarded`).
    pub failed: bool,
}

impl FixedStepClock {
    /// A clock with nothing due, counting wall time from `now`.
    pub fn new(now: Instant) -> FixedStepClock {
        FixedStepClock {
            accumulator: 0.0,
            last: now,
        }
    }

    /// Takes the steps due for the wall time since the last call, spending at most
    /// `budget` of wall time on them (a driver must get back to its commands and frames).
    pub fn advance(&mut self, sim: &mut Simulation, budget: Duration) -> Batch {
        let now = Instant::now();
        let settings = *sim.settings();
        if settings.paused {
            self.accumulator = 0.0;
        } else {
            self.accumulator += (now - self.last).as_secs_f64() * settings.time_scale;
        }
        self.last = now;
        let mut batch = Batch {
            steps: 0,
            failed: false,
        };
        while self.accumulator >= settings.dt
            && batch.steps < MAX_STEPS_PER_BATCH
            && now.elapsed() < budget
        {
            if guarded(sim, Simulation::step).is_none() {
                batch.failed = true;
                break;
            }
            self.accumulator -= settings.dt;
            batch.steps += 1;
        }
        // Behind the wall clock: drop the backlog rather than chase it.
        if self.accumulator >= settings.dt {
            self.accumulator = 0.0;
        }
        batch
    }

    /// Wall time until the next step is due, at most `IDLE_WAIT`.
    pub fn wait_for_next_step(&self, sim: &Simulation) -> Duration {
        let s = sim.settings();
        if s.paused || s.time_scale <= 0.0 {
            return IDLE_WAIT;
        }
        let wall = (s.dt - self.accumulator).max(0.0) / s.time_scale;
        Duration::from_secs_f64(wall).min(IDLE_WAIT)
    }
}

/// Runs `work` on the simulation; a panic inside it stops the simulation with the panic's
/// message (shown by the viewer) instead of ending the driver, and gives `None`.
pub fn guarded<T>(sim: &mut Simulation, work: impl FnOnce(&mut Simulation) -> T) -> Option<T> {
    match panic::catch_unwind(AssertUnwindSafe(|| work(sim))) {
        Ok(value) => Some(value),
        Err(payload) => {
            let cause = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".to_string());
            sim.fail(&cause);
            None
        }
    }
}
