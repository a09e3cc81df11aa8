//! Bodies beyond the range where a contact's arithmetic stays finite. A contact multiplies
//! speeds by masses and by each other, and GJK multiplies coordinates three at a time: a
//! finite body at 1e150 m/s meeting a stack overflowed inside the solver, and the NaN
//! reached every body of the island within the step. Such a body loses its pairs before the
//! narrow phase and is isolated, so the bodies it would have touched never see its numbers.

use crate::physics::collision::broad_phase::BodyPair;
use crate::physics::dynamics::body::RigidBody;

/// Largest position (m), speed (m/s) or spin (rad/s), in magnitude, of a body that may take
/// part in a contact. Its cube, and its square times any mass a scene accepts, stay far
/// inside f64; no simulated scene comes near it.
pub const CONTACT_RANGE: f64 = 1e100;

/// Whether the body's position, speed or spin lies beyond `CONTACT_RANGE`.
pub fn beyond_contact_range(body: &RigidBody) -> bool {
    let largest = |v: glam::DVec3| v.abs().max_element();
    let magnitudes = [
        largest(body.position),
        largest(body.velocity()),
        largest(body.angular_velocity()),
    ];
    magnitudes.iter().any(|&m| m > CONTACT_RANGE)
}

/// The candidates beyond `CONTACT_RANGE` that still take part, ascending; empty (and nothing
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
