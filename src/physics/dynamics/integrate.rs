//! Time integration of one body: momenta from forces, then position and orientation.
//!
//! All schemes are semi-implicit Euler on the momenta (L += F dt, A += τ dt, then
//! C += L/m dt). They differ in how the orientation follows ω = I_world⁻¹ A:
//! - `ReportEuler`: the report's R += ω* R dt, then Gram-Schmidt re-orthonormalisation.
//! - `ExactRotation`: R is rotated by the exact rotation exp(ω dt), a unit quaternion.
//! - `Midpoint`: like `ExactRotation` but ω is taken at the half-step orientation, found by
//!   fixed-point iteration; second order. The result is then turned slightly to keep the
//!   kinetic energy that the torque-free turn conserves, so a free spinning body neither
//!   gains nor loses energy.
//!
//! A negative dt runs the step backwards: the operations are applied in reverse order, so
//! that for forces that do not depend on position the linear part is the exact inverse of
//! the forward step (the bisection rewind of the contact stage relies on stepping back).

use glam::{DMat3, DQuat, DVec3};
use serde::{Deserialize, Serialize};

use crate::physics::dynamics::body::{RigidBody, is_isotropic};

/// How a body's orientation follows its angular velocity over a step (see the module
/// comment); all share semi-implicit Euler on the momenta and the centre of mass.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Integrator {
    /// The report's R += ω* R dt, then Gram-Schmidt re-orthonormalisation; first order.
    ReportEuler,
    /// R turned exactly by exp(ω dt), ω taken at the orientation the step starts from.
    ExactRotation,
    /// ω taken at the half-step orientation, and the kinetic energy kept: second order, and
    /// a free spinning body keeps its energy to round-off. The default.
    #[default]
    Midpoint,
}

impl Integrator {
    /// Every integrator, in declaration order (for menus and sweeps).
    pub const ALL: [Integrator; 3] = [
        Integrator::ReportEuler,
        Integrator::ExactRotation,
        Integrator::Midpoint,
    ];

    /// A snake-case label for menus and reports (scene files use the variant's name).
    pub fn name(self) -> &'static str {
        match self {
            Integrator::ReportEuler => "report_euler",
            Integrator::ExactRotation => "exact_rotation",
            Integrator::Midpoint => "midpoint",
        }
    }
}

/// Fixed-point iterations for the midpoint orientation; 3 reach f64 round-off for |ω dt| < 0.1.
const MIDPOINT_ITERATIONS: usize = 3;
/// The iteration stops once ω changes by less than this (squared, relative): round-off. A
/// slowly turning body (a pile settling) gets there in one or two iterations.
const SETTLED: f64 = 1e-30;

/// Advances one body by `dt` (which may be negative) using its accumulated force and torque.
pub fn integrate_body(body: &mut RigidBody, dt: f64, integrator: Integrator) {
    if !body.motion.moves() {
        return;
    }
    if dt >= 0.0 {
        integrate_momenta(body, dt);
        integrate_pose(body, dt, integrator);
    } else {
        integrate_pose(body, dt, integrator);
        integrate_momenta(body, dt);
    }
}

/// L += F dt, A += τ dt (nothing for a kinematic body: no force moves it)
pub fn integrate_momenta(body: &mut RigidBody, dt: f64) {
    if body.is_kinematic() {
        return;
    }
    body.linear_momentum += body.force * dt;
    body.angular_momentum += body.torque * dt;
}

/// C += L/m dt, then the orientation, then the world inverse inertia that depends on it
/// (unchanged when the orientation is).
///
/// This and the rotations it calls are always inlined, so that the soft step's AVX2 variant
/// (`solver::soft::step`) compiles them with its wider instructions, which makes the pose
/// updates markedly cheaper (BENCHMARKS.md, "Pose updates in the AVX2 step").
#[inline(always)]
pub fn integrate_pose(body: &mut RigidBody, dt: f64, integrator: Integrator) {
    if body.is_kinematic() {
        return move_kinematic(body, dt);
    }
    body.position += body.linear_momentum * body.inv_mass * dt;
    let orientation = match integrator {
        Integrator::ReportEuler => {
            rotate_report_euler(body.orientation, body.angular_velocity(), dt)
        }
        Integrator::ExactRotation => rotate_exact(body.orientation, body.angular_velocity(), dt),
        Integrator::Midpoint => rotate_midpoint(body, dt),
    };
    if orientation != body.orientation {
        body.orientation = orientation;
        body.refresh_world_inertia();
    }
}

/// A kinematic body along its own velocities: the turn is the exact rotation by ω dt, so
/// that substeps add up to the turn of the whole step (a target pose is reached).
fn move_kinematic(body: &mut RigidBody, dt: f64) {
    body.position += body.kinematic_velocity * dt;
    if body.kinematic_spin != DVec3::ZERO {
        body.orientation = rotate_exact(body.orientation, body.kinematic_spin, dt);
    }
}

