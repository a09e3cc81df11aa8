//! The passes over the contacts: **solve** (with the soft position bias) and **relax**
//! (without it, at the poses the substep moved to), colour by colour.

use rayon::prelude::*;

use super::SoftSolverSettings;
use super::constraint::{Contacts, PointConstraint, PointImpact};
use crate::physics::solver::contact_colors::ContactColors;
use crate::physics::solver::impulse::clamp_to_friction_disc;
#[cfg(target_arch = "x86_64")]
use crate::physics::solver::lanes::Avx2;
use crate::physics::solver::lanes::{Lanes, Portable};
use crate::physics::solver::solver_bodies::{SharedBodies, SolverBody};

/// The stiffest contact spring a substep of length h can carry is this many times 1/h:
/// stiffer springs ring at 4 or 5 substeps and stacks never settle (BENCHMARKS.md, "Contact
/// spring cap").
const MAX_HERTZ_PER_SUBSTEP_RATE: f64 = 0.2;

/// Spring coefficients of a soft constraint for one substep.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Softness {
    bias_rate: f64,
    mass_scale: f64,
    impulse_scale: f64,
}

impl Softness {
    /// The contacts' spring for substeps of length `h`: `contact_hertz`, capped at what the
    /// substep carries.
    pub(super) fn of_contacts(settings: &SoftSolverSettings, h: f64) -> Self {
        let hertz = settings.contact_hertz.min(MAX_HERTZ_PER_SUBSTEP_RATE / h);
        Softness::new(hertz, settings.damping_ratio, h)
    }

    /// The joints' spring for substeps of length `h`: `joint_hertz`, capped at a quarter of
    /// the substep rate, beyond which a weld's two blocks rang apart.
    pub(crate) fn of_joints(settings: &SoftSolverSettings, h: f64) -> Self {
        let hertz = settings.joint_hertz.min(0.25 / h);
        Softness::new(hertz, settings.joint_damping_ratio, h)
    }

