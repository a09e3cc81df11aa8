//! Islands and sleeping.
//!
//! Bodies touching through contacts form islands (static bodies do not join islands: a floor
//! does not tie everything on it together). A body is quiet while its kinetic energy stays
//! under ½ m v², v = `sleep_speed` (the report's criterion: energy, watched over time so a
//! ball at the top of its flight is not put to sleep). An island whose bodies have all been
//! quiet for `time_to_sleep` sleeps as a whole; an island with any body that is not quiet is
//! awake as a whole, which is how an awake body wakes the sleeping ones it touches.

use serde::{Deserialize, Serialize};

use crate::physics::body::RigidBody;
use crate::physics::contact::ContactManifold;

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SleepSettings {
    pub enabled: bool,
    /// m/s: a body whose kinetic energy is below ½ m v² at this v is quiet.
    pub sleep_speed: f64,
    /// s of quiet before an island sleeps.
    pub time_to_sleep: f64,
}

impl Default for SleepSettings {
    fn default() -> Self {
        SleepSettings {
            enabled: true,
            sleep_speed: 0.05,
            time_to_sleep: 0.5,
        }
    }
}

/// Updates quiet times, then wakes or sleeps every island. Returns the number of awake bodies.
pub fn update(
    bodies: &mut [RigidBody],
    manifolds: &[ContactManifold],
    dt: f64,
    settings: &SleepSettings,
) -> usize {
    if !settings.enabled {
        bodies
            .iter_mut()
            .filter(|b| b.sleeping)
            .for_each(RigidBody::wake);
        return bodies.iter().filter(|b| b.is_awake()).count();
    }
    for body in bodies.iter_mut().filter(|b| b.is_awake()) {
        let quiet = body.kinetic_energy() < 0.5 * body.mass() * settings.sleep_speed.powi(2);
        body.quiet_time = if quiet { body.quiet_time + dt } else { 0.0 };
    }
    let mut islands = UnionFind::new(bodies.len());
    for m in manifolds {
        let (a, b) = (m.body_a.index(), m.body_b.index());
        if bodies[a].is_dynamic() && bodies[b].is_dynamic() {
            islands.union(a, b);
        }
    }
    let ready = |body: &RigidBody| body.sleeping || body.quiet_time >= settings.time_to_sleep;
    // An island may sleep only if every member is ready.
    let mut island_ready = vec![true; bodies.len()];
    for (index, body) in bodies.iter().enumerate().filter(|(_, b)| b.is_dynamic()) {
        let root = islands.find(index);
        island_ready[root] &= ready(body);
    }
    for index in 0..bodies.len() {
        if !bodies[index].is_dynamic() {
            continue;
        }
        let sleep = island_ready[islands.find(index)];
        match (sleep, bodies[index].sleeping) {
            (true, false) => bodies[index].sleep(),
            (false, true) => bodies[index].wake(),
            _ => {}
        }
    }
    bodies.iter().filter(|b| b.is_awake()).count()
}

/// Disjoint sets with path halving and union by size.
struct UnionFind {
    parent: Vec<usize>,
    size: Vec<usize>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n).collect(),
            size: vec![1; n],
        }
    }

    fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] != x {
            self.parent[x] = self.parent[self.parent[x]];
            x = self.parent[x];
        }
        x
    }

    fn union(&mut self, a: usize, b: usize) {
        let (mut ra, mut rb) = (self.find(a), self.find(b));
        if ra == rb {
            return;
        }
        if self.size[ra] < self.size[rb] {
            std::mem::swap(&mut ra, &mut rb);
        }
        self.parent[rb] = ra;
        self.size[ra] += self.size[rb];
    }
}