/// The report's update R + ω* R dt, re-orthonormalised.
pub fn rotate_report_euler(orientation: DMat3, omega: DVec3, dt: f64) -> DMat3 {
    gram_schmidt(orientation + skew(omega) * orientation * dt)
}

/// exp(ω dt) R, with the rotation built as a unit quaternion and the result re-projected
/// onto the rotations so that round-off never accumulates. No spin leaves R exactly as is.
pub fn rotate_exact(orientation: DMat3, omega: DVec3, dt: f64) -> DMat3 {
    if omega == DVec3::ZERO {
        return orientation;
    }
    DMat3::from_quat(rotate_quat(DQuat::from_mat3(&orientation), omega, dt))
}

/// exp(ω dt) q, normalised.
#[inline(always)]
fn rotate_quat(current: DQuat, omega: DVec3, dt: f64) -> DQuat {
    renormalize(rotation_of_vector(omega * dt) * current)
}

/// Below this distance of |q|² from 1 a quaternion is brought back to unit length by the
/// first term of the series of 1/√(1 + e), whose next term, 3e²/8, is then below 4e-19: far
/// under the last place of 1 (1.1e-16).
const NEAR_UNIT: f64 = 1e-9;

/// q / |q| for a quaternion that round-off has moved off unit length. The product of two
/// unit quaternions is within a few units in the last place of it, and there
/// q (3 − |q|²)/2 gives the same to round-off without the square root and the division,
/// which took a large share of the soft step's own work on a rain, at every midpoint
/// iteration (BENCHMARKS.md, "Quaternion renormalisation").
#[inline(always)]
fn renormalize(q: DQuat) -> DQuat {
    let excess = q.length_squared() - 1.0;
    if excess.abs() < NEAR_UNIT {
        q * (1.0 - 0.5 * excess)
    } else {
        q.normalize()
    }
}

/// Up to this angle, rad, a step's rotation is taken from its series (see
/// `rotation_of_vector`); beyond it from the sine and cosine.
const SERIES_MAX_ANGLE: f64 = 0.2;

/// The unit quaternion (sin(θ/2) v/θ, cos(θ/2)) of the rotation vector v, θ = |v|. A step
/// turns a body by far less than SERIES_MAX_ANGLE, and there the series in z = θ²/4, cut
/// where its next term is below 3e-18 of the sum, give the same values to round-off without
/// the square root, sine and cosine, a noticeable share of a rain's whole step
/// (BENCHMARKS.md, "Rotation series").
#[inline(always)]
fn rotation_of_vector(v: DVec3) -> DQuat {
    let angle_squared = v.length_squared();
    // A NaN angle takes the sine and cosine too, which carry it on as they always did.
    let small = angle_squared <= SERIES_MAX_ANGLE * SERIES_MAX_ANGLE;
    if !small {
        return DQuat::from_scaled_axis(v);
    }
    let z = 0.25 * angle_squared;
    // sin(θ/2)/θ = ½ Σ (−z)ᵏ/(2k+1)!, cos(θ/2) = Σ (−z)ᵏ/(2k)!, in Horner form.
    let term = |k: f64| z * (1.0 / k);
    let sine_over_angle =
        0.5 * (1.0 - term(6.0) * (1.0 - term(20.0) * (1.0 - term(42.0) * (1.0 - term(72.0)))));
    let cosine = 1.0
        - term(2.0)
            * (1.0 - term(12.0) * (1.0 - term(30.0) * (1.0 - term(56.0) * (1.0 - term(90.0)))));
    let axis = v * sine_over_angle;
    DQuat::from_xyzw(axis.x, axis.y, axis.z, cosine)
}

/// ω taken at the half-step orientation, by fixed-point iteration. The iteration stops once
/// ω changes only by round-off, and is skipped when the inertia is isotropic (spheres, cubes: ω
/// does not depend on the orientation) or when nothing spins.
#[inline(always)]
fn rotate_midpoint(body: &RigidBody, dt: f64) -> DMat3 {
    let start = body.orientation;
    let mut omega = body.angular_velocity();
    if omega == DVec3::ZERO {
        return start;
    }
    let current = DQuat::from_mat3(&start);
    if is_isotropic(body.inv_inertia_local) {
        return DMat3::from_quat(rotate_quat(current, omega, dt));
    }
    let energy = 0.5 * body.angular_momentum.dot(omega);
    for _ in 0..MIDPOINT_ITERATIONS {
        let half = DMat3::from_quat(rotate_quat(current, omega, 0.5 * dt));
        let next = spin_at(body, half);
        let settled = next.distance_squared(omega) <= SETTLED * next.length_squared();
        omega = next;
        if settled {
            break;
        }
    }
    DMat3::from_quat(keep_energy(body, rotate_quat(current, omega, dt), energy))
}

