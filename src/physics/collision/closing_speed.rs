//! How fast two bodies' surfaces can approach each other within a step: what a pair's
//! speculative margin has to cover (see `narrow_phase`).
//!
//! Velocities change within a step only through the contacts solved in it, and two
//! idealisations of what those contacts do each give a bound; the smaller is used.
//! - Against the world: a contact slows a body down, at most to rest. Two surfaces then
//!   close at most at the sum of their bodies' surface speeds, |v| + |ω| r each.
//! - Within a cluster: contacts exchange momentum between bodies that can reach each other,
//!   so a body's velocity stays among the velocities of its cluster: the bodies tied to it
//!   by this step's broad-phase pairs, and rest when one of them is fixed. Two members then
//!   close at most at the spread of those velocities, plus their own spins.
//!
//! The second bound is what spares bodies that move together (a volley falling through the
//! air, a load carried along) a contact with every neighbour within |v| dt: they close at
//! the spread of their velocities, not at their speed. A cluster with a fixed body in it
//! spreads down to rest, so a body trailing another that a floor stops within the step is
//! still caught by their speculative contact.

use glam::DVec3;

use crate::physics::collision::broad_phase::BodyPair;
use crate::physics::dynamics::body::RigidBody;
use crate::physics::dynamics::union_find::UnionFind;

/// A bound on the speed of any surface point of `body` (its shape's bounding radius about
/// its origin is `radius`): |v| + |ω| r. Zero for a body the step does not move.
pub fn surface_speed(body: &RigidBody, radius: f64) -> f64 {
    let motion = Motion::of(body, radius);
    motion.speed + motion.spin_speed
}

/// What the closing bounds read of one body, measured once a step.
#[derive(Clone, Copy, Debug, Default)]
struct Motion {
    /// The bounding radius of its shape about the shape's origin.
    radius: f64,
    /// |v|; zero for a body the step does not move.
    speed: f64,
    /// |ω| times the reach of its surface from the centre of mass; zero likewise.
    spin_speed: f64,
}

impl Motion {
    fn of(body: &RigidBody, radius: f64) -> Self {
        if !body.is_awake() {
            return Motion {
                radius,
                ..Motion::default()
            };
        }
        let reach = radius + body.local_center.length();
        Motion {
            radius,
            speed: body.velocity().length(),
            spin_speed: body.angular_velocity().length() * reach,
        }
    }
}

/// What the narrow phase needs to know of a pair before it searches for contacts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairReach {
    /// The bounding radii of the two shapes about their origins.
    pub radii: [f64; 2],
    /// How far their surfaces can approach each other within the step, m.
    pub closable: f64,
}

/// The smaller of the two bounds on how far two bodies' surfaces approach in `dt`, given the
/// spread of their cluster's velocities.
fn closable_distance(a: &Motion, b: &Motion, spread: f64, dt: f64) -> f64 {
    let dt = dt.abs();
    let against_world = (a.speed + a.spin_speed) * dt + (b.speed + b.spin_speed) * dt;
    let within_cluster = (spread + a.spin_speed + b.spin_speed) * dt;
    against_world.min(within_cluster)
}

/// The bodies of a step's broad-phase pairs with their motions, the dynamic ones grouped
/// into clusters by those pairs, and the spread of each cluster's velocities. Kept between
/// steps so that measuring allocates nothing once grown; only the members' entries are
/// visited, so bodies in no pair (asleep apart, say) cost nothing.
#[derive(Clone, Debug, Default)]
pub struct Clusters {
    /// Bodies in some pair, in the order first met.
    members: Vec<u32>,
    /// Each member's place in `members`, by body index (`NOT_A_MEMBER` elsewhere).
    member_of: Vec<u32>,
    motions: Vec<Motion>,
    /// Over the dynamic members: fixed bodies tie nothing together.
    sets: UnionFind,
    /// For each set's root: the box around its members' velocities (and rest when a fixed
    /// body is paired with one of them).
    velocities: Vec<[DVec3; 2]>,
    /// Each dynamic member's cluster spread: the length of the diagonal of its root's box,
    /// m/s; zero for a fixed member.
    spread: Vec<f64>,
}

const NOT_A_MEMBER: u32 = u32::MAX;

impl Clusters {
    /// Measures the bodies of `pairs`, groups the dynamic ones and measures each group's
    /// spread of velocities.
    pub fn measure(&mut self, bodies: &[RigidBody], pairs: &[BodyPair]) {
        self.forget_members(bodies.len());
        for pair in pairs {
            for index in [pair.a.index(), pair.b.index()] {
                self.join(bodies, index);
            }
        }
        self.sets.reset(self.members.len());
        for pair in pairs {
            let [a, b] = [pair.a.index(), pair.b.index()];
            if bodies[a].motion.moves() && bodies[b].motion.moves() {
                self.sets.union(self.place(a), self.place(b));
            }
        }
        self.gather_velocities(bodies, pairs);
        self.spread.clear();
        for (k, &index) in self.members.iter().enumerate() {
            let spread = if bodies[index as usize].motion.moves() {
                let [low, high] = self.velocities[self.sets.find(k)];
                (high - low).length()
            } else {
                0.0
            };
            self.spread.push(spread);
        }
    }

