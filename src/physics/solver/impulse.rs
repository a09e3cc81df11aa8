//! Impulses at a contact point between two bodies: the arithmetic both contact solvers share.

use glam::DVec3;

use crate::physics::dynamics::body::RigidBody;

/// Where an impulse acts: the two bodies and the lever arms (contact point − centre of
/// mass) on each, in world axes.
#[derive(Clone, Copy, Debug)]
pub struct Arms {
    pub a: usize,
    pub b: usize,
    pub r_a: DVec3,
    pub r_b: DVec3,
}

impl Arms {
    pub fn at(bodies: &[RigidBody], a: usize, b: usize, point: DVec3) -> Arms {
        Arms {
            a,
            b,
            r_a: point - bodies[a].position,
            r_b: point - bodies[b].position,
        }
    }

    /// The mass an impulse along `direction` meets: the inverse of the report's denominator
    /// 1/mA + 1/mB + (rA × d)·IA⁻¹(rA × d) + (rB × d)·IB⁻¹(rB × d). Zero between two bodies
    /// that cannot move.
    pub fn effective_mass(&self, bodies: &[RigidBody], direction: DVec3) -> f64 {
        let (a, b) = (&bodies[self.a], &bodies[self.b]);
        let (ta, tb) = (self.r_a.cross(direction), self.r_b.cross(direction));
        let k = a.inv_mass
            + b.inv_mass
            + ta.dot(a.inv_inertia_world * ta)
            + tb.dot(b.inv_inertia_world * tb);
        if k > 0.0 { 1.0 / k } else { 0.0 }
    }

    /// Velocity of b's material point at the contact minus a's.
    pub fn relative_velocity(&self, bodies: &[RigidBody]) -> DVec3 {
        let (a, b) = (&bodies[self.a], &bodies[self.b]);
        let v_b = b.velocity() + b.angular_velocity().cross(self.r_b);
        let v_a = a.velocity() + a.angular_velocity().cross(self.r_a);
        v_b - v_a
    }

    /// +impulse to b and −impulse to a at their arms; only awake bodies respond.
    pub fn apply(&self, bodies: &mut [RigidBody], impulse: DVec3) {
        push(&mut bodies[self.a], self.r_a, -impulse);
        push(&mut bodies[self.b], self.r_b, impulse);
    }
}

fn push(body: &mut RigidBody, lever: DVec3, impulse: DVec3) {
    if body.is_awake() {
        body.linear_momentum += impulse;
        body.angular_momentum += lever.cross(impulse);
    }
}

/// Two unit vectors orthogonal to `n` and to each other.
pub fn tangent_basis(n: DVec3) -> [DVec3; 2] {
    let helper = if n.x.abs() < 0.57 { DVec3::X } else { DVec3::Y };
    let t1 = n.cross(helper).normalize();
    [t1, n.cross(t1)]
}

/// Coulomb's law on a tangential impulse (two components along a tangent basis): scaled back
/// onto the disc of radius `limit` = μ times the normal impulse when it lies outside.
#[inline(always)]
pub fn clamp_to_friction_disc(tangent: [f64; 2], limit: f64) -> [f64; 2] {
    // Compared squared, so that a sticking contact, inside the disc, takes no square root.
    // The limit is never negative.
    let squared = tangent[0] * tangent[0] + tangent[1] * tangent[1];
    if squared <= limit * limit {
        return tangent;
    }
    let magnitude = squared.sqrt();
    let scale = if magnitude > 0.0 {
        limit / magnitude
    } else {
        0.0
    };
    [tangent[0] * scale, tangent[1] * scale]
}
