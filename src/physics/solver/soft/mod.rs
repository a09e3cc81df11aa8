//! The `soft` contact solver: substepped sequential impulses on soft constraints.
//!
//! Per step, contact points are prepared once (anchors, tangents, effective masses, the
//! impulses remembered from the last step). Then each substep of length h = dt / substeps:
//! environmental forces → warm start → solve with a soft position bias → integrate poses →
//! relax (solve again without bias, removing the velocity the bias added). After the substeps
//! one restitution pass gives fast impacts their bounce.
//!
//! Softness: a penetration is not removed in one substep (which makes stacks jitter) but
//! pulled out like a critically-damped spring of `contact_hertz` Hz, capped at
//! `max_push_out` m/s. A contact that is still open (positive separation: speculative) lets
//! the bodies close the gap in this substep and no more, which stops fast bodies short of
//! the surface without adding energy.
//!
//! The solver works on the bodies' momenta (the report's state): velocities are derived
//! from them at every use, so a rotating body keeps its angular momentum exactly.
//!
//! Material combination: restitution is the smaller of the two (as in the report), friction
//! the geometric mean √(μa μb).

use glam::{DMat3, DVec3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::physics::dynamics::body::RigidBody;
use crate::physics::dynamics::forces::{self, EnvironmentForce};
use crate::physics::dynamics::integrate::{self, Integrator};
use crate::physics::solver::contact_colors::ContactColors;
use crate::physics::solver::impulse::{clamp_to_friction_disc, tangent_basis};
#[cfg(target_arch = "x86_64")]
use crate::physics::solver::lanes::Avx2;
use crate::physics::solver::lanes::{F64x4, LaneVector, Lanes, Portable};
use crate::physics::solver::solver_bodies::{
    FIXED_SLOT, Push, SharedBodies, SolverBodies, SolverBody,
};
use crate::physics::stage_times::Stopwatch;

/// A contact point handed to the solver. The normal points from body `a` to body `b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactInput {
    pub a: usize,
    pub b: usize,
    /// World position, midway between the two surfaces.
    pub point: DVec3,
    pub normal: DVec3,
    /// Distance between the surfaces along the normal; negative when penetrating.
    pub separation: f64,
    /// Normal and friction impulses this point ended the last step with.
    pub warm_impulse: WarmImpulse,
}

/// Accumulated impulses per substep, kept across steps for warm starting.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WarmImpulse {
    pub normal: f64,
    pub tangent: [f64; 2],
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SoftSolverSettings {
    pub substeps: u32,
    /// Stiffness of the contact spring, Hz (capped at a fifth of the substep rate).
    pub contact_hertz: f64,
    /// Damping ratio of the contact spring (>1: overdamped, no bounce from push-out).
    pub damping_ratio: f64,
    /// Fastest speed at which overlap is pushed out, m/s.
    pub max_push_out: f64,
    /// Approach speeds below this do not bounce (resting contacts), m/s.
    pub restitution_threshold: f64,
}

impl Default for SoftSolverSettings {
    fn default() -> Self {
        SoftSolverSettings {
            // A loaded contact settles by (load / effective mass)·g/ω²: 60 Hz keeps a stack of
            // ten boxes within 7 mm. Springs are capped at a fifth of the substep rate
            // (stiffer rings), 96 Hz for 8 substeps at dt = 1/60: 60 Hz is not cut.
            substeps: 8,
            contact_hertz: 60.0,
            damping_ratio: 10.0,
            max_push_out: 3.0,
            restitution_threshold: 1.0,
        }
    }
}

/// One side of a prepared contact point: where impulses act on that body.
#[derive(Clone, Copy, Debug, Default)]
struct Side {
    /// The lever arm r (contact point − centre of mass) in world axes, fixed for the step:
    /// an impulse J there turns the body by r × J, and the point moves at v + ω × r.
    lever: F64x4,
    /// I⁻¹ (r × d) for the normal and the tangents d, transposed like
    /// `PointConstraint::across` (zero where the body does not move). The point's speed
    /// along d from the turning, (r × d) · ω with ω = I⁻¹ A, is this · A (I⁻¹ is
    /// symmetric): one product with the momentum instead of deriving ω and crossing it with r,
    /// which made the longest chain of dependent operations in a pass longer.
    spins: [F64x4; 3],
    /// The point whose motion the separation follows as the bodies move in this step, in
    /// body axes, or for a body that does not move, in world axes. The contact point itself
    /// (the lever arm), except on a round surface, where it is the centre of the rounding
    /// (`Shape::round_core`): a ball rolling on a floor turns its material contact point up
    /// and away within the step, which read as the ball lifting off, and it sank 0.8 mm
    /// instead of 0.07 mm at 60 Hz. The sunk lever arm made it roll 0.03 % slow.
    anchor: F64x4,
}

/// What a side's impulses do while a contact is prepared: for the normal and the two
/// tangents d, the arm r × d and the spin I⁻¹ (r × d) that a unit impulse along d gives,
/// with the world inertia at step start (zero where the body does not move).
///
/// The arms and spins are held transposed, like `PointConstraint::across` (lane k of
/// `arms[c]` is component c of direction k's arm), so that the three directions are worked
/// on at once: the same operations glam's `cross`, matrix product and `dot` would do for
/// each, in the same order.
struct SideGeometry<V> {
    lever: DVec3,
    arms: [V; 3],
    spins: [V; 3],
    anchor: DVec3,
    /// From the contact point to the anchor at step start, world axes: zero but on a round
    /// surface.
    anchor_shift: DVec3,
}