    /// The radii and closable distance of a pair `measure` saw, over `dt`.
    pub fn reach_of(&self, pair: &BodyPair, dt: f64) -> PairReach {
        let [a, b] = [self.place(pair.a.index()), self.place(pair.b.index())];
        let (motion_a, motion_b) = (&self.motions[a], &self.motions[b]);
        // A dynamic pair shares its cluster; against a fixed body only the dynamic side has one.
        let spread = self.spread[a].max(self.spread[b]);
        PairReach {
            radii: [motion_a.radius, motion_b.radius],
            closable: closable_distance(motion_a, motion_b, spread, dt),
        }
    }

    /// A member's place in `members`.
    fn place(&self, index: usize) -> usize {
        self.member_of[index] as usize
    }

    fn forget_members(&mut self, body_count: usize) {
        for &index in &self.members {
            self.member_of[index as usize] = NOT_A_MEMBER;
        }
        self.members.clear();
        self.motions.clear();
        if self.member_of.len() < body_count {
            self.member_of.resize(body_count, NOT_A_MEMBER);
        }
    }

    fn join(&mut self, bodies: &[RigidBody], index: usize) {
        if self.member_of[index] == NOT_A_MEMBER {
            self.member_of[index] = self.members.len() as u32;
            self.members.push(index as u32);
            let body = &bodies[index];
            self.motions
                .push(Motion::of(body, body.shape.bounding_radius()));
        }
    }

    /// Each root's box around its dynamic members' velocities, widened to rest where a
    /// member is paired with a fixed body. A sleeping member counts with its velocity (rest).
    fn gather_velocities(&mut self, bodies: &[RigidBody], pairs: &[BodyPair]) {
        let empty = [DVec3::INFINITY, DVec3::NEG_INFINITY];
        self.velocities.clear();
        self.velocities.resize(self.members.len(), empty);
        for k in 0..self.members.len() {
            let body = &bodies[self.members[k] as usize];
            if body.motion.moves() {
                self.widen(k, body.velocity());
            }
        }
        for pair in pairs {
            let [a, b] = [pair.a.index(), pair.b.index()];
            match (bodies[a].motion.moves(), bodies[b].motion.moves()) {
                (true, false) => self.widen(self.place(a), DVec3::ZERO),
                (false, true) => self.widen(self.place(b), DVec3::ZERO),
                _ => {}
            }
        }
    }

    fn widen(&mut self, member: usize, velocity: DVec3) {
        let root = self.sets.find(member);
        let [low, high] = &mut self.velocities[root];
        *low = low.min(velocity);
        *high = high.max(velocity);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::dynamics::body::BodyDesc;
    use crate::physics::geometry::shape::Shape;

    fn ball(velocity: DVec3) -> RigidBody {
        RigidBody::from_desc(&BodyDesc::dynamic(Shape::sphere(0.1)).with_velocity(velocity))
            .expect("valid")
    }

    fn floor() -> RigidBody {
        RigidBody::from_desc(&BodyDesc::fixed(Shape::cuboid(DVec3::ONE))).expect("valid")
    }

    fn pairs(list: &[(usize, usize)]) -> Vec<BodyPair> {
        list.iter().map(|&(i, j)| BodyPair::new(i, j)).collect()
    }

    #[test]
    fn a_cluster_spreads_over_its_members_velocities_and_rest_when_fixed_bodies_join() {
        let down = DVec3::new(0.0, -10.0, 0.0);
        let side = DVec3::new(3.0, -10.0, 4.0);
        // 0-1 fall together; 2-3-4 are a chain, 4 paired with the floor 5.
        let bodies = vec![
            ball(down),
            ball(down),
            ball(down),
            ball(side),
            ball(down),
            floor(),
        ];
        let mut clusters = Clusters::default();
        clusters.measure(&bodies, &pairs(&[(0, 1), (2, 3), (3, 4), (4, 5)]));
        // The balls do not turn: what a pair can close in 1 s is its cluster's spread.
        let closable =
            |clusters: &Clusters, i, j| clusters.reach_of(&BodyPair::new(i, j), 1.0).closable;
        assert_eq!(closable(&clusters, 0, 1), 0.0);
        // The box from rest to (3, 10, 4) in size: its diagonal.
        let chain = (3.0f64 * 3.0 + 10.0 * 10.0 + 4.0 * 4.0).sqrt();
        for (i, j, against_world) in [
            (2, 3, 10.0 + 125f64.sqrt()),
            (3, 4, 10.0 + 125f64.sqrt()),
            (4, 5, 10.0),
        ] {
            let spread = closable(&clusters, i, j);
            assert!(
                (spread - chain.min(against_world)).abs() < 1e-12,
                "{i}-{j}: {spread}"
            );
        }
        // Measured again with the floor under 0 only: the old chain is forgotten.
        clusters.measure(&bodies, &pairs(&[(0, 5), (2, 3)]));
        assert_eq!(closable(&clusters, 0, 5), 10.0);
        assert_eq!(closable(&clusters, 2, 3), 5.0);
        assert_eq!(
            clusters.reach_of(&BodyPair::new(0, 5), 1.0).radii,
            [0.1, 3f64.sqrt()]
        );
    }

    #[test]
    fn the_closable_distance_is_the_smaller_of_the_two_bounds() {
        let (a, b) = (ball(DVec3::X * 6.0), ball(DVec3::X * 5.0));
        let (a, b) = (Motion::of(&a, 0.1), Motion::of(&b, 0.1));
        let dt = 0.5;
        // Apart in their own cluster they close at 1 m/s; stopped by the world, at 11.
        assert_eq!(closable_distance(&a, &b, 1.0, dt), 0.5);
        assert_eq!(closable_distance(&a, &b, 20.0, dt), 5.5);
    }
}
