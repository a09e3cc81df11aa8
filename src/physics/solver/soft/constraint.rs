//! A prepared contact point as the passes read it: the bodies' slots, the three directions
//! (normal, two tangents), effective masses, each side's lever arm and spins, and the
//! impulses accumulated so far.

use glam::{DMat3, DVec3};
use smallvec::SmallVec;

use super::WarmImpulse;
use crate::physics::dynamics::body::RigidBody;
use crate::physics::solver::lanes::{F32x4, F64x4, LaneVector, Lanes};
use crate::physics::solver::solver_bodies::{
    FIXED_SLOT, Push, SharedBodies, SolverBodies, SolverBody,
};

/// One prepared contact point. Its directions are the normal (from a to b), then the two
/// tangents; the arms stay fixed for the step: impulses act where the bodies touch, not
/// where that material point has rotated to (a rolling ball keeps pushing at its bottom).
///
/// A pass streams the constraints through memory, so only what shortens a point's solve is
/// stored: the spins that give the speeds from the momenta (`Side::spins`); the turning an
/// impulse gives is derived from the levers. The directions, levers and spins are stored
/// as f32 (`F32x4`) and widened to f64 as a pass loads them; `prepare` rounds the
/// directions and levers first, so that the passes solve the constraint it prepared. The
/// tangents' masses and couplings and the friction coefficient, which only scale a
/// friction step, are f32 too. The directions are stored once, transposed (`across`), and
/// turned back into vectors where an impulse needs them. What only the relax pass reads
/// (`PointAnchors`) and what only restitution reads (`PointImpact`) are kept apart. The
/// fields are laid out in the order a pass reads them, so that the processor's prefetcher
/// sees one forward stream, and a record is four whole cache lines (BENCHMARKS.md,
/// "Narrow contact records", "Contact records in four cache lines").
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(64))]
pub(super) struct PointConstraint {
    /// The solver slots of a and b.
    pub(super) slots: [u32; 2],
    /// Whether the next contact in the pass shares no moving body with this one, so that
    /// the two may be solved side by side (`solve_two`).
    pub(super) pairs_with_next: bool,
    /// Whether the point began the step deeper than `deep_overlap` beyond what its load
    /// explains (`push_out::mark_deep`).
    pub(super) deep: bool,
    /// The pair's Coulomb coefficient, √(μa μb).
    pub(super) friction: f32,
    /// The impulses accumulated so far, N·s: the warm start at first, the contact's final
    /// impulse after the step.
    pub(super) impulse: WarmImpulse,
    /// The separation at the bodies' current poses. Poses only change between a substep's
    /// biased pass and its relax pass, so the relax pass measures it and the next
    /// substep's biased pass and the restitution pass read it.
    pub(super) separation: f64,
    /// The mass an impulse along the normal meets, kg (zero when neither body moves).
    pub(super) normal_mass: f64,
    /// The largest normal impulse one pass has added in this step, N·s: zero until the
    /// contact first pushes, and restitution leaves a contact that never did alone.
    pub(super) max_normal_impulse: f64,
    /// The same along each tangent, kg.
    pub(super) tangent_mass: [f32; 2],
    /// What a unit normal impulse adds to the relative speed along each tangent (zero for
    /// point masses; the lever arms couple them). The friction solve after the normal
    /// solve reads the tangent speeds through it instead of from the bodies again, so that
    /// each contact reads and writes its two bodies once per pass.
    pub(super) normal_to_tangent: [f32; 2],
    /// The normal and the tangents, transposed (lane k of `across[c]` is component c of
    /// direction k), to take the speeds along all three at once.
    pub(super) across: [F32x4; 3],
    /// Where the impulses act on body a.
    pub(super) a: Side,
    /// Where the impulses act on body b.
    pub(super) b: Side,
}