impl<V: LaneVector> SideGeometry<V> {
    #[inline(always)]
    fn new<L: Lanes<Vector = V>>(
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
        // I⁻¹ (r × d) by columns: col x · arm.x + col y · arm.y + col z · arm.z.
        let m = body.inv_inertia_world;
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
    fn arm_dot_spin(&self) -> V {
        let (arms, spins) = (&self.arms, &self.spins);
        arms[0] * spins[0] + arms[1] * spins[1] + arms[2] * spins[2]
    }

    /// The normal's arm · spin_k for each direction k, in lane k.
    #[inline(always)]
    fn normal_arm_dot_spin(&self) -> V {
        let (arms, spins) = (&self.arms, &self.spins);
        spins[0] * arms[0].lane(0) + spins[1] * arms[1].lane(0) + spins[2] * arms[2].lane(0)
    }

    /// The anchor in world coordinates with the body at this pose.
    #[inline(always)]
    fn anchor_at(&self, slot: u32, position: DVec3, orientation: DMat3) -> DVec3 {
        if moves(slot) {
            position + orientation * self.anchor
        } else {
            self.anchor
        }
    }

    #[inline(always)]
    fn into_lanes(self) -> Side {
        Side {
            lever: F64x4::from_vec3(self.lever),
            spins: [
                self.spins[0].store(),
                self.spins[1].store(),
                self.spins[2].store(),
            ],
            anchor: F64x4::from_vec3(self.anchor),
        }
    }
}

impl Side {
    /// The speeds along the three directions (in lanes) that the body's turning gives its
    /// material point at the contact (see `spins`).
    #[inline(always)]
    fn turning_speeds<L: Lanes>(&self, l: L, body: &SolverBody) -> L::Vector {
        let a = body.angular_momentum;
        let [x, y, z] = load3(l, &self.spins);
        x * a.lane(0) + y * a.lane(1) + z * a.lane(2)
    }

    #[inline(always)]
    fn anchor_in_world<L: Lanes>(&self, l: L, bodies: &SharedBodies, slot: u32) -> L::Vector {
        if !moves(slot) {
            return l.load(self.anchor); // without reading the slot: this runs every pass
        }
        let body = bodies.get(slot);
        let [x, y, z] = load3(l, &body.orientation);
        let anchor = self.anchor;
        l.load(body.position) + (x * anchor.lane(0) + y * anchor.lane(1) + z * anchor.lane(2))
    }
}

/// Three stored lanes, loaded (written out: an array's `map` is not always inlined, and
/// would then run without the packed instructions).
#[inline(always)]
fn load3<L: Lanes>(l: L, stored: &[F64x4; 3]) -> [L::Vector; 3] {
    [l.load(stored[0]), l.load(stored[1]), l.load(stored[2])]
}

/// The body's inverse mass as the impulses see it: zero when it does not move.
#[inline(always)]
fn inv_mass(body: &RigidBody, slot: u32) -> f64 {
    if moves(slot) { body.inv_mass } else { 0.0 }
}

fn moves(slot: u32) -> bool {
    slot != FIXED_SLOT
}

/// One prepared contact point. Its directions are the normal (from a to b), then the two
/// tangents; the arms stay fixed for the step: impulses act where the bodies touch, not
/// where that material point has rotated to (a rolling ball keeps pushing at its bottom).
///
/// A pass streams the constraints through memory, so only what shortens a point's solve is
/// stored: the spins that give the speeds from the momenta (`Side::spins`); the turning an
/// impulse gives is derived from the levers. The fields are laid out in the order a pass
/// reads them, so that the processor's prefetcher sees one forward stream.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
struct PointConstraint {
    /// The solver slots of a and b.
    slots: [u32; 2],
    /// Whether the next contact in the pass shares no moving body with this one, so that
    /// the two may be solved side by side (`solve_two`).
    pairs_with_next: bool,
    impulse: WarmImpulse,
    /// The separation at the bodies' current poses. Poses only change between a substep's
    /// biased pass and its relax pass, so the relax pass measures it and the next
    /// substep's biased pass and the restitution pass read it.
    separation: f64,
    normal_mass: f64,
    tangent_mass: [f64; 2],
    /// What a unit normal impulse adds to the relative speed along each tangent (zero for
    /// point masses; the lever arms couple them). The friction solve after the normal
    /// solve reads the tangent speeds through it instead of from the bodies again, so that
    /// each contact reads and writes its two bodies once per pass.
    normal_to_tangent: [f64; 2],
    friction: f64,
    max_normal_impulse: f64,
    /// Relative normal acceleration from the environmental forces, for the impact speed.
    approach_acceleration: f64,
    /// The fastest approach the pair can reach in this step on its own (`fastest_approach`).
    /// A neighbour solved
    /// earlier in the same pass can push the bodies together faster; that momentum is the
    /// neighbour's contact's business, and bouncing it here too would add energy (a ball
    /// pressed onto a pin by another gained 6 % of its energy in one step when the
    /// ball–ball contact happened to be solved first).
    fastest_approach: f64,
    /// Normal relative velocity at impact, as the speed of the discrete arc (see
    /// `rebound_speed`); before the step until the contact first pushes. What restitution
    /// reflects.
    approach_speed: f64,
    restitution: f64,
    /// Separation = normal · (world anchor b − world anchor a) + separation_offset.
    separation_offset: f64,
    /// The same transposed (lane k of `across[c]` is component c of direction k), to take
    /// the speeds along all three at once.
    across: [F64x4; 3],
    a: Side,
    b: Side,
    /// The normal and the tangents, each as a vector: the impulses' directions.
    directions: [F64x4; 3],
}

impl PointConstraint {
    fn normal(&self) -> DVec3 {
        self.directions[0].to_vec3()
    }

    /// The relative speeds of b's material point over a's along the normal and both
    /// tangents.
    #[inline(always)]
    fn speeds<L: Lanes>(&self, l: L, bodies: &SharedBodies) -> [f64; 3] {
        let [slot_a, slot_b] = self.slots;
        let (a, b) = (bodies.get(slot_a), bodies.get(slot_b));
        let relative =
            l.load(b.linear_momentum) * b.inv_mass - l.load(a.linear_momentum) * a.inv_mass;
        let [x, y, z] = load3(l, &self.across);
        let sliding = x * relative.lane(0) + y * relative.lane(1) + z * relative.lane(2);
        let speeds = sliding + (self.b.turning_speeds(l, b) - self.a.turning_speeds(l, a));
        [speeds.lane(0), speeds.lane(1), speeds.lane(2)]
    }