/// ω = R I⁻¹ Rᵀ L at orientation R, as three matrix-vector products rather than two matrix
/// products.
#[inline(always)]
fn spin_at(body: &RigidBody, orientation: DMat3) -> DVec3 {
    let local = body.inv_inertia_local * (orientation.transpose() * body.angular_momentum);
    orientation * local
}

/// Newton steps that bring the rotational kinetic energy back within round-off.
const ENERGY_ITERATIONS: usize = 8;
/// Relative energy error below which `keep_energy` stops: round-off.
const ENERGY_SETTLED: f64 = 1e-15;
/// The largest turn, rad, `keep_energy` makes in one Newton step.
const MAX_ENERGY_TURN: f64 = 0.5;

/// `turned`, turned slightly so that the kinetic energy ½ L · ω is `energy`, its value at
/// the step's start. With L fixed over the turn, the exact motion keeps that energy, and the
/// midpoint rule's error, tiny per step, otherwise adds up to a drift that grows with the
/// spin (BENCHMARKS.md, "Free rotation energy"). Turning the body by δ about a unit axis u
/// changes the energy at the rate u · (ω × L), so the turn is along ω × L, by Newton steps.
/// Where ω × L vanishes (a spin about a principal axis) the energy is stationary and
/// nothing is turned.
#[inline(always)]
fn keep_energy(body: &RigidBody, turned: DQuat, energy: f64) -> DQuat {
    let momentum = body.angular_momentum;
    let mut q = turned;
    for _ in 0..ENERGY_ITERATIONS {
        let omega = spin_at(body, DMat3::from_quat(q));
        let error = energy - 0.5 * momentum.dot(omega);
        let gradient = omega.cross(momentum);
        let square = gradient.length_squared();
        // Near a principal axis a tiny rate would ask for a large turn: the error there is
        // of second order, and is left.
        let turn = error.abs() / square.sqrt();
        if !(error.abs() > ENERGY_SETTLED * energy && turn <= MAX_ENERGY_TURN) {
            break;
        }
        q = renormalize(rotation_of_vector(gradient * (error / square)) * q);
    }
    q
}

/// The report's * operator: skew(v) w = v × w.
pub fn skew(v: DVec3) -> DMat3 {
    DMat3::from_cols(
        DVec3::new(0.0, v.z, -v.y),
        DVec3::new(-v.z, 0.0, v.x),
        DVec3::new(v.y, -v.x, 0.0),
    )
}

/// Gram-Schmidt on the columns: normalise x, remove its part from y, z = x × y.
pub fn gram_schmidt(m: DMat3) -> DMat3 {
    let x = m.x_axis.normalize();
    let y = (m.y_axis - x * x.dot(m.y_axis)).normalize();
    let z = x.cross(y);
    DMat3::from_cols(x, y, z)
}

/// max |(RᵀR − I)ᵢⱼ|: how far a matrix is from being orthonormal.
pub fn orthonormality_error(m: DMat3) -> f64 {
    let e = m.transpose() * m - DMat3::IDENTITY;
    [e.x_axis, e.y_axis, e.z_axis]
        .iter()
        .map(|c| c.abs().max_element())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use glam::DVec4;

    use super::*;

    /// Near unit length the cheap renormalisation gives unit quaternions as `normalize`
    /// does: |q| within 2 units in the last place of 1, the direction unchanged.
    #[test]
    fn renormalizing_near_unit_length_matches_normalize() {
        let base = DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0);
        for k in 0..200 {
            let stretch = 1.0 + (k as f64 - 100.0) * 1e-12;
            let q = base * stretch;
            let (cheap, exact) = (renormalize(q), q.normalize());
            assert!(
                (cheap.length() - 1.0).abs() <= 2.0 * f64::EPSILON,
                "{k}: {cheap:?}"
            );
            let gap = (DVec4::from(cheap) - DVec4::from(exact))
                .abs()
                .max_element();
            assert!(
                gap <= 2.0 * f64::EPSILON,
                "{k}: {cheap:?} against {exact:?}"
            );
        }
        // Far from unit length it normalises exactly.
        assert_eq!(renormalize(base * 3.0), (base * 3.0).normalize());
    }

    /// The series give the sine and cosine's quaternion to within 2 units in the last place
    /// over the whole range they are used for, about any axis.
    #[test]
    fn the_series_rotation_matches_the_sine_and_cosine() {
        for k in 0..=2000 {
            let angle = SERIES_MAX_ANGLE * k as f64 / 2000.0;
            let axis = DVec3::new(1.0, -2.0 + k as f64 * 1e-3, 0.5).normalize();
            let series = rotation_of_vector(axis * angle);
            let exact = DQuat::from_scaled_axis(axis * angle);
            let gap = (DVec4::from(series) - DVec4::from(exact))
                .abs()
                .max_element();
            assert!(
                gap <= 2.0 * f64::EPSILON,
                "{angle}: {series:?} against {exact:?}"
            );
        }
    }
}
