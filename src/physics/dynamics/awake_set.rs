//! The bodies a step works on. Every per-step pass (proxies, broad phase, islands, solver,
//! checks) visits the awake bodies and the bodies the user touched since the last step, never
//! the whole body list, so sleeping and static bodies cost nothing per step. The awake list
//! is rebuilt (one O(n) pass) only on steps where some body fell asleep, woke, or was added,
//! removed or handed out for editing.

use crate::physics::dynamics::body::RigidBody;

#[derive(Clone, Debug, Default)]
pub struct AwakeSet {
    /// Awake dynamic bodies in ascending order; valid while `current`.
    awake: Vec<u32>,
    current: bool,
    /// Set by each rebuild, taken by the broad phase: the idle bodies may have changed.
    rebuilt: bool,
    /// Bodies added, removed or handed out by `World::body_mut` since the last step.
    touched: Vec<u32>,
}

impl AwakeSet {
    /// A set that starts with `touched` to look at (a world restored from a snapshot).
    pub fn with_touched(touched: Vec<u32>) -> Self {
        AwakeSet {
            touched,
            ..AwakeSet::default()
        }
    }

    /// Body `index` may have changed in any way: look at it in the next step.
    pub fn touch(&mut self, index: usize) {
        self.touched.push(index as u32);
        self.current = false;
    }

    /// Some body fell asleep or woke: rebuild before the list is used again.
    pub fn invalidate(&mut self) {
        self.current = false;
    }

    pub fn touched(&self) -> &[u32] {
        &self.touched
    }

    /// The touched bodies, ascending and without repeats; the list starts empty again.
    pub fn take_touched(&mut self) -> Vec<u32> {
        let mut touched = std::mem::take(&mut self.touched);
        touched.sort_unstable();
        touched.dedup();
        touched
    }

    /// The awake bodies, rebuilt first if something changed.
    pub fn awake(&mut self, bodies: &[RigidBody]) -> &[u32] {
        if !self.current {
            self.awake.clear();
            let awake = bodies.iter().enumerate().filter(|(_, b)| b.is_awake());
            self.awake.extend(awake.map(|(i, _)| i as u32));
            self.current = true;
            self.rebuilt = true;
        }
        &self.awake
    }

    /// True once after each rebuild.
    pub fn take_rebuilt(&mut self) -> bool {
        std::mem::take(&mut self.rebuilt)
    }
}