    /// The impulse Σ λ d of impulses λ along the three directions.
    #[inline(always)]
    fn along_directions<L: Lanes>(&self, l: L, lambda: [f64; 3]) -> L::Vector {
        let [n, t1, t2] = load3(l, &self.directions);
        n * lambda[0] + t1 * lambda[1] + t2 * lambda[2]
    }

    /// Impulses λ along the three directions: +Σ λ d to b, −Σ λ d to a, at their levers.
    #[inline(always)]
    fn apply<L: Lanes>(&self, l: L, bodies: &SharedBodies, lambda: [f64; 3]) {
        let [to_a, to_b] = self.on_each_body(l, self.along_directions(l, lambda));
        bodies.add(l, to_a);
        bodies.add(l, to_b);
    }

    /// A normal impulse only.
    fn apply_normal<L: Lanes>(&self, l: L, bodies: &SharedBodies, lambda: f64) {
        let [to_a, to_b] = self.on_each_body(l, l.load(self.directions[0]) * lambda);
        bodies.add(l, to_a);
        bodies.add(l, to_b);
    }

    /// Adds the impulse the contact holds to its bodies' next warm start.
    #[inline(always)]
    fn add_to_warm_start<L: Lanes>(&self, l: L, bodies: &SharedBodies) {
        let [tangent_1, tangent_2] = self.impulse.tangent;
        let linear = self.along_directions(l, [self.impulse.normal, tangent_1, tangent_2]);
        let [to_a, to_b] = self.on_each_body(l, linear);
        bodies.add_warm_start(l, to_a);
        bodies.add_warm_start(l, to_b);
    }

    /// The impulse J to b and −J to a, each at its lever. (Returned rather than handed to a
    /// closure: a closure is compiled without the packed instructions, and was left out of
    /// line once it called them.)
    #[inline(always)]
    fn on_each_body<L: Lanes>(&self, l: L, linear: L::Vector) -> [Push<L::Vector>; 2] {
        let [slot_a, slot_b] = self.slots;
        [
            Push {
                slot: slot_a,
                linear: -linear,
                angular: -l.load(self.a.lever).cross(linear),
            },
            Push {
                slot: slot_b,
                linear,
                angular: l.load(self.b.lever).cross(linear),
            },
        ]
    }

    /// The next point of the same manifold (or of one between the same two bodies).
    fn same_bodies(&self, other: &PointConstraint) -> bool {
        self.slots == other.slots
    }
}

/// The stiffest contact spring a substep of length h can carry is this many times 1/h.
/// At a quarter the C10 pyramid never settled at 4 or 5 substeps (it rang, never slept and
/// drifted 33 to 40 mm); at a fifth it sleeps within a second at both, drifting 18 and 13 mm.
const MAX_HERTZ_PER_SUBSTEP_RATE: f64 = 0.2;

/// Spring coefficients of a soft constraint for one substep.
#[derive(Clone, Copy, Debug)]
struct Softness {
    bias_rate: f64,
    mass_scale: f64,
    impulse_scale: f64,
}

impl Softness {
    fn new(hertz: f64, damping_ratio: f64, h: f64) -> Self {
        let omega = 2.0 * std::f64::consts::PI * hertz;
        let a1 = 2.0 * damping_ratio + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        Softness {
            bias_rate: omega / a1,
            mass_scale: a2 * a3,
            impulse_scale: a3,
        }
    }
}

/// Everything one soft step needs besides the bodies and contacts.
pub struct StepContext<'a> {
    pub forces: &'a [EnvironmentForce],
    pub integrator: Integrator,
    pub settings: &'a SoftSolverSettings,
    pub dt: f64,
    /// Whether to measure `SoftStep::integrate_seconds` (it reads the clock per substep).
    pub timed: bool,
}

/// What a soft step hands back.
pub struct SoftStep {
    /// Seconds spent on forces and integration, over all substeps (for the stage profile);
    /// 0 unless the step was `timed`.
    pub integrate_seconds: f64,
}

/// Buffers a soft step keeps for the next one, so that stepping allocates nothing once
/// they have grown to the scene.
#[derive(Clone, Debug, Default)]
pub struct SoftScratch {
    /// In colour order (see `contact_colors`).
    constraints: Vec<PointConstraint>,
    colors: ContactColors,
    user_forces: Vec<(DVec3, DVec3)>,
    /// Each slot's body's motion at step start.
    motions: Vec<SlotMotion>,
    bodies: SolverBodies,
}

impl SoftScratch {
    /// The impulses each contact ended the last step with (in the order of its contacts),
    /// for warm starting.
    pub fn impulses(&self) -> impl Iterator<Item = WarmImpulse> + '_ {
        let constraints = &self.constraints;
        (self.colors.position_of.iter()).map(move |&k| constraints[k as usize].impulse)
    }
}

/// Advances the `awake` bodies (ascending indices into `bodies`) by one step of `ctx.dt` with
/// the given contacts. No other body is visited.
///
/// Compiled a second time for processors with AVX2, as the passes are (`run_pass`): the
/// preparation of the contacts is plain vector arithmetic that the wider instructions
/// carry with fewer moves between registers. Both compute the same bits: neither fuses a
/// multiply with an add.
pub fn step(
    bodies: &mut [RigidBody],
    awake: &[u32],
    contacts: &[ContactInput],
    ctx: &StepContext,
    scratch: &mut SoftScratch,
) -> SoftStep {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx) = Avx2::detect() {
        // SAFETY: the processor has AVX2, as `avx` proves.
        return unsafe { step_avx2(avx, bodies, awake, contacts, ctx, scratch) };
    }
    step_inline(Portable, bodies, awake, contacts, ctx, scratch)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn step_avx2(
    avx: Avx2,
    bodies: &mut [RigidBody],
    awake: &[u32],
    contacts: &[ContactInput],
    ctx: &StepContext,
    scratch: &mut SoftScratch,
) -> SoftStep {
    step_inline(avx, bodies, awake, contacts, ctx, scratch)
}

