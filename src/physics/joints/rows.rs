//! The joints' constraint rows, each a soft constraint solved by sequential impulses on the
//! two bodies' velocities: the point block (anchors together), the angular block (no
//! relative turn, or none across a hinge's axis), single rows along a direction (a slider's
//! cross directions, a distance), and the limits and motor along an axis.
//!
//! Every row follows the soft step: λ = −s_m·m·(Ċ + b) − s_i·λ_acc with the spring's bias
//! b = rate·C, mass and impulse scales (`Softness`) in the biased pass, and b = 0, s_m = 1,
//! s_i = 0 in the relax pass. A limit not yet reached lets the gap close within the
//! substep and no further (b = C/h), as a speculative contact does.

use glam::{DMat3, DVec3};

use crate::physics::solver::soft::Softness;

/// One body as a joint's rows see it during a pass: pose and velocities, and the momentum
/// the rows have given it (written back to its solver slot after the joint).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BodyView {
    pub(crate) position: DVec3,
    pub(crate) orientation: DMat3,
    pub(crate) velocity: DVec3,
    pub(crate) spin: DVec3,
    /// 1/m as impulses see it: zero for a body that does not move or is kinematic.
    pub(crate) inv_mass: f64,
    /// I⁻¹ in world axes as impulses see it (zero likewise).
    pub(crate) inv_inertia: DMat3,
    pub(crate) linear_impulse: DVec3,
    pub(crate) angular_impulse: DVec3,
}

impl BodyView {
    /// Adds a linear impulse at the lever `r` from the centre of mass.
    #[inline(always)]
    pub(crate) fn push_at(&mut self, r: DVec3, impulse: DVec3) {
        self.push(impulse, r.cross(impulse));
    }

    /// Adds a linear and an angular impulse.
    #[inline(always)]
    pub(crate) fn push(&mut self, linear: DVec3, angular: DVec3) {
        self.velocity += linear * self.inv_mass;
        self.spin += self.inv_inertia * angular;
        self.linear_impulse += linear;
        self.angular_impulse += angular;
    }

    /// Velocity of the point at lever `r`.
    #[inline(always)]
    fn point_velocity(&self, r: DVec3) -> DVec3 {
        self.velocity + self.spin.cross(r)
    }
}

/// How a row is solved in this pass: with the spring's bias (`Some`) or relaxed.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowPass {
    pub(crate) softness: Option<Softness>,
    pub(crate) h: f64,
}

impl RowPass {
    /// (bias velocity, mass scale, impulse scale) for an equality of error `c`.
    fn equality(&self, c: f64) -> (f64, f64, f64) {
        match self.softness {
            Some(s) => (s.bias_rate() * c, s.mass_scale(), s.impulse_scale()),
            None => (0.0, 1.0, 0.0),
        }
    }

    /// The same for an inequality C ≥ 0: an open gap may close within the substep.
    fn inequality(&self, c: f64) -> (f64, f64, f64) {
        if c > 0.0 {
            (c / self.h, 1.0, 0.0)
        } else {
            self.equality(c)
        }
    }
}

/// The anchors of both bodies together (ball, hinge, fixed): a 3×3 block.
#[inline(always)]
pub(crate) fn solve_point(
    [a, b]: [&mut BodyView; 2],
    [ra, rb]: [DVec3; 2],
    mass: &DMat3,
    accumulated: &mut DVec3,
    pass: RowPass,
) {
    let error = (b.position + rb) - (a.position + ra);
    let speed = b.point_velocity(rb) - a.point_velocity(ra);
    let (bias, mass_scale, impulse_scale) = vector_scales(pass, error);
    let rigid = *mass * (speed + bias);
    let impulse = -rigid * mass_scale - *accumulated * impulse_scale;
    *accumulated += impulse;
    a.push_at(ra, -impulse);
    b.push_at(rb, impulse);
}

