//! Islands and sleeping.
//!
//! Bodies touching through contacts or held by a joint form islands (static bodies do not join islands: a floor
//! does not tie everything on it together). A body is quiet while its kinetic energy stays
//! under ½ m v², v = `sleep_speed` (the report's criterion: energy, watched over time so a
//! ball at the top of its flight is not put to sleep). An island whose bodies have all been
//! quiet for `time_to_sleep` sleeps as a whole; an island with any body that is not quiet is
//! awake as a whole, which is how an awake body wakes the sleeping ones it touches.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::physics::collision::contact::ContactManifold;
use crate::physics::dynamics::body::{BodyId, RigidBody};
use crate::physics::dynamics::union_find::UnionFind;

/// When bodies fall asleep: an island of touching bodies sleeps once each of them has had
/// less kinetic energy than ½ m v², v = `sleep_speed`, for `time_to_sleep`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SleepSettings {
    /// Whether islands may sleep; switching it off wakes every body at the next step.
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

/// What `update` works with, kept between steps so that it allocates nothing once grown.
#[derive(Clone, Debug, Default)]
pub struct IslandScratch {
    /// The members: awake bodies and the sleeping ones they touch, ascending.
    members: Vec<u32>,
    /// Each member's place in `members`, by body index (`NOT_A_MEMBER` elsewhere). Only the
    /// members' entries are set, and `update` clears them again, so that bodies asleep apart
    /// cost nothing here.
    member_of: Vec<u32>,
    island_ready: Vec<bool>,
    islands: UnionFind,
}

const NOT_A_MEMBER: u32 = u32::MAX;

/// Adds `dt` to the quiet time of each awake body slow enough to sleep, and resets the others.
/// Called after a step's motion: a body is quiet when the step left it slow, not when it
/// started slow (a body released at rest would otherwise count a whole long step as quiet
/// and fall asleep in mid-air before it ever moved).
pub fn add_quiet_time(bodies: &mut [RigidBody], awake: &[u32], dt: f64, settings: &SleepSettings) {
    for &index in awake {
        let body = &mut bodies[index as usize];
        let quiet = if body.is_kinematic() {
            // It never sleeps while it moves, and keeps its island awake.
            body.velocity() == DVec3::ZERO
                && body.angular_velocity() == DVec3::ZERO
                && body.kinematic_target.is_none()
        } else {
            body.kinetic_energy() < 0.5 * body.mass() * settings.sleep_speed.powi(2)
        };
        body.quiet_time = if quiet { body.quiet_time + dt } else { 0.0 };
    }
}

/// A body a joint drives (`Joint::is_driven`) is quiet only below this fraction of the
/// sleep speed. A servo's last approach is an exponential creep: at the sleep speed the
/// door scene's closer stopped 1.15° short of shut, and a slow motor would stop as well; at
/// a hundredth of it the creep ends a hundred times nearer, and a drive that is held still
/// (a stalled motor, a servo against a stop) still lets its bodies sleep.
const DRIVEN_SLEEP_SPEED_FRACTION: f64 = 0.01;

/// Resets the quiet time of each awake dynamic body among `driven` (the bodies of the driven
/// joints) that moves faster than `DRIVEN_SLEEP_SPEED_FRACTION` of the sleep speed.
pub fn hold_driven_awake(
    bodies: &mut [RigidBody],
    driven: impl Iterator<Item = usize>,
    settings: &SleepSettings,
) {
    let speed = DRIVEN_SLEEP_SPEED_FRACTION * settings.sleep_speed;
    for index in driven {
        let body = &mut bodies[index];
        if !(body.is_awake() && body.is_dynamic()) {
            continue;
        }
        if body.kinetic_energy() >= 0.5 * body.mass() * speed * speed {
            body.quiet_time = 0.0;
        }
    }
}

/// Puts to sleep or wakes the islands the awake bodies form with the bodies they touch or
/// are joined to (`links`: the bodies of each joint), by
/// the quiet times of the steps before (`add_quiet_time`). Only the awake bodies and the
/// sleeping bodies in this step's contacts are visited: bodies asleep apart from them stay
/// as they are at no cost. Returns true when some body fell asleep or woke.
pub fn update(
    bodies: &mut [RigidBody],
    awake: &[u32],
    manifolds: &[ContactManifold],
    links: &[(u32, u32)],
    settings: &SleepSettings,
    scratch: &mut IslandScratch,
) -> bool {
    let IslandScratch {
        members,
        member_of,
        island_ready,
        islands,
    } = scratch;
    members.clear();
    members.extend_from_slice(awake);
    for m in manifolds {
        for id in [m.body_a, m.body_b] {
            if bodies[id.index()].motion.moves() && bodies[id.index()].sleeping {
                members.push(id.0);
            }
        }
    }
    for &(a, b) in links {
        for (this, other) in [(a, b), (b, a)] {
            let (this_body, other_body) = (&bodies[this as usize], &bodies[other as usize]);
            if other_body.is_awake() && this_body.motion.moves() && this_body.sleeping {
                members.push(this);
            }
        }
    }
    members.sort_unstable();
    members.dedup();
    if member_of.len() < bodies.len() {
        member_of.resize(bodies.len(), NOT_A_MEMBER);
    }
    for (k, &index) in members.iter().enumerate() {
        member_of[index as usize] = k as u32;
    }
    let local =
        |id: BodyId| Some(member_of[id.index()] as usize).filter(|&k| k != NOT_A_MEMBER as usize);
    islands.reset(members.len());
    for m in manifolds {
        if let (Some(a), Some(b)) = (local(m.body_a), local(m.body_b)) {
            islands.union(a, b);
        }
    }
    for &(a, b) in links {
        if let (Some(a), Some(b)) = (local(BodyId(a)), local(BodyId(b))) {
            islands.union(a, b);
        }
    }
    for &index in members.iter() {
        member_of[index as usize] = NOT_A_MEMBER;
    }
    let ready = |body: &RigidBody| body.sleeping || body.quiet_time >= settings.time_to_sleep;
    // An island may sleep only if every member is ready.
    island_ready.clear();
    island_ready.resize(members.len(), true);
    for (k, &index) in members.iter().enumerate() {
        let root = islands.find(k);
        island_ready[root] &= ready(&bodies[index as usize]);
    }
    let mut changed = false;
    for (k, &index) in members.iter().enumerate() {
        let body = &mut bodies[index as usize];
        match (island_ready[islands.find(k)], body.sleeping) {
            (true, false) => body.sleep(),
            (false, true) => body.wake(),
            _ => continue,
        }
        changed = true;
    }
    changed
}