/// The body of `step`, compiled into each of its variants.
#[inline(always)]
fn step_inline<L: Lanes>(
    l: L,
    bodies: &mut [RigidBody],
    awake: &[u32],
    contacts: &[ContactInput],
    ctx: &StepContext,
    scratch: &mut SoftScratch,
) -> SoftStep {
    let SoftScratch {
        constraints,
        colors,
        user_forces,
        motions,
        bodies: slots,
    } = scratch;
    slots.assign(bodies, awake);
    let contact_slots = contacts
        .iter()
        .map(|c| [slots.slot_of(c.a), slots.slot_of(c.b)]);
    colors.assign(contact_slots, slots.count(), FIXED_SLOT);
    SlotMotion::gather(motions, bodies, awake, ctx.forces);
    // Written in place: collecting would build each (large) constraint aside and copy it.
    constraints.resize(colors.order.len(), PointConstraint::default());
    // A manifold's points share their normal, and so their tangents: taken in contact order,
    // where they are neighbours.
    let mut basis = (DVec3::NAN, [DVec3::NAN; 2]);
    for (contact, &position) in contacts.iter().zip(&colors.position_of) {
        let constraint = &mut constraints[position as usize];
        if contact.normal != basis.0 {
            basis = (contact.normal, tangent_basis(contact.normal));
        }
        *constraint = prepare(l, bodies, slots, contact, basis.1, motions, ctx.dt);
    }
    mark_pairs(constraints);
    let shared = SharedBodies::new(&mut slots.slots);
    for constraint in constraints.iter() {
        constraint.add_to_warm_start(l, &shared);
    }
    let substeps = ctx.settings.substeps.max(1);
    let h = ctx.dt / substeps as f64;
    let hertz = ctx
        .settings
        .contact_hertz
        .min(MAX_HERTZ_PER_SUBSTEP_RATE / h);
    let softness = Softness::new(hertz, ctx.settings.damping_ratio, h);
    // Forces the user applied before the step act over all of it, like the environment's.
    user_forces.clear();
    user_forces.extend(
        awake
            .iter()
            .map(|&i| (bodies[i as usize].force, bodies[i as usize].torque)),
    );
    let mut integrate_seconds = 0.0;
    let biased = Pass::Biased {
        softness,
        max_push_out: ctx.settings.max_push_out,
    };
    for substep in 0..substeps {
        let mut clock = Stopwatch::start(ctx.timed);
        slots.kick_and_warm_start(bodies, |k, body| {
            (body.force, body.torque) = user_forces[k];
            forces::apply_environment(ctx.forces, body);
            integrate::integrate_momenta(body, h);
        });
        integrate_seconds += clock.lap();
        for_each_contact(&mut slots.slots, constraints, colors, biased, h);
        clock.lap();
        slots.drift(bodies, |body| {
            integrate::integrate_pose(body, h, ctx.integrator)
        });
        integrate_seconds += clock.lap();
        for_each_contact(&mut slots.slots, constraints, colors, Pass::Relax, h);
        slots.end_substep(bodies, substep + 1 < substeps);
    }
    // One pass, in contact order rather than colour order, on one thread. A body bouncing
    // off two things in one step gets both rebounds one after the other, and the second
    // changes the first's outgoing speed: the order decides how much energy that adds. In
    // colour order the pachinko soak saw a ball gain 6 % of its energy in one step (1e-4 of
    // the scene's); in contact order it never gains. A single pass is cheap to keep serial.
    let threshold = ctx.settings.restitution_threshold;
    let shared = SharedBodies::new(&mut slots.slots);
    for &k in &colors.position_of {
        apply_restitution(&shared, &mut constraints[k as usize], threshold, h);
    }
    slots.scatter(bodies);
    slots.release();
    for &index in awake {
        bodies[index as usize].clear_accumulators();
    }
    SoftStep { integrate_seconds }
}

/// What the preparation reads of a moving body, computed once per body rather than at each
/// of its contact points.
#[derive(Clone, Copy, Debug, Default)]
struct SlotMotion {
    /// The environment's acceleration at step start.
    acceleration: DVec3,
    velocity: DVec3,
    angular_velocity: DVec3,
}

impl SlotMotion {
    /// Into `motions`, slot by slot: the fixed slot, then the `awake` bodies in slot order.
    fn gather(
        motions: &mut Vec<SlotMotion>,
        bodies: &[RigidBody],
        awake: &[u32],
        forces: &[EnvironmentForce],
    ) {
        motions.clear();
        // The fixed slot: nothing that does not move accelerates (its velocities are not read).
        motions.push(SlotMotion::default());
        motions.extend((awake.iter()).map(|&i| SlotMotion::of(&bodies[i as usize], forces)));
    }

    fn of(body: &RigidBody, forces: &[EnvironmentForce]) -> Self {
        SlotMotion {
            acceleration: environment_acceleration(body, forces),
            velocity: body.velocity(),
            angular_velocity: body.angular_velocity(),
        }
    }
}

fn environment_acceleration(body: &RigidBody, forces: &[EnvironmentForce]) -> DVec3 {
    if !body.is_awake() {
        return DVec3::ZERO;
    }
    forces.iter().map(|f| f.force_on(body)).sum::<DVec3>() * body.inv_mass
}

/// Velocity at step start of the material point at `lever` from the body's centre of mass
/// (the passes take theirs from the momenta: `PointConstraint::speeds`).
#[inline(always)]
fn velocity_at_start(body: &RigidBody, slot: u32, motions: &[SlotMotion], lever: DVec3) -> DVec3 {
    if moves(slot) {
        let motion = &motions[slot as usize];
        motion.velocity + motion.angular_velocity.cross(lever)
    } else {
        body.velocity() + body.angular_velocity().cross(lever)
    }
}

/// Speed at which two surfaces `gap` apart, closing at `speed` (< 0) under a constant
/// relative `acceleration`, actually meet: −√(v² − 2 a s) when accelerating toward contact.
#[inline(always)]
fn impact_speed(speed: f64, acceleration: f64, gap: f64) -> f64 {
    if gap > 0.0 && acceleration < 0.0 {
        -(speed * speed - 2.0 * acceleration * gap).sqrt()
    } else {
        speed
    }
}