/// The inverse of the mass the point block of two bodies meets at levers `ra`, `rb`: K⁻¹ with
/// K = (1/mA + 1/mB) 1 − [rA]× IA⁻¹ [rA]× − [rB]× IB⁻¹ [rB]×; None where K is singular.
/// K is symmetric, so the rows of its inverse (its cofactors over det K) are its columns.
pub(crate) fn point_mass(
    [ra, rb]: [DVec3; 2],
    [inv_mass_a, inv_mass_b]: [f64; 2],
    [inv_inertia_a, inv_inertia_b]: [&DMat3; 2],
) -> Option<DMat3> {
    let mut k = arm_mass(ra, *inv_inertia_a) + arm_mass(rb, *inv_inertia_b);
    let inv_mass = inv_mass_a + inv_mass_b;
    k.x_axis.x += inv_mass;
    k.y_axis.y += inv_mass;
    k.z_axis.z += inv_mass;
    let (cofactors, det) = cofactors(k)?;
    let [cx, cy, cz] = cofactors.map(|c| c / det);
    Some(DMat3::from_cols(cx, cy, cz))
}

/// −[r]× I⁻¹ [r]×: what an impulse at lever r adds to the point's velocity through turning.
/// Column k is (I⁻¹ u_k) × r with u_k = r × e_k, so entry (i, k) is u_i · I⁻¹ u_k: symmetric,
/// and each u has a zero component, which the products skip.
#[inline(always)]
fn arm_mass(r: DVec3, inv_inertia: DMat3) -> DMat3 {
    let (ix, iy, iz) = (inv_inertia.x_axis, inv_inertia.y_axis, inv_inertia.z_axis);
    // I⁻¹ u_k for u_x = (0, r.z, −r.y), u_y = (−r.z, 0, r.x), u_z = (r.y, −r.x, 0).
    let wx = iy * r.z - iz * r.y;
    let wy = iz * r.x - ix * r.z;
    let wz = ix * r.y - iy * r.x;
    let xx = r.z * wx.y - r.y * wx.z;
    let yy = r.x * wy.z - r.z * wy.x;
    let zz = r.y * wz.x - r.x * wz.y;
    let xy = r.z * wy.y - r.y * wy.z;
    let xz = r.z * wz.y - r.y * wz.z;
    let yz = r.x * wz.z - r.z * wz.x;
    DMat3::from_cols(
        DVec3::new(xx, xy, xz),
        DVec3::new(xy, yy, yz),
        DVec3::new(xz, yz, zz),
    )
}

#[inline(always)]
fn vector_scales(pass: RowPass, error: DVec3) -> (DVec3, f64, f64) {
    match pass.softness {
        Some(s) => (error * s.bias_rate(), s.mass_scale(), s.impulse_scale()),
        None => (DVec3::ZERO, 1.0, 0.0),
    }
}

/// x with k x = v, None where k is singular: the rows of k⁻¹ are the cross products of
/// k's columns over det k.
#[inline(always)]
fn solve3(k: DMat3, v: DVec3) -> Option<DVec3> {
    let (cofactors, det) = cofactors(k)?;
    let [cx, cy, cz] = cofactors.map(|c| c.dot(v));
    Some(DVec3::new(cx, cy, cz) / det)
}

/// The cross products of k's columns (k⁻¹'s rows times det k) and det k; None where k is
/// singular.
#[inline(always)]
fn cofactors(k: DMat3) -> Option<([DVec3; 3], f64)> {
    let (x, y, z) = (k.x_axis, k.y_axis, k.z_axis);
    let cofactors = [y.cross(z), z.cross(x), x.cross(y)];
    let det = x.dot(cofactors[0]);
    (det.abs() > 1e-300 && det.is_finite()).then_some((cofactors, det))
}

/// No relative turn but about `free` (a hinge's axis; zero for none): `error` is the small
/// rotation that would bring b back, world (across `free`).
pub(crate) fn solve_angular(
    [a, b]: [&mut BodyView; 2],
    free: DVec3,
    error: DVec3,
    accumulated: &mut DVec3,
    pass: RowPass,
) {
    let across = DMat3::IDENTITY - outer(free);
    let speed = across * (b.spin - a.spin);
    // Across the free axis the block is the bodies' inverse inertia; along it, 1 keeps it
    // invertible and, with a right-hand side across it, gives an impulse across it.
    let k = across * (a.inv_inertia + b.inv_inertia) * across + outer(free);
    let (bias, mass_scale, impulse_scale) = vector_scales(pass, error);
    let Some(rigid) = solve3(k, speed + bias) else {
        return;
    };
    let impulse = -rigid * mass_scale - *accumulated * impulse_scale;
    *accumulated += impulse;
    a.push(DVec3::ZERO, -impulse);
    b.push(DVec3::ZERO, impulse);
}