/// What restitution reads of a prepared contact point, kept out of the records every pass
/// streams; a pass only writes `approach_speed`, when the contact first pushes.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PointImpact {
    /// Normal relative velocity at impact, m/s (negative when closing), as the speed of the
    /// discrete arc (see `restitution::rebound_speed`); until the contact first pushes, the
    /// one at step start. What restitution reflects.
    pub(super) approach_speed: f64,
    /// Relative normal acceleration from the environmental forces, for the impact speed.
    pub(super) approach_acceleration: f64,
    /// The fastest approach the pair can reach in this step on its own, m/s, negative
    /// (`prepare::fastest_approach`): `approach_speed` is never taken faster than this. A
    /// neighbour solved earlier in the same pass can push the bodies together faster; that
    /// momentum is the neighbour's contact's business, and bouncing it here too would add
    /// energy, as it did to a ball pressed onto a pin by another when the ball–ball contact
    /// happened to be solved first (BENCHMARKS.md, "Fastest approach").
    pub(super) fastest_approach: f64,
    /// The pair's restitution ε, the smaller of the two.
    pub(super) restitution: f64,
}

/// Contact points with their anchors and impacts, in the same order.
pub(super) struct Contacts<'a> {
    pub(super) points: &'a mut [PointConstraint],
    pub(super) anchors: &'a [PointAnchors],
    pub(super) impacts: &'a mut [PointImpact],
}

impl<'a> Contacts<'a> {
    /// The points in `range`.
    pub(super) fn range(&mut self, range: std::ops::Range<usize>) -> Contacts<'_> {
        Contacts {
            points: &mut self.points[range.clone()],
            anchors: &self.anchors[range.clone()],
            impacts: &mut self.impacts[range],
        }
    }

    /// The same points, borrowed again.
    pub(super) fn reborrow(&mut self) -> Contacts<'_> {
        Contacts {
            points: self.points,
            anchors: self.anchors,
            impacts: self.impacts,
        }
    }

    /// The first `mid` points, and the others.
    fn split_at(self, mid: usize) -> (Contacts<'a>, Contacts<'a>) {
        let (points, points_rest) = self.points.split_at_mut(mid);
        let (anchors, anchors_rest) = self.anchors.split_at(mid);
        let (impacts, impacts_rest) = self.impacts.split_at_mut(mid);
        (
            Contacts {
                points,
                anchors,
                impacts,
            },
            Contacts {
                points: points_rest,
                anchors: anchors_rest,
                impacts: impacts_rest,
            },
        )
    }

    /// The points cut into about `parts` runs of near-equal length that never cut a run of
    /// points between the same two bodies (a manifold), at most `MAX_PARTS`.
    pub(super) fn split(self, parts: usize) -> SmallVec<[Contacts<'a>; MAX_PARTS]> {
        let length = self.points.len().div_ceil(parts.clamp(1, MAX_PARTS));
        let mut split = SmallVec::new();
        let mut rest = self;
        while !rest.points.is_empty() {
            let mut end = length.min(rest.points.len());
            while end < rest.points.len() && rest.points[end].same_bodies(&rest.points[end - 1]) {
                end += 1;
            }
            let (part, tail) = rest.split_at(end);
            split.push(part);
            rest = tail;
        }
        split
    }
}

/// The most parts `Contacts::split` makes: a colour split many times over the threads
/// balances them, and a split costs little next to a colour large enough to spread.
pub(super) const MAX_PARTS: usize = 32;

// Four cache lines (see the struct's comment).
const _: () = assert!(std::mem::size_of::<PointConstraint>() == 256);

impl PointConstraint {
    pub(super) fn normal(&self) -> DVec3 {
        let [x, y, z] = self.across.map(|row| f64::from(row.0[0]));
        DVec3::new(x, y, z)
    }