/// The constraint of one contact point, whose normal has the tangents `[t1, t2]`.
#[inline(always)]
fn prepare<L: Lanes>(
    l: L,
    bodies: &[RigidBody],
    slots: &SolverBodies,
    contact: &ContactInput,
    [t1, t2]: [DVec3; 2],
    motions: &[SlotMotion],
    dt: f64,
) -> PointConstraint {
    let (a, b) = (&bodies[contact.a], &bodies[contact.b]);
    let normal = contact.normal;
    let directions = [normal, t1, t2];
    let (r_a, r_b) = (contact.point - a.position, contact.point - b.position);
    let (slot_a, slot_b) = (slots.slot_of(contact.a), slots.slot_of(contact.b));
    let relative_velocity =
        velocity_at_start(b, slot_b, motions, r_b) - velocity_at_start(a, slot_a, motions, r_a);
    let approach_speed = normal.dot(relative_velocity);
    let acceleration = |slot: u32| motions[slot as usize].acceleration;
    let approach_acceleration = normal.dot(acceleration(slot_b) - acceleration(slot_a));
    let across = F64x4::transpose(directions);
    let side_a = SideGeometry::new(l, a, slot_a, r_a, &across);
    let side_b = SideGeometry::new(l, b, slot_b, r_b, &across);
    let separation_offset = contact.separation
        - normal.dot(r_b - r_a + b.position - a.position)
        - normal.dot(side_b.anchor_shift - side_a.anchor_shift);
    let (anchor_a, anchor_b) = (
        side_a.anchor_at(slot_a, a.position, a.orientation),
        side_b.anchor_at(slot_b, b.position, b.orientation),
    );
    let inv_masses = inv_mass(a, slot_a) + inv_mass(b, slot_b);
    let [normal_mass, tangent_1, tangent_2] = effective_masses(l, &side_a, &side_b, inv_masses);
    PointConstraint {
        pairs_with_next: false,
        separation: normal.dot(anchor_b - anchor_a) + separation_offset,
        normal_to_tangent: normal_to_tangent(l, &side_a, &side_b, inv_masses, &across),
        a: side_a.into_lanes(),
        b: side_b.into_lanes(),
        directions: F64x4::from_vec3s(directions),
        across,
        slots: [slot_a, slot_b],
        separation_offset,
        normal_mass,
        tangent_mass: [tangent_1, tangent_2],
        impulse: contact.warm_impulse,
        max_normal_impulse: 0.0,
        approach_speed,
        fastest_approach: fastest_approach(approach_speed, approach_acceleration, contact, dt),
        approach_acceleration,
        friction: (a.material.friction * b.material.friction).sqrt(),
        restitution: a.material.restitution.min(b.material.restitution),
    }
}

/// The mass an impulse along each direction meets: the inverse of the report's denominator
/// 1/mA + 1/mB + (rA × d)·IA⁻¹(rA × d) + (rB × d)·IB⁻¹(rB × d), from the arms and spins the
/// sides hold (`inv_masses` is 1/mA + 1/mB). A body that does not move in this step counts
/// as immovable, as the impulses treat it.
#[inline(always)]
fn effective_masses<L: Lanes>(
    l: L,
    a: &SideGeometry<L::Vector>,
    b: &SideGeometry<L::Vector>,
    inv_masses: f64,
) -> [f64; 3] {
    let inverse = (l.load(F64x4::splat(inv_masses)) + a.arm_dot_spin() + b.arm_dot_spin()).store();
    let mass = |k: usize| {
        let inverse = inverse.lane(k);
        if inverse > 0.0 { 1.0 / inverse } else { 0.0 }
    };
    [mass(0), mass(1), mass(2)]
}

/// `PointConstraint::normal_to_tangent`: the relative speed along each tangent that a unit
/// normal impulse adds.
#[inline(always)]
fn normal_to_tangent<L: Lanes>(
    l: L,
    a: &SideGeometry<L::Vector>,
    b: &SideGeometry<L::Vector>,
    inv_masses: f64,
    across: &[F64x4; 3],
) -> [f64; 2] {
    // d_k · n for each direction k, then the arms' share.
    let n = [across[0].lane(0), across[1].lane(0), across[2].lane(0)];
    let [x, y, z] = load3(l, across);
    let along_normal = x * n[0] + y * n[1] + z * n[2];
    let coupling =
        (along_normal * inv_masses + a.normal_arm_dot_spin() + b.normal_arm_dot_spin()).store();
    [coupling.lane(1), coupling.lane(2)]
}

/// Contacts in a colour that make it worth spreading over the threads.
const PARALLEL_MIN_CONTACTS: usize = 128;

/// One pass of a substep over the contacts.
///
/// Each substep starts by applying the impulses the contacts hold (the warm start). That
/// needs no pass of its own: once the relax pass has solved every contact, what each body's
/// momenta gained since the warm start is the sum of its contacts' final impulses, the next
/// substep's warm start (`SolverBodies::end_substep`); `step` gathers the first from
/// the impulses remembered from the last step. A pass over the contacts streams them all
/// through memory; a pass over the bodies is far smaller.
#[derive(Clone, Copy)]
enum Pass {
    /// Solves with the soft position bias.
    Biased {
        softness: Softness,
        max_push_out: f64,
    },
    /// Measures the separations at the poses the substep moved to, then solves without
    /// bias, removing the velocity the bias added.
    Relax,
}

/// Runs `pass` on every contact, colour by colour (see `contact_colors`). A colour large
/// enough is spread over the threads, a manifold per task; the result is the same to the
/// last bit, as its manifolds share no moving body.
fn for_each_contact(
    bodies: &mut [SolverBody],
    constraints: &mut [PointConstraint],
    colors: &ContactColors,
    pass: Pass,
    h: f64,
) {
    let shared = SharedBodies::new(bodies);
    let threads = rayon::current_num_threads();
    for (range, parallel) in colors.ranges() {
        let color = &mut constraints[range];
        if parallel && threads > 1 && color.len() >= PARALLEL_MIN_CONTACTS {
            color
                .par_chunk_by_mut(PointConstraint::same_bodies)
                .for_each(|manifold| run_pass(pass, &shared, manifold, h));
        } else {
            run_pass(pass, &shared, color, h);
        }
    }
}

