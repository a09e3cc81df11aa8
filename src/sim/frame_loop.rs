//! The simulation driven by the page's animation frames, for the browser, where the main
//! thread must never block and there is no thread to give the physics. It has the interface
//! of `SimHandle` (commands in, newest snapshot out) and the same fixed-dt clock; the viewer
//! calls `pump` once a frame, which applies the queued commands and takes the steps due.

use std::cell::RefCell;
use std::sync::Arc;

use web_time::{Duration, Instant};

use crate::sim::command::Command;
use crate::sim::fixed_step::{FixedStepClock, guarded};
use crate::sim::simulation::Simulation;
use crate::sim::snapshot::Snapshot;

/// Most wall time one frame spends stepping: the rest of a 60 Hz frame is left for drawing,
/// so a heavy scene slows simulated time down instead of freezing the page.
const FRAME_STEP_BUDGET: Duration = Duration::from_millis(10);

/// The browser's driver: the simulation and its clock, stepped by `pump` on the page's thread.
pub struct FrameLoop {
    state: RefCell<State>,
    inbox: RefCell<Vec<Command>>,
}

struct State {
    sim: Simulation,
    clock: FixedStepClock,
    latest: Arc<Snapshot>,
    /// A `Quit` was applied: nothing steps any more.
    stopped: bool,
}

impl FrameLoop {
    /// Takes over the simulation; nothing steps until the first `pump`. Never fails: the
    /// `Result` matches `SimHandle::start`.
    pub fn start(sim: Simulation) -> Result<FrameLoop, String> {
        let now = Instant::now();
        let latest = Arc::new(sim.snapshot(now));
        Ok(FrameLoop {
            state: RefCell::new(State {
                sim,
                clock: FixedStepClock::new(now),
                latest,
                stopped: false,
            }),
            inbox: RefCell::new(Vec::new()),
        })
    }

    /// Queues a command for the next `pump`.
    pub fn send(&self, command: Command) {
        self.inbox.borrow_mut().push(command);
    }

    /// The newest snapshot; always `Some`.
    pub fn latest(&self) -> Option<Arc<Snapshot>> {
        Some(self.state.borrow().latest.clone())
    }

    /// Applies the queued commands, takes the steps due since the last pump and publishes a
    /// snapshot if anything changed.
    pub fn pump(&self) {
        let commands = std::mem::take(&mut *self.inbox.borrow_mut());
        let mut state = self.state.borrow_mut();
        if state.stopped {
            return;
        }
        let changed = !commands.is_empty();
        for command in commands {
            if guarded(&mut state.sim, |sim| sim.apply(command)) == Some(false) {
                state.stopped = true;
                return;
            }
        }
        let State { sim, clock, .. } = &mut *state;
        let batch = clock.advance(sim, FRAME_STEP_BUDGET);
        if batch.steps > 0 || batch.failed || changed {
            state.latest = Arc::new(state.sim.snapshot(Instant::now()));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pump_for(sim: &FrameLoop, wall: Duration) {
        let end = Instant::now() + wall;
        while Instant::now() < end {
            sim.pump();
            std::thread::sleep(Duration::from_millis(4));
        }
    }

    #[test]
    fn frames_step_at_fixed_dt_with_the_wall_clock() {
        let sim = FrameLoop::start(Simulation::new("falling_box").unwrap()).unwrap();
        sim.send(Command::SetDt(0.004));
        let started = Instant::now();
        pump_for(&sim, Duration::from_millis(300));
        let wall = started.elapsed().as_secs_f64();
        let c = sim.latest().unwrap().counters;
        assert!((c.sim_time - c.steps as f64 * 0.004).abs() < 1e-9, "{c:?}");
        assert!(
            c.sim_time > 0.5 * wall && c.sim_time <= wall + 0.01,
            "{c:?} wall {wall}"
        );
    }

    #[test]
    fn commands_wait_for_the_next_pump() {
        let sim = FrameLoop::start(Simulation::new("falling_box").unwrap()).unwrap();
        sim.send(Command::SetPaused(true));
        assert!(
            !sim.latest().unwrap().settings.paused,
            "applied before a pump"
        );
        sim.pump();
        let paused = sim.latest().unwrap();
        assert!(paused.settings.paused);
        pump_for(&sim, Duration::from_millis(50));
        assert_eq!(sim.latest().unwrap().counters.steps, paused.counters.steps);
        sim.send(Command::StepOnce);
        sim.pump();
        assert_eq!(
            sim.latest().unwrap().counters.steps,
            paused.counters.steps + 1
        );
    }

    #[test]
    fn quit_stops_stepping() {
        let sim = FrameLoop::start(Simulation::new("falling_box").unwrap()).unwrap();
        sim.send(Command::Quit);
        sim.pump();
        let steps = sim.latest().unwrap().counters.steps;
        pump_for(&sim, Duration::from_millis(50));
        assert_eq!(sim.latest().unwrap().counters.steps, steps);
    }
}
