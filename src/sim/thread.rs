//! The simulation thread: the fixed-dt clock (`fixed_step`) on a thread of its own. It
//! sleeps on the command queue until the next step is due, so commands are applied at once;
//! a snapshot is published after each batch.

use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use web_time::{Duration, Instant};

use crate::sim::command::Command;
use crate::sim::fixed_step::{FixedStepClock, guarded};
use crate::sim::simulation::Simulation;
use crate::sim::snapshot::Snapshot;

/// Most wall time spent stepping before commands are read and a snapshot is published: with
/// thousands of awake bodies a step can take tens of milliseconds, and the viewer must still
/// see its commands (pause, reset) applied at once.
const MAX_BATCH_WALL_TIME: Duration = Duration::from_millis(50);

/// The newest snapshot, replaced by each publish (latest wins; nobody queues old ones).
pub type SnapshotSlot = Arc<Mutex<Option<Arc<Snapshot>>>>;

/// The viewer's end of the simulation thread. Dropping it stops the thread.
pub struct SimHandle {
    commands: Sender<Command>,
    latest: SnapshotSlot,
    thread: Option<JoinHandle<()>>,
}

impl SimHandle {
    /// Builds the scene (errors are returned here, not on the thread) and starts stepping.
    pub fn spawn(scene: &str) -> Result<SimHandle, String> {
        SimHandle::start(Simulation::new(scene)?)
    }

    /// Starts stepping a simulation on its own thread.
    pub fn start(sim: Simulation) -> Result<SimHandle, String> {
        let (commands, inbox) = mpsc::channel();
        let latest: SnapshotSlot =
            Arc::new(Mutex::new(Some(Arc::new(sim.snapshot(Instant::now())))));
        let slot = latest.clone();
        let thread = std::thread::Builder::new()
            .name("simulation".into())
            .spawn(move || run(sim, inbox, slot))
            .map_err(|e| e.to_string())?;
        Ok(SimHandle {
            commands,
            latest,
            thread: Some(thread),
        })
    }

    /// Queues a command; ignored if the thread has ended.
    pub fn send(&self, command: Command) {
        let _ = self.commands.send(command);
    }

    /// The newest published snapshot; `None` only if a thread panicked holding its lock.
    pub fn latest(&self) -> Option<Arc<Snapshot>> {
        self.latest.lock().ok().and_then(|slot| slot.clone())
    }

    /// Nothing to do: the thread steps on its own. (The browser's `FrameLoop` steps here.)
    pub fn pump(&self) {}
}