/// `pass` on these contacts in order, with the lanes (see `lanes`) packed four to an
/// instruction where the processor has AVX2, and as the compiler packs them otherwise. Both
/// compute the same bits.
fn run_pass(pass: Pass, bodies: &SharedBodies, contacts: &mut [PointConstraint], h: f64) {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx) = Avx2::detect() {
        // SAFETY: the processor has AVX2, as `avx` proves.
        return unsafe { run_pass_avx2(avx, pass, bodies, contacts, h) };
    }
    run_pass_inline(Portable, pass, bodies, contacts, h);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_pass_avx2(
    avx: Avx2,
    pass: Pass,
    bodies: &SharedBodies,
    contacts: &mut [PointConstraint],
    h: f64,
) {
    run_pass_inline(avx, pass, bodies, contacts, h);
}

/// The body of `run_pass`, compiled into each of its variants.
#[inline(always)]
fn run_pass_inline<L: Lanes>(
    l: L,
    pass: Pass,
    bodies: &SharedBodies,
    contacts: &mut [PointConstraint],
    h: f64,
) {
    // Plain loops: an iterator adaptor's closure may be left out of line, and would then be
    // compiled without the variant's instructions.
    let bias = match pass {
        Pass::Biased {
            softness,
            max_push_out,
        } => Some((softness, max_push_out)),
        Pass::Relax => None,
    };
    let relax = bias.is_none();
    let mut k = 0;
    while k < contacts.len() {
        let paired = contacts[k].pairs_with_next && k + 1 < contacts.len();
        let group = &mut contacts[k..k + 1 + paired as usize];
        k += group.len();
        if relax {
            for c in group.iter_mut() {
                c.separation = current_separation(l, bodies, c);
            }
        }
        match group {
            [first, second] => solve_two(l, bodies, [first, second], h, bias),
            [only] => solve(l, bodies, only, h, bias),
            _ => unreachable!("a group is one contact or two"),
        }
    }
}

/// Sets `pairs_with_next` on contacts in pass order.
fn mark_pairs(constraints: &mut [PointConstraint]) {
    for k in 1..constraints.len() {
        let independent = independent(&constraints[k - 1], &constraints[k]);
        constraints[k - 1].pairs_with_next = independent;
    }
}

/// Whether two contacts share no moving body, so that either may be solved first.
#[inline(always)]
fn independent(x: &PointConstraint, y: &PointConstraint) -> bool {
    x.slots
        .iter()
        .all(|&slot| !moves(slot) || !y.slots.contains(&slot))
}

/// `solve` on two independent contacts, step by step side by side, so that the processor
/// works on both chains of dependent operations at once.
#[inline(always)]
fn solve_two<L: Lanes>(
    l: L,
    bodies: &SharedBodies,
    [x, y]: [&mut PointConstraint; 2],
    h: f64,
    bias: Option<(Softness, f64)>,
) {
    let (speeds_x, speeds_y) = (x.speeds(l, bodies), y.speeds(l, bodies));
    let normal_x = solve_normal(x, speeds_x[0], h, bias);
    let normal_y = solve_normal(y, speeds_y[0], h, bias);
    let friction_x = solve_friction(x, tangent_speeds(x, speeds_x, normal_x));
    let friction_y = solve_friction(y, tangent_speeds(y, speeds_y, normal_y));
    x.apply(l, bodies, [normal_x, friction_x[0], friction_x[1]]);
    y.apply(l, bodies, [normal_y, friction_y[0], friction_y[1]]);
}

/// The fastest the pair can be closing when it meets in this step with no other contact
/// pushing it: falling the whole gap from its speed at step start under the environment's
/// acceleration |a|, −√(v² + 2|a|s), plus |a|·dt of slack for the discrete arc's offsets.
#[inline(always)]
fn fastest_approach(speed: f64, acceleration: f64, contact: &ContactInput, dt: f64) -> f64 {
    let closing = speed.min(0.0);
    let gap = contact.separation.max(0.0);
    let fall = (closing * closing + 2.0 * acceleration.abs() * gap).sqrt();
    -fall - acceleration.abs() * dt
}

/// Current separation: the anchors carried along by the bodies' motion in this step.
#[inline(always)]
fn current_separation<L: Lanes>(l: L, bodies: &SharedBodies, c: &PointConstraint) -> f64 {
    let [slot_a, slot_b] = c.slots;
    let (anchor_a, anchor_b) = (
        c.a.anchor_in_world(l, bodies, slot_a),
        c.b.anchor_in_world(l, bodies, slot_b),
    );
    (anchor_b - anchor_a).dot3(c.normal()) + c.separation_offset
}

/// One contact's share of a pass: normal (soft or rigid) then friction, applied together.
/// `bias` is the softness and push-out cap when solving with position bias, None to relax.
#[inline(always)]
fn solve<L: Lanes>(
    l: L,
    bodies: &SharedBodies,
    c: &mut PointConstraint,
    h: f64,
    bias: Option<(Softness, f64)>,
) {
    let speeds = c.speeds(l, bodies);
    let normal = solve_normal(c, speeds[0], h, bias);
    let [t1, t2] = solve_friction(c, tangent_speeds(c, speeds, normal));
    c.apply(l, bodies, [normal, t1, t2]);
}

/// The speeds along the tangents once the normal impulse `normal` is added.
#[inline(always)]
fn tangent_speeds(c: &PointConstraint, speeds: [f64; 3], normal: f64) -> [f64; 2] {
    // Skipped when no normal impulse is added: on an absurd contact (a body flung 1e298 m
    // away) the coupling overflows, and 0 · ∞ would poison the friction of the other body.
    if normal == 0.0 {
        [speeds[1], speeds[2]]
    } else {
        [
            speeds[1] + c.normal_to_tangent[0] * normal,
            speeds[2] + c.normal_to_tangent[1] * normal,
        ]
    }
}