fn outer(v: DVec3) -> DMat3 {
    DMat3::from_cols(v * v.x, v * v.y, v * v.z)
}

/// A direction `n` between two points: b's anchor at lever `rb`, and a's point at lever
/// `ra` (for a slider, a's anchor moved along the axis to face b's).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LinearRow {
    pub(crate) n: DVec3,
    pub(crate) ra: DVec3,
    pub(crate) rb: DVec3,
}

/// What the bounds of a scalar row are.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Bound {
    /// An equality: any impulse.
    Equal,
    /// C ≥ 0: the accumulated impulse never pulls.
    AtLeast,
    /// A motor: no position error; the accumulated impulse within ±limit toward a speed.
    Motor { speed: f64, limit: f64 },
    /// A user's spring of this softness toward C = 0, in both passes (it is a force of the
    /// model, not an error correction).
    Spring(Softness),
    /// A servo: a user's spring, its accumulated impulse within ±limit.
    Servo { softness: Softness, limit: f64 },
}

impl LinearRow {
    fn speed(&self, a: &BodyView, b: &BodyView) -> f64 {
        self.n
            .dot(b.point_velocity(self.rb) - a.point_velocity(self.ra))
    }

    fn mass(&self, a: &BodyView, b: &BodyView) -> f64 {
        let (arm_a, arm_b) = (self.ra.cross(self.n), self.rb.cross(self.n));
        let k = a.inv_mass
            + b.inv_mass
            + arm_a.dot(a.inv_inertia * arm_a)
            + arm_b.dot(b.inv_inertia * arm_b);
        if k > 0.0 { 1.0 / k } else { 0.0 }
    }

    /// Solves the row of position error `c` (`sign` −1 turns an upper limit into C ≥ 0).
    pub(crate) fn solve(
        &self,
        [a, b]: [&mut BodyView; 2],
        c: f64,
        bound: Bound,
        accumulated: &mut f64,
        pass: RowPass,
    ) {
        let speed = self.speed(a, b);
        let impulse = scalar_impulse(self.mass(a, b), speed, c, bound, accumulated, pass);
        a.push_at(self.ra, -self.n * impulse);
        b.push_at(self.rb, self.n * impulse);
    }
}

/// A turn about the unit `axis`: a hinge's limits and motor.
pub(crate) fn solve_axial(
    [a, b]: [&mut BodyView; 2],
    axis: DVec3,
    c: f64,
    bound: Bound,
    accumulated: &mut f64,
    pass: RowPass,
) {
    let speed = axis.dot(b.spin - a.spin);
    let k = axis.dot((a.inv_inertia + b.inv_inertia) * axis);
    let mass = if k > 0.0 { 1.0 / k } else { 0.0 };
    let impulse = scalar_impulse(mass, speed, c, bound, accumulated, pass);
    a.push(DVec3::ZERO, -axis * impulse);
    b.push(DVec3::ZERO, axis * impulse);
}

/// The accumulated impulse of a spring of softness `s` toward C = 0.
fn spring_impulse(s: Softness, mass: f64, speed: f64, c: f64, old: f64) -> f64 {
    let bias = s.bias_rate() * c;
    old - mass * s.mass_scale() * (speed + bias) - s.impulse_scale() * old
}

/// The impulse a scalar row adds, its accumulated impulse updated and kept in bounds.
fn scalar_impulse(
    mass: f64,
    speed: f64,
    c: f64,
    bound: Bound,
    accumulated: &mut f64,
    pass: RowPass,
) -> f64 {
    let old = *accumulated;
    let new = match bound {
        Bound::Motor {
            speed: target,
            limit,
        } => (old - mass * (speed - target)).clamp(-limit, limit),
        Bound::Spring(s) => spring_impulse(s, mass, speed, c, old),
        Bound::Servo { softness, limit } => {
            spring_impulse(softness, mass, speed, c, old).clamp(-limit, limit)
        }
        Bound::Equal => {
            let (bias, mass_scale, impulse_scale) = pass.equality(c);
            old - mass * mass_scale * (speed + bias) - impulse_scale * old
        }
        Bound::AtLeast => {
            let (bias, mass_scale, impulse_scale) = pass.inequality(c);
            (old - mass * mass_scale * (speed + bias) - impulse_scale * old).max(0.0)
        }
    };
    *accumulated = new;
    new - old
}