impl Drop for SimHandle {
    fn drop(&mut self) {
        self.send(Command::Quit);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

fn run(mut sim: Simulation, inbox: Receiver<Command>, slot: SnapshotSlot) {
    let mut clock = FixedStepClock::new(Instant::now());
    loop {
        let mut changed = false;
        match inbox.recv_timeout(clock.wait_for_next_step(&sim)) {
            Ok(command) => {
                if guarded(&mut sim, |sim| apply_all(sim, command, &inbox)) == Some(false) {
                    return;
                }
                changed = true;
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => return,
        }
        let batch = clock.advance(&mut sim, MAX_BATCH_WALL_TIME);
        if batch.steps > 0 || batch.failed || changed {
            publish(&sim, &slot);
        }
    }
}

/// Applies `first` and everything else already queued; false when one of them is `Quit`.
fn apply_all(sim: &mut Simulation, first: Command, inbox: &Receiver<Command>) -> bool {
    if !sim.apply(first) {
        return false;
    }
    while let Ok(command) = inbox.try_recv() {
        if !sim.apply(command) {
            return false;
        }
    }
    true
}

fn publish(sim: &Simulation, slot: &SnapshotSlot) {
    let snapshot = Arc::new(sim.snapshot(Instant::now()));
    if let Ok(mut latest) = slot.lock() {
        *latest = Some(snapshot);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::command::SpawnKind;
    use glam::DVec3;

    /// Polls until `accept` holds for the newest snapshot, or fails after two seconds.
    fn wait_for(handle: &SimHandle, accept: impl Fn(&Snapshot) -> bool) -> Arc<Snapshot> {
        let deadline = Instant::now() + Duration::from_secs(2);
        loop {
            let snap = handle.latest().unwrap();
            if accept(&snap) {
                return snap;
            }
            assert!(Instant::now() < deadline, "condition not reached");
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    #[test]
    fn runs_at_fixed_dt_in_step_with_the_wall_clock() {
        let handle = SimHandle::spawn("falling_box").unwrap();
        handle.send(Command::SetDt(0.004));
        let started = Instant::now();
        std::thread::sleep(Duration::from_millis(400));
        let snap = handle.latest().unwrap();
        let wall = started.elapsed().as_secs_f64();
        let c = snap.counters;
        // Sim time is exactly steps × dt (up to round-off): the step never varies.
        assert!((c.sim_time - c.steps as f64 * 0.004).abs() < 1e-9, "{c:?}");
        // And it keeps up with the wall clock (loose: the machine is shared).
        assert!(
            c.sim_time > 0.5 * wall && c.sim_time <= wall + 0.01,
            "{c:?} wall {wall}"
        );
    }

    #[test]
    fn pause_and_step_once_take_exactly_one_step() {
        let handle = SimHandle::spawn("falling_box").unwrap();
        handle.send(Command::SetPaused(true));
        let paused = wait_for(&handle, |s| s.settings.paused);
        std::thread::sleep(Duration::from_millis(50));
        let still = handle.latest().unwrap();
        assert_eq!(still.counters.steps, paused.counters.steps);
        handle.send(Command::StepOnce);
        wait_for(&handle, |s| s.counters.steps == paused.counters.steps + 1);
    }

    #[test]
    fn a_panic_in_a_step_stops_the_simulation_until_reset() {
        let mut sim = Simulation::new("falling_box").unwrap();
        sim.step();
        let result = guarded(&mut sim, |_: &mut Simulation| -> () {
            panic!("solver blew up")
        });
        assert!(result.is_none());
        let failure = sim.failure().expect("the failure is kept").to_string();
        assert!(failure.contains("solver blew up"), "{failure}");
        let shown = sim.snapshot(Instant::now());
        assert_eq!(shown.message.as_deref(), Some(failure.as_str()));
        assert!(shown.settings.paused);
        // Stepping is refused while failed; a reset brings the scene back.
        let ticks = sim.ticks();
        sim.step();
        sim.apply(Command::StepOnce);
        assert_eq!(sim.ticks(), ticks);
        sim.apply(Command::Reset);
        assert!(sim.failure().is_none());
        assert!(!sim.settings().paused);
        sim.step();
        assert_eq!(sim.ticks(), ticks + 1);
    }

    #[test]
    fn a_spawn_storm_keeps_commands_answered() {
        let handle = SimHandle::spawn("falling_box").unwrap();
        for i in 0..10_000 {
            handle.send(Command::Spawn {
                kind: SpawnKind::ALL[i % SpawnKind::ALL.len()],
                position: DVec3::new(0.0, 6.0, 0.0),
                velocity: DVec3::ZERO,
            });
        }
        let stormed = wait_for(&handle, |s| s.bodies.len() == 10_003);
        // Spawned at one point, the bodies were stacked into a column, not overlapped.
        let top = stormed
            .bodies
            .iter()
            .map(|b| b.pose.position.y)
            .fold(0.0, f32::max);
        assert!(top > 0.5 * 10_000.0, "column top at {top} m");
        // Steps of 10 000 awake bodies are slow, but a pause is still seen within a batch.
        handle.send(Command::SetPaused(true));
        let paused = wait_for(&handle, |s| s.settings.paused);
        std::thread::sleep(Duration::from_millis(200));
        assert_eq!(
            handle.latest().unwrap().counters.steps,
            paused.counters.steps
        );
    }

    #[test]
    fn reset_and_spawn_are_applied() {
        let handle = SimHandle::spawn("falling_box").unwrap();
        handle.send(Command::Spawn {
            kind: SpawnKind::Box,
            position: DVec3::new(0.0, 6.0, 0.0),
            velocity: DVec3::ZERO,
        });
        wait_for(&handle, |s| s.bodies.len() == 4);
        handle.send(Command::SetPaused(true));
        handle.send(Command::Reset);
        let snap = wait_for(&handle, |s| s.bodies.len() == 3);
        assert_eq!(snap.counters.steps, 0);
        handle.send(Command::LoadScene("pachinko".into()));
        wait_for(&handle, |s| s.scene == "pachinko" && s.bodies.len() > 50);
    }
}