/// The normal impulse this pass adds, at the relative normal speed `normal_speed`.
#[inline(always)]
fn solve_normal(
    c: &mut PointConstraint,
    normal_speed: f64,
    h: f64,
    bias: Option<(Softness, f64)>,
) -> f64 {
    let separation = c.separation;
    let (velocity_bias, mass_scale, impulse_scale) = if separation > 0.0 {
        // Speculative: allow the gap to close within this substep, no further.
        (separation / h, 1.0, 0.0)
    } else if let Some((soft, max_push_out)) = bias {
        (
            at_least(soft.bias_rate * separation, -max_push_out),
            soft.mass_scale,
            soft.impulse_scale,
        )
    } else {
        (0.0, 1.0, 0.0)
    };
    let delta = -c.normal_mass * mass_scale * (normal_speed + velocity_bias)
        - impulse_scale * c.impulse.normal;
    let accumulated = at_least(c.impulse.normal + delta, 0.0);
    let applied = accumulated - c.impulse.normal;
    if c.max_normal_impulse == 0.0 && applied > 0.0 {
        // The contact closes now. Restitution must reflect the speed at which the surfaces
        // meet: the speed at step start misses up to g·dt of fall, and the gap that is
        // still open would have been crossed while accelerating. The velocity holds this
        // substep's kick; the bodies are where the substep started before the drift and
        // where it ended after (the relax pass), which sets the arc speed there.
        let a = c.approach_acceleration;
        let arc_speed = normal_speed + if bias.is_some() { -0.5 } else { 0.5 } * a * h;
        c.approach_speed = impact_speed(arc_speed, a, separation).max(c.fastest_approach);
    }
    c.impulse.normal = accumulated;
    c.max_normal_impulse = at_least(applied, c.max_normal_impulse);
    applied
}

/// `x.max(floor)` for a floor that is a number (a NaN x gives the floor, as with `max`), in one
/// comparison: `f64::max` also has to handle a NaN floor, which costs three more
/// instructions on the solver's hottest path.
#[inline(always)]
fn at_least(x: f64, floor: f64) -> f64 {
    if x > floor { x } else { floor }
}

/// Coulomb friction: the tangential impulse stays inside the disc of radius μ·λn. Returns
/// the impulses this pass adds along the tangents.
#[inline(always)]
fn solve_friction(c: &mut PointConstraint, speeds: [f64; 2]) -> [f64; 2] {
    let limit = c.friction * c.impulse.normal;
    let unclamped = [
        c.impulse.tangent[0] - c.tangent_mass[0] * speeds[0],
        c.impulse.tangent[1] - c.tangent_mass[1] * speeds[1],
    ];
    let accumulated = clamp_to_friction_disc(unclamped, limit);
    let applied = [
        accumulated[0] - c.impulse.tangent[0],
        accumulated[1] - c.impulse.tangent[1],
    ];
    c.impulse.tangent = accumulated;
    applied
}

/// Newton's restitution on contacts that were approaching faster than the threshold: the
/// outgoing normal speed becomes ε times the approach speed, as `rebound_speed` reads it
/// for the substeps of length `h`.
fn apply_restitution(bodies: &SharedBodies, c: &mut PointConstraint, threshold: f64, h: f64) {
    if c.restitution == 0.0 || c.approach_speed > -threshold || c.max_normal_impulse == 0.0 {
        return;
    }
    let gap = c.separation.max(0.0);
    let [normal_speed, _, _] = c.speeds(Portable, bodies);
    let delta = -c.normal_mass * (normal_speed - rebound_speed(c, gap, h));
    let accumulated = (c.impulse.normal + delta).max(0.0);
    let applied = accumulated - c.impulse.normal;
    c.impulse.normal = accumulated;
    c.apply_normal(Portable, bodies, applied);
}