    /// A spring of `hertz` and `damping_ratio` over substeps of length `h`.
    pub(crate) fn new(hertz: f64, damping_ratio: f64, h: f64) -> Self {
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

    /// How deep the spring holds a contact that carries `impulse` (N·s per substep) against
    /// a body of effective mass `mass`: where its push balances the impulse's leak, as a
    /// loaded contact settles (the static deflection, load / mass · g/ω²).
    #[inline(always)]
    pub(super) fn depth_under_load(&self, impulse: f64, mass: f64) -> f64 {
        self.impulse_scale * impulse / (mass * self.mass_scale * self.bias_rate)
    }

    /// The velocity bias per metre (or radian) of error, 1/s.
    pub(crate) fn bias_rate(&self) -> f64 {
        self.bias_rate
    }

    /// How much of the rigid impulse the spring gives.
    pub(crate) fn mass_scale(&self) -> f64 {
        self.mass_scale
    }

    /// How much of the accumulated impulse the spring lets go each solve.
    pub(crate) fn impulse_scale(&self) -> f64 {
        self.impulse_scale
    }
}

/// Contacts in a colour that make it worth spreading over the threads.
const PARALLEL_MIN_CONTACTS: usize = 128;

/// Parts a colour is split into per thread, so that a thread that finishes early takes
/// another.
const PARTS_PER_THREAD: usize = 4;

/// One pass of a substep over the contacts.
///
/// Each substep starts by applying the impulses the contacts hold (the warm start). That
/// needs no pass of its own: once the relax pass has solved every contact, what each body's
/// momenta gained since the warm start is the sum of its contacts' final impulses, the next
/// substep's warm start (`SolverBodies::store_warm_start`); `prepare` gathers the first
/// from the impulses remembered from the last step. A pass over the contacts streams them all
/// through memory; a pass over the bodies is far smaller.
#[derive(Clone, Copy)]
pub(super) enum Pass {
    /// Solves with the soft position bias; a deep point (`PointConstraint::deep`) is solved
    /// rigidly, and `push_out` moves its bodies apart instead of the spring. `deep_points`
    /// says whether the step has any.
    Biased {
        softness: Softness,
        max_push_out: f64,
        deep_points: bool,
    },
    /// Measures the separations at the poses the substep moved to, then solves without
    /// bias, removing the velocity the bias added.
    Relax,
}

/// Runs `pass` on every contact, colour by colour (see `contact_colors`). A colour large
/// enough is split over the threads, in runs of whole manifolds; the result is the same to
/// the last bit, as its manifolds share no moving body.
pub(super) fn for_each_contact(
    bodies: &mut [SolverBody],
    contacts: &mut Contacts,
    colors: &ContactColors,
    pass: Pass,
    h: f64,
) {
    // SAFETY: the threads share one colour at a time, whose contacts address disjoint moving
    // slots (`contact_colors`).
    let shared = unsafe { SharedBodies::new(bodies) };
    let threads = rayon::current_num_threads();
    for (range, parallel) in colors.ranges() {
        let color = contacts.range(range);
        if parallel && threads > 1 && color.points.len() >= PARALLEL_MIN_CONTACTS {
            let mut parts = color.split(PARTS_PER_THREAD * threads);
            (parts.par_iter_mut()).for_each(|part| run_pass(pass, &shared, part.reborrow(), h));
        } else {
            run_pass(pass, &shared, color, h);
        }
    }
}

/// `pass` on these contacts in order, with the lanes (see `lanes`) packed four to an
/// instruction where the processor has AVX2, and as the compiler packs them otherwise. Both
/// compute the same bits.
fn run_pass(pass: Pass, bodies: &SharedBodies, contacts: Contacts, h: f64) {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx) = Avx2::detect() {
        // SAFETY: the processor has AVX2, as `avx` proves.
        return unsafe { run_pass_avx2(avx, pass, bodies, contacts, h) };
    }
    run_pass_inline(Portable, pass, bodies, contacts, h);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(super) fn run_pass_avx2(
    avx: Avx2,
    pass: Pass,
    bodies: &SharedBodies,
    contacts: Contacts,
    h: f64,
) {
    run_pass_inline(avx, pass, bodies, contacts, h);
}

/// The body of `run_pass`, compiled into each of its variants.
#[inline(always)]
pub(super) fn run_pass_inline<L: Lanes>(
    l: L,
    pass: Pass,
    bodies: &SharedBodies,
    contacts: Contacts,
    h: f64,
) {
    // A second copy of the loop for the steps with deep points, so that every other step
    // runs the loop it ran before: a check in the one loop cost 5.6 % more instructions
    // (BENCHMARKS.md, "Deep overlap pushed out by moving the bodies").
    match pass {
        Pass::Biased {
            deep_points: true, ..
        } => run_points::<L, true>(l, pass, bodies, contacts, h),
        _ => run_points::<L, false>(l, pass, bodies, contacts, h),
    }
}

/// `run_pass_inline`'s loop; `DEEP` when a biased pass has deep points to look for.
#[inline(always)]
fn run_points<L: Lanes, const DEEP: bool>(
    l: L,
    pass: Pass,
    bodies: &SharedBodies,
    contacts: Contacts,
    h: f64,
) {
    let Contacts {
        points,
        anchors,
        impacts,
    } = contacts;
    // Plain loops: an iterator adaptor's closure may be left out of line, and would then be
    // compiled without the variant's instructions.
    let bias = match pass {
        Pass::Biased {
            softness,
            max_push_out,
            ..
        } => Some(Bias {
            softness,
            max_push_out,
        }),
        Pass::Relax => None,
    };
    let relax = bias.is_none();
    let mut k = 0;
    while k < points.len() {
        let paired = points[k].pairs_with_next && k + 1 < points.len();
        let end = k + 1 + paired as usize;
        let (group, group_impacts) = (&mut points[k..end], &mut impacts[k..end]);
        if relax {
            for (c, anchors) in group.iter_mut().zip(&anchors[k..]) {
                c.separation = anchors.separation(l, bodies, c);
            }
        }
        k = end;
        match (group, group_impacts) {
            ([first, second], [first_impact, second_impact]) => {
                let pair = [(first, first_impact), (second, second_impact)];
                solve_two::<L, DEEP>(l, bodies, pair, h, bias)
            }
            ([only], [impact]) => solve::<L, DEEP>(l, bodies, (only, impact), h, bias),
            _ => unreachable!("a group is one contact or two"),
        }
    }
}

/// `solve` on two independent contacts, step by step side by side, so that the processor
/// works on both chains of dependent operations at once.
#[inline(always)]
fn solve_two<L: Lanes, const DEEP: bool>(
    l: L,
    bodies: &SharedBodies,
    [(x, impact_x), (y, impact_y)]: [(&mut PointConstraint, &mut PointImpact); 2],
    h: f64,
    bias: Option<Bias>,
) {
    let (speeds_x, speeds_y) = (x.speeds(l, bodies), y.speeds(l, bodies));
    let normal_x = solve_normal::<DEEP>((x, impact_x), speeds_x[0], h, bias);
    let normal_y = solve_normal::<DEEP>((y, impact_y), speeds_y[0], h, bias);
    let friction_x = solve_friction(x, tangent_speeds(x, speeds_x, normal_x));
    let friction_y = solve_friction(y, tangent_speeds(y, speeds_y, normal_y));
    x.apply(l, bodies, [normal_x, friction_x[0], friction_x[1]]);
    y.apply(l, bodies, [normal_y, friction_y[0], friction_y[1]]);
}

/// The soft position bias of a biased pass.
#[derive(Clone, Copy)]
struct Bias {
    softness: Softness,
    max_push_out: f64,
}

/// One contact's share of a pass: normal (soft or rigid) then friction, applied together.
/// `bias` is the softness and push-out limits when solving with position bias, None to
/// relax.
#[inline(always)]
fn solve<L: Lanes, const DEEP: bool>(
    l: L,
    bodies: &SharedBodies,
    (c, impact): (&mut PointConstraint, &mut PointImpact),
    h: f64,
    bias: Option<Bias>,
) {
    let speeds = c.speeds(l, bodies);
    let normal = solve_normal::<DEEP>((c, impact), speeds[0], h, bias);
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
            speeds[1] + f64::from(c.normal_to_tangent[0]) * normal,
            speeds[2] + f64::from(c.normal_to_tangent[1]) * normal,
        ]
    }
}