    /// The relative speeds of b's material point over a's along the normal and both
    /// tangents.
    #[inline(always)]
    pub(super) fn speeds<L: Lanes>(&self, l: L, bodies: &SharedBodies) -> [f64; 3] {
        let [slot_a, slot_b] = self.slots;
        let (a, b) = (bodies.get(slot_a), bodies.get(slot_b));
        let relative =
            l.load(b.linear_momentum) * b.inv_mass - l.load(a.linear_momentum) * a.inv_mass;
        let [x, y, z] = load3_narrow(l, &self.across);
        let sliding = x * relative.lane(0) + y * relative.lane(1) + z * relative.lane(2);
        let speeds = sliding + (self.b.turning_speeds(l, b) - self.a.turning_speeds(l, a));
        [speeds.lane(0), speeds.lane(1), speeds.lane(2)]
    }

    /// The impulse Σ λ d of impulses λ along the three directions.
    #[inline(always)]
    pub(super) fn along_directions<L: Lanes>(&self, l: L, lambda: [f64; 3]) -> L::Vector {
        let [n, t1, t2] = l.load_narrow_columns(&self.across);
        n * lambda[0] + t1 * lambda[1] + t2 * lambda[2]
    }

    /// Impulses λ along the three directions: +Σ λ d to b, −Σ λ d to a, at their levers.
    #[inline(always)]
    pub(super) fn apply<L: Lanes>(&self, l: L, bodies: &SharedBodies, lambda: [f64; 3]) {
        let [to_a, to_b] = self.on_each_body(l, self.along_directions(l, lambda));
        bodies.add(l, to_a);
        bodies.add(l, to_b);
    }

    /// A normal impulse only.
    pub(super) fn apply_normal<L: Lanes>(&self, l: L, bodies: &SharedBodies, lambda: f64) {
        let normal = l.load(F64x4::from_vec3(self.normal()));
        let [to_a, to_b] = self.on_each_body(l, normal * lambda);
        bodies.add(l, to_a);
        bodies.add(l, to_b);
    }

    /// The impulse the contact holds, as it acts on each body: what it adds to their next
    /// warm start.
    #[inline(always)]
    pub(super) fn warm_start_pushes<L: Lanes>(&self, l: L) -> [Push<L::Vector>; 2] {
        let [tangent_1, tangent_2] = self.impulse.tangent;
        let linear = self.along_directions(l, [self.impulse.normal, tangent_1, tangent_2]);
        self.on_each_body(l, linear)
    }

    /// The impulse J to b and −J to a, each at its lever. (Returned rather than handed to a
    /// closure: a closure is compiled without the packed instructions, and was left out of
    /// line once it called them.)
    #[inline(always)]
    pub(super) fn on_each_body<L: Lanes>(&self, l: L, linear: L::Vector) -> [Push<L::Vector>; 2] {
        let [slot_a, slot_b] = self.slots;
        [
            Push {
                slot: slot_a,
                linear: -linear,
                angular: -l.load_narrow(self.a.lever).cross(linear),
            },
            Push {
                slot: slot_b,
                linear,
                angular: l.load_narrow(self.b.lever).cross(linear),
            },
        ]
    }

    /// The next point of the same manifold (or of one between the same two bodies).
    pub(super) fn same_bodies(&self, other: &PointConstraint) -> bool {
        self.slots == other.slots
    }
}

/// One side of a prepared contact point: where impulses act on that body.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Side {
    /// The lever arm r (contact point − centre of mass) in world axes, fixed for the step:
    /// an impulse J there turns the body by r × J, and the point moves at v + ω × r.
    pub(super) lever: F32x4,
    /// I⁻¹ (r × d) for the normal and the tangents d, transposed like
    /// `PointConstraint::across` (zero where the body does not move). The point's speed
    /// along d from the turning, (r × d) · ω with ω = I⁻¹ A, is this · A (I⁻¹ is
    /// symmetric): one product with the momentum instead of deriving ω and crossing it with r,
    /// which made the longest chain of dependent operations in a pass longer.
    pub(super) spins: [F32x4; 3],
}