/// The normal speed a bounce leaves with, `gap` apart, under the relative acceleration a.
///
/// A substep (kick v += a h, then drift x += v h) conserves ½ (v + ½ a h)² − a·x exactly
/// under a constant a, x the position after the drift and v the velocity it drifted with:
/// the discrete arc rises and falls with the speed w = v + ½ a h, not v. The law is applied
/// to w, w_out = −ε w_in (the approach speed is kept as w); reflecting v instead would lose
/// (1 + ε)·½|a|h of launch speed at every bounce (C2 apexes 3.7 % low by bounce 3 at 8
/// substeps). The bodies leave from the end of the step, so v_out = w_out − ½ a h.
///
/// The speculative contact may stop the bodies short of each other: the last substep then
/// leaves a gap the next step would close. The rebound gets the speed it has at that gap,
/// √(w_out² + 2 a s) as `impact_speed` mirrored; leaving at the impact speed from above the
/// surface would add |a|·s of height.
fn rebound_speed(c: &PointConstraint, gap: f64, h: f64) -> f64 {
    let a = c.approach_acceleration;
    let at_surface = -c.restitution * c.approach_speed;
    let at_gap = if a < 0.0 {
        (at_surface * at_surface + 2.0 * a * gap).max(0.0).sqrt()
    } else {
        at_surface
    };
    at_gap - 0.5 * a * h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::dynamics::body::BodyDesc;
    use crate::physics::geometry::shape::Shape;
    use glam::DQuat;

    /// Two turning, moving boxes on a fixed one, with contacts at skew points and
    /// remembered impulses, prepared as a step would.
    fn scene() -> (Vec<RigidBody>, SolverBodies, Vec<PointConstraint>) {
        scene_prepared_with(Portable)
    }

    fn scene_prepared_with<L: Lanes>(l: L) -> (Vec<RigidBody>, SolverBodies, Vec<PointConstraint>) {
        let cuboid = |h: f64| Shape::cuboid(DVec3::new(h, 0.7 * h, 1.3 * h));
        let descs = [
            BodyDesc::fixed(cuboid(5.0)).at(DVec3::new(0.0, -3.5, 0.0)),
            BodyDesc::dynamic(cuboid(0.5))
                .rotated(DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.2, 0.7))
                .with_velocity(DVec3::new(0.4, -1.1, 0.2))
                .with_angular_velocity(DVec3::new(1.3, 0.2, -0.9)),
            BodyDesc::dynamic(cuboid(0.3))
                .at(DVec3::new(0.2, 0.9, -0.1))
                .rotated(DQuat::from_euler(glam::EulerRot::XYZ, -0.5, 0.1, 0.2))
                .with_velocity(DVec3::new(-0.3, 0.5, 0.1))
                .with_angular_velocity(DVec3::new(-0.2, 2.1, 0.4)),
        ];
        let bodies: Vec<RigidBody> = descs
            .iter()
            .map(|d| RigidBody::from_desc(d).expect("valid"))
            .collect();
        let mut slots = SolverBodies::default();
        slots.assign(&bodies, &[1, 2]);
        let contact = |a: usize, b: usize, k: f64| ContactInput {
            a,
            b,
            point: DVec3::new(0.1 * k, 0.3 - 0.2 * k, -0.05 * k),
            normal: DVec3::new(0.1, 1.0, -0.2 * k).normalize(),
            separation: 0.01 - 0.004 * k,
            warm_impulse: WarmImpulse {
                normal: 0.8 * k,
                tangent: [0.1 * k, -0.05],
            },
        };
        // The first two share no moving body: a pass solves them side by side.
        let contacts = [
            contact(0, 1, 1.0),
            contact(0, 2, 4.0),
            contact(0, 1, 2.0),
            contact(1, 2, 3.0),
        ];
        let mut motions = Vec::new();
        SlotMotion::gather(&mut motions, &bodies, &[1, 2], &[]);
        let mut constraints = (contacts.iter())
            .map(|c| {
                prepare(
                    l,
                    &bodies,
                    &slots,
                    c,
                    tangent_basis(c.normal),
                    &motions,
                    1.0 / 60.0,
                )
            })
            .collect::<Vec<_>>();
        mark_pairs(&mut constraints);
        assert!(constraints[0].pairs_with_next && !constraints[2].pairs_with_next);
        (bodies, slots, constraints)
    }

    /// The warm start gathered from the change in momenta is what adding up every contact's
    /// final impulse gives (the sum the relax pass used to build contact by contact).
    #[test]
    fn gathered_warm_start_is_the_sum_of_the_final_impulses() {
        let (mut bodies, mut slots, mut constraints) = scene();
        let h = 1.0 / 480.0;
        let shared = SharedBodies::new(&mut slots.slots);
        for c in &constraints {
            c.add_to_warm_start(Portable, &shared);
        }
        slots.kick_and_warm_start(&mut bodies, |_, _| {});
        let biased = Pass::Biased {
            softness: Softness::new(60.0, 10.0, h),
            max_push_out: 3.0,
        };
        for pass in [biased, Pass::Relax] {
            run_pass_inline(
                Portable,
                pass,
                &SharedBodies::new(&mut slots.slots),
                &mut constraints,
                h,
            );
        }
        slots.end_substep(&mut bodies, true);
        let mut summed = slots.clone();
        for slot in &mut summed.slots {
            slot.warm_start = [F64x4::ZERO; 2];
        }
        let shared = SharedBodies::new(&mut summed.slots);
        for c in &constraints {
            c.add_to_warm_start(Portable, &shared);
        }
        let mut pushed = 0.0;
        for (gathered, summed) in slots.slots[1..].iter().zip(&summed.slots[1..]) {
            for k in 0..2 {
                let (x, y) = (
                    gathered.warm_start[k].to_vec3(),
                    summed.warm_start[k].to_vec3(),
                );
                // Round-off of two sums of a few terms of order 10.
                assert!(
                    x.distance(y) < 1e-12 * (1.0 + y.length()),
                    "{x} against {y}"
                );
                pushed += y.length();
            }
        }
        assert!(pushed > 1.0, "the contacts push: {pushed}");
    }

    #[test]
    fn packed_and_unpacked_preparation_compute_the_same_bits() {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = Avx2::detect() {
            let (_, _, portable) = scene();
            let (_, _, packed) = scene_prepared_with(avx);
            for (x, y) in portable.iter().zip(&packed) {
                // Debug prints each number exactly (shortest round trip), signed zeros too.
                assert_eq!(format!("{x:?}"), format!("{y:?}"));
            }
        }
    }

    #[test]
    fn packed_and_unpacked_passes_compute_the_same_bits() {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = Avx2::detect() {
            let softness = Softness::new(60.0, 10.0, 1.0 / 480.0);
            let passes = [
                Pass::Biased {
                    softness,
                    max_push_out: 3.0,
                },
                Pass::Relax,
            ];
            let (_, mut slots_inline, mut inline) = scene();
            let (_, mut slots_packed, mut packed) = scene();
            for pass in passes {
                let h = 1.0 / 480.0;
                run_pass_inline(
                    Portable,
                    pass,
                    &SharedBodies::new(&mut slots_inline.slots),
                    &mut inline,
                    h,
                );
                // SAFETY: the processor has AVX2, as `avx` proves.
                unsafe {
                    run_pass_avx2(
                        avx,
                        pass,
                        &SharedBodies::new(&mut slots_packed.slots),
                        &mut packed,
                        h,
                    )
                };
            }
            for (x, y) in slots_inline.slots.iter().zip(&slots_packed.slots) {
                assert_eq!(x.linear_momentum, y.linear_momentum);
                assert_eq!(x.angular_momentum, y.angular_momentum);
            }
            for (x, y) in inline.iter().zip(&packed) {
                assert_eq!((x.impulse, x.separation), (y.impulse, y.separation));
            }
            // The passes did something: the momenta moved from where the bodies had them.
            let (bodies, _, _) = scene();
            assert_ne!(
                slots_inline.slots[1].linear_momentum.to_vec3(),
                bodies[1].linear_momentum
            );
        }
    }
}