/// The normal impulse this pass adds, at the relative normal speed `normal_speed`.
#[inline(always)]
fn solve_normal<const DEEP: bool>(
    (c, impact): (&mut PointConstraint, &mut PointImpact),
    normal_speed: f64,
    h: f64,
    bias: Option<Bias>,
) -> f64 {
    let separation = c.separation;
    let (velocity_bias, mass_scale, impulse_scale) = if separation > 0.0 {
        // Speculative: allow the gap to close within this substep, no further.
        (separation / h, 1.0, 0.0)
    } else if let Some(bias) = bias {
        // A deep overlap that no load explains (bodies created inside each other) is pushed
        // out by moving the bodies (`push_out`): its spring's push, passed from body to body
        // through a crowd, flung them apart at many times `max_push_out`.
        if DEEP && c.deep {
            (0.0, 1.0, 0.0)
        } else {
            let soft = bias.softness;
            (
                at_least(soft.bias_rate * separation, -bias.max_push_out),
                soft.mass_scale,
                soft.impulse_scale,
            )
        }
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
        let a = impact.approach_acceleration;
        let arc_speed = normal_speed + if bias.is_some() { -0.5 } else { 0.5 } * a * h;
        impact.approach_speed = impact_speed(arc_speed, a, separation).max(impact.fastest_approach);
    }
    c.impulse.normal = accumulated;
    c.max_normal_impulse = at_least(applied, c.max_normal_impulse);
    applied
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

/// `x.max(floor)` for a floor that is a number (a NaN x gives the floor, as with `max`), in one
/// comparison: `f64::max` also has to handle a NaN floor, which the solver's hottest path
/// never has.
#[inline(always)]
fn at_least(x: f64, floor: f64) -> f64 {
    if x > floor { x } else { floor }
}

/// Coulomb friction: the tangential impulse stays inside the disc of radius μ·λn. Returns
/// the impulses this pass adds along the tangents.
#[inline(always)]
fn solve_friction(c: &mut PointConstraint, speeds: [f64; 2]) -> [f64; 2] {
    let limit = f64::from(c.friction) * c.impulse.normal;
    let tangent_mass = [f64::from(c.tangent_mass[0]), f64::from(c.tangent_mass[1])];
    let unclamped = [
        c.impulse.tangent[0] - tangent_mass[0] * speeds[0],
        c.impulse.tangent[1] - tangent_mass[1] * speeds[1],
    ];
    let accumulated = clamp_to_friction_disc(unclamped, limit);
    let applied = [
        accumulated[0] - c.impulse.tangent[0],
        accumulated[1] - c.impulse.tangent[1],
    ];
    c.impulse.tangent = accumulated;
    applied
}