/// For each side of a prepared contact point, the point whose motion the separation follows
/// as the bodies move in this step: in body axes, or for a body that does not move, in world
/// axes. The contact point itself (the lever arm), except on a round surface, where it is
/// the centre of the rounding (`Shape::round_core`): a ball rolling on a floor turns its
/// material contact point up and away within the step, which read as the ball lifting off,
/// so it sank far deeper than the contact spring's deflection, and the sunk lever arm made
/// it roll slow (BENCHMARKS.md, "Rolling anchor").
///
/// Only the relax pass reads these, so they are kept in a list of their own, in the
/// constraints' order, out of the records that every pass streams (BENCHMARKS.md, "Contact
/// records in five cache lines", "Contact records in four cache lines").
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PointAnchors {
    pub(super) a: DVec3,
    pub(super) b: DVec3,
    /// Separation = normal · (world anchor b − world anchor a) + this.
    pub(super) separation_offset: f64,
}

impl PointAnchors {
    /// The separation of `c` at the bodies' current poses: its anchors carried along by the
    /// bodies' motion in this step.
    #[inline(always)]
    pub(super) fn separation<L: Lanes>(
        &self,
        l: L,
        bodies: &SharedBodies,
        c: &PointConstraint,
    ) -> f64 {
        let [slot_a, slot_b] = c.slots;
        let (anchor_a, anchor_b) = (
            anchor_in_world(l, self.a, bodies, slot_a),
            anchor_in_world(l, self.b, bodies, slot_b),
        );
        (anchor_b - anchor_a).dot3(c.normal()) + self.separation_offset
    }
}

/// An anchor (`PointAnchors`) in world coordinates at the body's current pose.
#[inline(always)]
fn anchor_in_world<L: Lanes>(l: L, anchor: DVec3, bodies: &SharedBodies, slot: u32) -> L::Vector {
    if !moves(slot) {
        // Without reading the slot: this runs every relax pass.
        return l.load(F64x4::from_vec3(anchor));
    }
    let body = bodies.get(slot);
    let [x, y, z] = load3(l, &body.orientation);
    l.load(body.position) + (x * anchor.x + y * anchor.y + z * anchor.z)
}

/// What a side's impulses do while a contact is prepared: for the normal and the two
/// tangents d, the arm r × d and the spin I⁻¹ (r × d) that a unit impulse along d gives,
/// with the world inertia at step start (zero where the body does not move).
///
/// The arms and spins are held transposed, like `PointConstraint::across` (lane k of
/// `arms[c]` is component c of direction k's arm), so that the three directions are worked
/// on at once: the same operations glam's `cross`, matrix product and `dot` would do for
/// each, in the same order.
pub(super) struct SideGeometry<V> {
    pub(super) lever: DVec3,
    pub(super) arms: [V; 3],
    pub(super) spins: [V; 3],
    pub(super) anchor: DVec3,
    /// From the contact point to the anchor at step start, world axes: zero but on a round
    /// surface.
    pub(super) anchor_shift: DVec3,
}

