//! Bodies beyond the range where a contact's arithmetic holds. A finite body at 1e150 m/s
//! meeting a stack overflowed inside the solver, and the NaN reached every body of the
//! island within the step; at 1e22 to 1e100 m/s nothing overflowed, but the stack's kinetic
//! energy grew 1e150-fold within two seconds. Such a body loses its pairs before the narrow
//! phase and is isolated, so the bodies it would have touched never see its numbers.

use crate::physics::collision::broad_phase::BodyPair;
use crate::physics::dynamics::body::RigidBody;

/// Largest speed (m/s) or spin (rad/s), in magnitude, of a body that may take part in a
/// contact. A ball hitting a stack of boxes at up to 1e21 m/s leaves them at most 0.18 of
/// its kinetic energy, as an inelastic hit should; from 1e22 m/s the energy exploded. The
/// limit keeps seven orders of magnitude from there, and is 50 000 times the speed of light.
pub const MAX_CONTACT_SPEED: f64 = 1e15;

/// Largest coordinate, m, of a body that may take part in a contact: a stack 1e30 m from the
/// origin stands as it does at the origin, and products of coordinates overflow near 1e154.
pub const MAX_CONTACT_POSITION: f64 = 1e100;

/// Whether the body's position, speed or spin lies beyond what a contact can take.
pub fn beyond_contact_range(body: &RigidBody) -> bool {
    let largest = |v: glam::DVec3| v.abs().max_element();
    // Written so that NaN counts as beyond.
    let within = largest(body.position) <= MAX_CONTACT_POSITION
        && largest(body.velocity()) <= MAX_CONTACT_SPEED
        && largest(body.angular_velocity()) <= MAX_CONTACT_SPEED;
    !within
}

/// The candidates beyond contact range that still take part, ascending; empty (and nothing
/// allocated) in a healthy step.
pub fn bodies_beyond_range(bodies: &[RigidBody], candidates: &[u32], more: &[u32]) -> Vec<u32> {
    let mut far: Vec<u32> = (candidates.iter().chain(more).copied())
        .filter(|&i| {
            let body = &bodies[i as usize];
            body.motion.takes_part() && beyond_contact_range(body)
        })
        .collect();
    far.sort_unstable();
    far.dedup();
    far
}

/// Drops every pair with a body of `far` (ascending), and returns those of `far` that had
/// one: the bodies a contact would have involved.
pub fn drop_pairs_of(pairs: &mut Vec<BodyPair>, far: &[u32]) -> Vec<u32> {
    let is_far = |id: u32| far.binary_search(&id).is_ok();
    let mut involved = Vec::new();
    pairs.retain(|pair| {
        let (a, b) = (pair.a.0, pair.b.0);
        involved.extend([a, b].into_iter().filter(|&i| is_far(i)));
        !(is_far(a) || is_far(b))
    });
    involved.sort_unstable();
    involved.dedup();
    involved
}
