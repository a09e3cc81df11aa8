//! Narrow phase: contact manifolds for the pairs the broad phase reported.
//!
//! Contacts are generated while bodies are still apart (speculative contacts) whenever their
//! surfaces could meet within the step: the margin of a pair is a small fixed distance plus
//! how far the two surfaces can approach each other in dt (see `closing_speed`). The solver
//! then lets such a gap close and no more, which is what keeps fast bodies from tunnelling.

use glam::DVec3;
use rayon::prelude::*;

use crate::physics::collision::broad_phase::{BodyPair, Proxy};
use crate::physics::collision::closing_speed::{Clusters, PairReach, surface_speed};
use crate::physics::collision::contact::ContactManifold;
use crate::physics::collision::manifold::{PairFeature, PairOutcome, push_contact_manifold};
use crate::physics::collision::manifold_memory::{ManifoldMemory, Remembered, RememberedManifold};
use crate::physics::collision::separating_axis::SeparatedPair;
use crate::physics::dynamics::body::{Motion, RigidBody};
use crate::physics::geometry::aabb::Aabb;
use crate::physics::geometry::shape::Shape;

/// Contacts closer than this are always kept, m: enough for resting contacts to persist.
pub const SPECULATIVE_DISTANCE: f64 = 0.02;

/// An upper bound on how far any surface point of `body` moves in `dt`: |v| dt + |ω| r dt.
pub fn motion_bound(body: &RigidBody, dt: f64) -> f64 {
    if !body.is_awake() {
        return 0.0; // without measuring the shape
    }
    surface_speed(body, body.shape.bounding_radius()) * dt.abs()
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
        Motion::Dynamic | Motion::Kinematic | Motion::Static => Proxy {
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
/// are generated. `clusters` holds what was measured of these pairs' bodies this step.
/// Pairs are independent, so they are computed on all threads; the collected
/// order, and so every later stage, is the same for any number of threads.
///
/// The manifolds replace those in `manifolds`, and what to remember replaces `memory`, whose
/// old list is handed back in `scratch` for the next step to fill: once grown, a step
/// allocates none of these lists.
pub fn find_manifolds(
    bodies: &[RigidBody],
    pairs: &[BodyPair],
    clusters: &Clusters,
    dt: f64,
    memory: &mut ManifoldMemory,
    scratch: &mut NarrowScratch,
    manifolds: &mut Vec<ContactManifold>,
) {
    let mut found = Found {
        manifolds: std::mem::take(manifolds),
        remembered: std::mem::take(&mut scratch.spare),
    };
    // No room is reserved for one manifold per pair: in a pile most pairs are apart, and
    // the lists, kept between steps, grow to what the scene needs and stay there.
    found.clear();
    let memory_read: &ManifoldMemory = memory;
    if rayon::current_num_threads() == 1 {
        // Handing the work to a pool of one thread only adds its wake-ups.
        found.add_pairs(bodies, pairs, clusters, dt, memory_read);
    } else {
        // Parts beyond this step's are kept, with their memory, for a busier step.
        let tasks = pairs.len().div_ceil(PAIRS_PER_TASK);
        if scratch.parts.len() < tasks {
            scratch.parts.resize_with(tasks, Found::default);
        }
        let parts = &mut scratch.parts[..tasks];
        (parts.par_iter_mut())
            .zip(pairs.par_chunks(PAIRS_PER_TASK))
            .for_each(|(part, chunk)| {
                // Empty (the appends below empty them), and a pair makes at most one
                // manifold: a part never grows past this.
                part.manifolds.reserve(chunk.len());
                part.remembered.reserve(chunk.len());
                part.add_pairs(bodies, chunk, clusters, dt, memory_read);
            });
        for part in parts.iter_mut() {
            found.manifolds.append(&mut part.manifolds);
            found.remembered.append(&mut part.remembered);
        }
    }
    *manifolds = found.manifolds;
    scratch.spare = memory.replace(found.remembered);
}

/// The lists the narrow phase keeps between steps, so that once grown a step allocates
/// none of them.
#[derive(Clone, Debug, Default)]
pub struct NarrowScratch {
    /// The lists the next step's memory is built in: those the memory held before.
    spare: Remembered,
    /// One part per task when the pairs are spread over threads, joined in pair order.
    parts: Vec<Found>,
}

/// Manifolds found, in pair order, with what to remember of each.
#[derive(Clone, Debug, Default)]
struct Found {
    manifolds: Vec<ContactManifold>,
    remembered: Remembered,
}

impl Found {
    fn clear(&mut self) {
        self.manifolds.clear();
        self.remembered.clear();
    }

    /// The manifolds of `pairs`, in their order. Each is pushed where it is made: a
    /// manifold holds its contacts inline, and handing it back through the callers cost
    /// two copies of it per pair.
    fn add_pairs(
        &mut self,
        bodies: &[RigidBody],
        pairs: &[BodyPair],
        clusters: &Clusters,
        dt: f64,
        memory: &ManifoldMemory,
    ) {
        // Where the searches of `memory` start (see `ManifoldMemory::find_from`).
        let mut cursors = MemoryCursors::default();
        for pair in pairs {
            let (a, b) = (&bodies[pair.a.index()], &bodies[pair.b.index()]);
            if !a.is_awake() && !b.is_awake() {
                continue;
            }
            let reach = clusters.reach_of(pair, dt);
            self.add_pair((a, b), pair, reach, memory, &mut cursors);
        }
    }

    /// One pair of bodies of which at least one is awake.
    fn add_pair(
        &mut self,
        (a, b): (&RigidBody, &RigidBody),
        pair: &BodyPair,
        PairReach { radii, closable }: PairReach,
        memory: &ManifoldMemory,
        cursors: &mut MemoryCursors,
    ) {
        let margin = SPECULATIVE_DISTANCE + closable;
        let remembered = memory.find_from(pair.a, pair.b, &mut cursors.manifolds);
        if let Some(remembered) = remembered
            && remembered.carry_into(a, b, radii, margin, closable, &mut self.manifolds)
        {
            // Cloned where it is stored, not aside and then moved there.
            let manifolds = &mut self.remembered.manifolds;
            manifolds.extend_from_slice(std::slice::from_ref(remembered));
            return;
        }
        if !bounding_spheres_within(a, b, radii, margin) {
            return;
        }
        let hint = match remembered {
            Some(remembered) => remembered.feature.map(PairFeature::Touching),
            None => (memory.separating_feature(pair.a, pair.b, &mut cursors.separated))
                .map(PairFeature::Apart),
        };
        match push_contact_manifold((a, pair.a), (b, pair.b), margin, hint, &mut self.manifolds) {
            PairOutcome::Touching(feature) => {
                let manifold = self.manifolds.last().expect("just pushed");
                let manifolds = &mut self.remembered.manifolds;
                manifolds.push(RememberedManifold::of(manifold, a, b, margin, feature));
            }
            PairOutcome::Apart(Some(feature)) => {
                self.remembered.separated.push(SeparatedPair {
                    body_a: pair.a,
                    body_b: pair.b,
                    feature,
                });
            }
            PairOutcome::Apart(None) => {}
        }
    }
}

/// Where the narrow phase's searches of the two lists of the memory stand.
#[derive(Default)]
struct MemoryCursors {
    manifolds: usize,
    separated: usize,
}

/// Whether the spheres around the two shapes (about their origins, through their farthest
/// points: `radii`) come within `margin`; always true unless one of them is round or a hull.
/// Otherwise their surfaces are farther apart than the margin, so they cannot touch within
/// the step, and most pairs whose boxes overlap in a pile are apart like this. A sliver
/// above the margin is kept for the search to decide, as it measures the distance to a
/// tolerance. Boxes against boxes (also as parts of compounds) always go to their
/// closed-form search, which is cheap.
fn bounding_spheres_within(a: &RigidBody, b: &RigidBody, radii: [f64; 2], margin: f64) -> bool {
    let tested = |shape: &Shape| {
        (shape.is_convex() && !shape.is_polyhedral()) || matches!(shape, Shape::ConvexHull(_))
    };
    if !tested(&a.shape) && !tested(&b.shape) {
        return true;
    }
    let reach = radii[0] + radii[1];
    let gap = a.shape_origin().distance(b.shape_origin()) - reach;
    gap <= margin + 1e-6 * reach
}

#[cfg(test)]
mod tests {
    use glam::DQuat;

    use super::*;
    use crate::physics::dynamics::body::BodyDesc;
    use crate::physics::geometry::epa::signed_distance_within;
    use crate::physics::geometry::gjk::PosedShape;
    use crate::physics::geometry::hull::ConvexHull;

    /// Over pairs of a round shape or hull and every kind of shape, at distances and turns
    /// around touching, the sphere test never rules out a pair whose surfaces (GJK's
    /// distance) come within the margin, and it does rule out the pairs far apart.
    #[test]
    fn bounding_spheres_never_rule_out_a_contact() {
        let tetrahedron =
            ConvexHull::from_points(&[DVec3::ZERO, DVec3::X * 0.3, DVec3::Y * 0.3, DVec3::Z * 0.3])
                .expect("a tetrahedron");
        let tetrahedron = Shape::ConvexHull(std::sync::Arc::new(tetrahedron));
        let tested = [
            Shape::sphere(0.15),
            Shape::capsule(0.12, 0.08),
            Shape::cylinder(0.08, 0.15),
            tetrahedron.clone(),
        ];
        let others = [
            Shape::sphere(0.1),
            Shape::capsule(0.2, 0.05),
            Shape::cylinder(0.1, 0.2),
            Shape::cuboid(DVec3::new(0.15, 0.1, 0.12)),
            tetrahedron,
        ];
        let margin = 0.02;
        let (mut found, mut ruled_out) = (0, 0);
        for (i, a_shape) in tested.iter().enumerate() {
            for (j, b_shape) in others.iter().enumerate() {
                for k in 0..200 {
                    // Offsets from 0 to 1 m along a turning direction, both bodies tilted.
                    let t = k as f64 * 0.005;
                    let direction = DVec3::new(1.0, 0.3 * (k as f64).sin(), 0.2).normalize();
                    let tilt = |s: f64| DQuat::from_euler(glam::EulerRot::XYZ, s, 0.7 * s, 0.3);
                    let a = RigidBody::from_desc(
                        &BodyDesc::dynamic(a_shape.clone()).rotated(tilt(0.1 * k as f64)),
                    )
                    .expect("valid");
                    let b = RigidBody::from_desc(
                        &BodyDesc::dynamic(b_shape.clone())
                            .at(direction * t)
                            .rotated(tilt(0.37 * (k + i + j) as f64)),
                    )
                    .expect("valid");
                    let radii = [a.shape.bounding_radius(), b.shape.bounding_radius()];
                    let within = bounding_spheres_within(&a, &b, radii, margin);
                    let (posed_a, posed_b) = (PosedShape::of_body(&a), PosedShape::of_body(&b));
                    if signed_distance_within(&posed_a, &posed_b, margin, 1e-9).is_some() {
                        found += 1;
                        assert!(within, "{a_shape:?} and {b_shape:?} at {t} m ruled out");
                    }
                    ruled_out += usize::from(!within);
                }
            }
        }
        // Of the 4000 pairs, 1064 come within the margin and 2212 are ruled out.
        assert!(found > 800, "only {found} pairs touched");
        assert!(ruled_out > 1600, "only {ruled_out} pairs were ruled out");
    }
}