impl<V: LaneVector> SideGeometry<V> {
    #[inline(always)]
    pub(super) fn new<L: Lanes<Vector = V>>(
        l: L,
        body: &RigidBody,
        slot: u32,
        lever: DVec3,
        across: &[F64x4; 3],
    ) -> Self {
        if !moves(slot) {
            // Nothing turns it: only the anchor, the contact point in world axes, is read.
            let zero = l.load(F64x4::ZERO);
            return SideGeometry {
                lever,
                arms: [zero; 3],
                spins: [zero; 3],
                anchor: body.position + lever,
                anchor_shift: DVec3::ZERO,
            };
        }
        let r = lever;
        let [d0, d1, d2] = load3(l, across);
        // r × d: (r.y d.z − d.y r.z, r.z d.x − d.z r.x, r.x d.y − d.x r.y).
        let arms = [
            d2 * r.y - d1 * r.z,
            d0 * r.z - d2 * r.x,
            d1 * r.x - d0 * r.y,
        ];
        // I⁻¹ (r × d) by columns: col x · arm.x + col y · arm.y + col z · arm.z (a kinematic
        // body's spin is read through its slot's scale: `solver_bodies`).
        let m = SolverBodies::spin_of_momentum(body);
        let (x, y, z) = (m.x_axis, m.y_axis, m.z_axis);
        let spins = [
            arms[0] * x.x + arms[1] * y.x + arms[2] * z.x,
            arms[0] * x.y + arms[1] * y.y + arms[2] * z.y,
            arms[0] * x.z + arms[1] * y.z + arms[2] * z.z,
        ];
        let to_body = body.orientation.transpose();
        let on_surface = to_body * lever;
        let (anchor, anchor_shift) = match (body.shape).round_core(on_surface + body.local_center) {
            Some(core) => {
                let anchor = core - body.local_center;
                (anchor, body.orientation * anchor - lever)
            }
            None => (on_surface, DVec3::ZERO),
        };
        SideGeometry {
            lever,
            arms,
            spins,
            anchor,
            anchor_shift,
        }
    }

    /// arm_k · spin_k for each direction k, in lane k.
    #[inline(always)]
    pub(super) fn arm_dot_spin(&self) -> V {
        let (arms, spins) = (&self.arms, &self.spins);
        arms[0] * spins[0] + arms[1] * spins[1] + arms[2] * spins[2]
    }

    /// The normal's arm · spin_k for each direction k, in lane k.
    #[inline(always)]
    pub(super) fn normal_arm_dot_spin(&self) -> V {
        let (arms, spins) = (&self.arms, &self.spins);
        spins[0] * arms[0].lane(0) + spins[1] * arms[1].lane(0) + spins[2] * arms[2].lane(0)
    }

    /// The anchor in world coordinates with the body at this pose.
    #[inline(always)]
    pub(super) fn anchor_at(&self, slot: u32, position: DVec3, orientation: DMat3) -> DVec3 {
        if moves(slot) {
            position + orientation * self.anchor
        } else {
            self.anchor
        }
    }

    #[inline(always)]
    pub(super) fn into_lanes(self) -> Side {
        Side {
            lever: F32x4::narrowed(F64x4::from_vec3(self.lever)),
            spins: F32x4::narrowed3([
                self.spins[0].store(),
                self.spins[1].store(),
                self.spins[2].store(),
            ]),
        }
    }
}

impl Side {
    /// The speeds along the three directions (in lanes) that the body's turning gives its
    /// material point at the contact (see `spins`).
    #[inline(always)]
    pub(super) fn turning_speeds<L: Lanes>(&self, l: L, body: &SolverBody) -> L::Vector {
        let a = body.angular_momentum;
        let [x, y, z] = load3_narrow(l, &self.spins);
        x * a.lane(0) + y * a.lane(1) + z * a.lane(2)
    }
}

/// Three stored lanes, loaded (written out: an array's `map` is not always inlined, and
/// would then run without the packed instructions).
#[inline(always)]
pub(super) fn load3<L: Lanes>(l: L, stored: &[F64x4; 3]) -> [L::Vector; 3] {
    [l.load(stored[0]), l.load(stored[1]), l.load(stored[2])]
}

/// Three stored f32 lanes, loaded widened to f64 (written out, as `load3`).
#[inline(always)]
pub(super) fn load3_narrow<L: Lanes>(l: L, stored: &[F32x4; 3]) -> [L::Vector; 3] {
    [
        l.load_narrow(stored[0]),
        l.load_narrow(stored[1]),
        l.load_narrow(stored[2]),
    ]
}

/// The body's inverse mass as the impulses see it: zero when it does not move.
#[inline(always)]
pub(super) fn inv_mass(body: &RigidBody, slot: u32) -> f64 {
    if moves(slot) { body.inv_mass } else { 0.0 }
}

pub(super) fn moves(slot: u32) -> bool {
    slot != FIXED_SLOT
}
