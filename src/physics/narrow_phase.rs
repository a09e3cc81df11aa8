//! Narrow phase: contact manifolds for the pairs the broad phase reported.
//!
//! Contacts are generated while bodies are still apart (speculative contacts) whenever their
//! surfaces could meet within the step: the margin of a pair is a small fixed distance plus
//! how far each body's surface can move in dt. The solver then lets such a gap close and no
//! more, which is what keeps fast bodies from tunnelling.

use glam::DVec3;
use rayon::prelude::*;

use crate::physics::aabb::Aabb;
use crate::physics::body::{Motion, RigidBody};
use crate::physics::broad_phase::{BodyPair, Proxy};
use crate::physics::contact::ContactManifold;
use crate::physics::manifold::contact_manifold;
use crate::physics::manifold_memory::{ManifoldMemory, RememberedManifold};

/// Contacts closer than this are always kept, m: enough for resting contacts to persist.
pub const SPECULATIVE_DISTANCE: f64 = 0.02;

/// An upper bound on how far any surface point of `body` moves in `dt`: |v| dt + |ω| r dt.
pub fn motion_bound(body: &RigidBody, dt: f64) -> f64 {
    if !body.is_awake() {
        return 0.0;
    }
    let reach = body.shape.bounding_radius() + body.local_center.length();
    (body.velocity().length() + body.angular_velocity().length() * reach) * dt.abs()
}

/// A proxy that overlaps nothing.
const EMPTY_PROXY: Proxy = Proxy {
    aabb: Aabb {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
    },
    active: false,
};

/// A body's broad-phase proxy: its box grown by half the fixed margin and by its motion
/// bound. Sleeping bodies are inactive (they pair with awake bodies only); isolated and
/// removed bodies get an empty box so that they meet nothing.
pub fn proxy_of(body: &RigidBody, dt: f64) -> Proxy {
    match body.motion {
        Motion::Isolated | Motion::Removed => EMPTY_PROXY,
        Motion::Dynamic | Motion::Static => Proxy {
            active: body.is_awake(),
            ..Proxy::of_body(body, 0.5 * SPECULATIVE_DISTANCE + motion_bound(body, dt))
        },
    }
}

/// Recomputes the proxies of the bodies in `refresh` (the awake ones and those the user
/// touched). Static and sleeping bodies do not move, so their boxes are kept from when they
/// were last computed: idle bodies cost nothing here.
pub fn update_proxies(
    bodies: &[RigidBody],
    dt: f64,
    proxies: &mut Vec<Proxy>,
    refresh: impl Iterator<Item = usize>,
) {
    proxies.resize(bodies.len(), EMPTY_PROXY);
    for index in refresh {
        proxies[index] = proxy_of(&bodies[index], dt);
    }
}

/// Pairs handed to one rayon task: enough work to outweigh the task's overhead.
const PAIRS_PER_TASK: usize = 64;

/// The manifolds of all candidate pairs whose surfaces are, or may come, within reach, in
/// pair order, and what to remember of them for the next step. A pair that has barely moved
/// since `memory` saw it carries its remembered manifold (see `manifold_memory`); the others
/// are generated. Pairs are independent, so they are computed on all threads; the collected
/// order, and so every later stage, is the same for any number of threads.
pub fn find_manifolds(
    bodies: &[RigidBody],
    pairs: &[BodyPair],
    dt: f64,
    memory: &ManifoldMemory,
) -> (Vec<ContactManifold>, ManifoldMemory) {
    let (manifolds, remembered) = if rayon::current_num_threads() == 1 {
        // Handing the work to a pool of one thread only adds its wake-ups.
        let mut found = (
            Vec::with_capacity(pairs.len()),
            Vec::with_capacity(pairs.len()),
        );
        found.extend((pairs.iter()).filter_map(|pair| manifold_of_pair(bodies, pair, dt, memory)));
        found
    } else {
        pairs
            .par_iter()
            .with_min_len(PAIRS_PER_TASK)
            .filter_map(|pair| manifold_of_pair(bodies, pair, dt, memory))
            .unzip()
    };
    (manifolds, ManifoldMemory::new(remembered))
}

fn manifold_of_pair(
    bodies: &[RigidBody],
    pair: &BodyPair,
    dt: f64,
    memory: &ManifoldMemory,
) -> Option<(ContactManifold, RememberedManifold)> {
    let (a, b) = (&bodies[pair.a.index()], &bodies[pair.b.index()]);
    if !a.is_awake() && !b.is_awake() {
        return None;
    }
    let closable = motion_bound(a, dt) + motion_bound(b, dt);
    let margin = SPECULATIVE_DISTANCE + closable;
    let remembered = memory.find(pair.a, pair.b);
    if let Some(carried) = remembered.and_then(|r| r.carried(a, b, margin, closable)) {
        return Some((carried, remembered?.clone()));
    }
    let manifold = contact_manifold(a, pair.a, b, pair.b, margin)?;
    let remembered = RememberedManifold::of(&manifold, a, b, margin);
    Some((manifold, remembered))
}
