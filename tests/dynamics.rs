//! Dynamics of free bodies against analytic answers: free fall and projectile (C1),
//! torque-free spin about the intermediate axis (C3), orthonormality of the orientation,
//! running backwards, forces at points and the environmental force list.

use glam::{DQuat, DVec3};
use rigid::physics::dynamics::integrate::orthonormality_error;
use rigid::physics::{BodyDesc, BodyId, EnvironmentForce, Integrator, Shape, World, WorldSettings};

const G: f64 = 9.81;

/// The world integrates each step in this many substeps of dt / SUBSTEPS.
fn substeps() -> usize {
    rigid::physics::solver::soft::SoftSolverSettings::default().substeps as usize
}

fn world_with(integrator: Integrator, forces: Vec<EnvironmentForce>) -> World {
    let mut world = World::new(WorldSettings {
        integrator,
        ..Default::default()
    });
    world.forces = forces;
    world
}

fn gravity() -> Vec<EnvironmentForce> {
    vec![EnvironmentForce::earth_gravity()]
}

fn add(world: &mut World, desc: BodyDesc) -> BodyId {
    world.add_body(desc).expect("valid body")
}

fn run(world: &mut World, dt: f64, steps: usize) {
    for _ in 0..steps {
        world.step(dt);
    }
}

/// Semi-implicit Euler on a constant acceleration a from rest velocity v0:
/// v_k = v0 + a k h and x_n = x0 + h Σ_{k=1..n} v_k = x0 + v0 n h + a h² n(n+1)/2.
/// The scheme is first order: x_n − x(t) = a t h / 2 exactly.
fn semi_implicit_position(x0: f64, v0: f64, a: f64, h: f64, n: usize) -> f64 {
    let n = n as f64;
    x0 + v0 * n * h + a * h * h * n * (n + 1.0) / 2.0
}

#[test]
fn free_fall_follows_the_discrete_closed_form_and_is_first_order() {
    for integrator in Integrator::ALL {
        let h = 1.0 / 60.0;
        let n = 60;
        let mut world = world_with(integrator, gravity());
        let ball = add(
            &mut world,
            BodyDesc::dynamic(Shape::sphere(0.1)).at(DVec3::Y * 20.0),
        );
        run(&mut world, h, n);
        let y = world.body(ball).position.y;
        // The world integrates n steps as n·s substeps of h/s. Round-off over 240 substeps
        // of magnitude ~20 m stays far below 1e-9 m.
        let (s, substep) = (substeps(), h / substeps() as f64);
        let discrete = semi_implicit_position(20.0, 0.0, -G, substep, n * s);
        assert!(
            (y - discrete).abs() < 1e-9,
            "{integrator:?}: y = {y}, expected {discrete}"
        );
        // Against the exact path 20 − g t²/2 the error is g t (h/s) / 2 (t = 1 s).
        let analytic = 20.0 - 0.5 * G;
        let expected_error = G * 1.0 * substep / 2.0;
        assert!(((analytic - y) - expected_error).abs() < 1e-9);
        // Velocity is exact for a constant force.
        assert!((world.body(ball).velocity().y + G).abs() < 1e-12);
    }
}

#[test]
fn free_fall_error_halves_when_dt_halves() {
    let error_at = |h: f64| {
        let mut world = world_with(Integrator::Midpoint, gravity());
        let ball = add(&mut world, BodyDesc::dynamic(Shape::sphere(0.1)));
        run(&mut world, h, (1.0 / h).round() as usize);
        (world.body(ball).position.y + 0.5 * G).abs()
    };
    let coarse = error_at(1.0 / 60.0);
    let fine = error_at(1.0 / 120.0);
    // First order: the ratio is exactly 2 up to round-off (bound 1e-6).
    assert!(
        (coarse / fine - 2.0).abs() < 1e-6,
        "ratio {}",
        coarse / fine
    );
}

#[test]
fn projectile_matches_the_analytic_path_to_first_order() {
    let h = 1.0 / 120.0;
    let n = 240;
    let v0 = DVec3::new(7.0, 12.0, -3.0);
    let mut world = world_with(Integrator::Midpoint, gravity());
    let shell = add(
        &mut world,
        BodyDesc::dynamic(Shape::cuboid(DVec3::splat(0.1))).with_velocity(v0),
    );
    run(&mut world, h, n);
    let p = world.body(shell).position;
    let t = n as f64 * h;
    // Horizontal motion has no force: exact to round-off.
    assert!((p.x - v0.x * t).abs() < 1e-12 && (p.z - v0.z * t).abs() < 1e-12);
    // Vertical: analytic v0 t − g t²/2, with the scheme's known error g t (h/s) / 2.
    let analytic = v0.y * t - 0.5 * G * t * t;
    let h = h / substeps() as f64;
    assert!(
        (p.y - (analytic - G * t * h / 2.0)).abs() < 1e-9,
        "y = {}",
        p.y
    );
}

#[test]
fn negative_dt_runs_the_linear_motion_exactly_backwards() {
    let h = 1.0 / 60.0;
    let mut world = world_with(Integrator::Midpoint, gravity());
    let start = DVec3::new(1.0, 5.0, -2.0);
    let v0 = DVec3::new(3.0, 4.0, 0.5);
    let ball = add(
        &mut world,
        BodyDesc::dynamic(Shape::sphere(0.2))
            .at(start)
            .with_velocity(v0),
    );
    run(&mut world, h, 120);
    run(&mut world, -h, 120);
    let body = world.body(ball);
    // Each backward step is the algebraic inverse of the forward one: only round-off remains.
    assert!(
        (body.position - start).length() < 1e-12,
        "{}",
        body.position
    );
    assert!((body.velocity() - v0).length() < 1e-12);
    assert!(world.time().abs() < 1e-12);
}

#[test]
fn negative_dt_retraces_a_tumbling_body() {
    // Rotation backwards is not the algebraic inverse (ω is re-evaluated at the new
    // orientation). The midpoint rule is symmetric in time and retraces 1 s of tumbling to
    // round-off; the first-order schemes do not (measured ~0.6 and ~0.25), which is printed.
    for integrator in Integrator::ALL {
        let mut world = world_with(integrator, vec![]);
        let spin = DVec3::new(0.3, 4.0, 0.2);
        let block = add(
            &mut world,
            BodyDesc::dynamic(Shape::cuboid(DVec3::new(0.1, 0.3, 0.6))).with_angular_velocity(spin),
        );
        let start = world.body(block).orientation;
        run(&mut world, 1.0 / 240.0, 240);
        run(&mut world, -1.0 / 240.0, 240);
        let error = (world.body(block).orientation - start)
            .abs()
            .to_cols_array();
        let error = error.iter().cloned().fold(0.0, f64::max);
        println!("{integrator:?}: orientation error after 1 s forward and back: {error:.3e}");
        if integrator == Integrator::Midpoint {
            assert!(error < 1e-9, "{error}");
        }
    }
}

/// C3: a box spun about its intermediate principal axis in zero gravity.
/// Half extents (0.1, 0.3, 0.6) give principal moments ∝ (0.45, 0.37, 0.10): y is intermediate.
struct SpinReport {
    momentum_error: f64,
    energy_drift: f64,
    flipped: bool,
}

fn spin_about_intermediate_axis(integrator: Integrator, dt: f64, seconds: f64) -> SpinReport {
    let mut world = world_with(integrator, vec![]);
    let omega0 = DVec3::new(0.01, 10.0, 0.01);
    let block = add(
        &mut world,
        BodyDesc::dynamic(Shape::cuboid(DVec3::new(0.1, 0.3, 0.6))).with_angular_velocity(omega0),
    );
    let momentum0 = world.body(block).angular_momentum;
    let energy0 = world.body(block).kinetic_energy();
    let axis0 = momentum0.normalize();
    let mut report = SpinReport {
        momentum_error: 0.0,
        energy_drift: 0.0,
        flipped: false,
    };
    for _ in 0..(seconds / dt).round() as usize {
        world.step(dt);
        let body = world.body(block);
        let total = world.totals().angular_momentum;
        report.momentum_error = report
            .momentum_error
            .max((body.angular_momentum - momentum0).length() / momentum0.length())
            .max((total - momentum0).length() / momentum0.length());
        report.energy_drift = report
            .energy_drift
            .max((body.kinetic_energy() - energy0).abs() / energy0);
        // The body's y axis starts along the angular momentum; a flip turns it around.
        if body.orientation.y_axis.dot(axis0) < -0.9 {
            report.flipped = true;
        }
    }
    report
}

#[test]
fn torque_free_spin_conserves_momentum_and_flips_about_the_intermediate_axis() {
    let dt = 1.0 / 240.0;
    for integrator in Integrator::ALL {
        let report = spin_about_intermediate_axis(integrator, dt, 20.0);
        println!(
            "{:>15}: |ΔA|/|A| = {:.1e}, max |ΔE|/E over 20 s = {:.3e}, flipped = {}",
            integrator.name(),
            report.momentum_error,
            report.energy_drift,
            report.flipped
        );
        // Momentum form: with no torque A never changes, to the last bit.
        assert!(report.momentum_error < 1e-14, "{integrator:?}");
        assert!(
            report.flipped,
            "{integrator:?}: the intermediate-axis flip did not happen"
        );
        // The first-order schemes pump energy until the box spins about its minor axis
        // (ΔE/E = I_y/I_z − 1 ≈ 2.7, measured); the midpoint rule, with its energy kept,
        // stays within round-off accumulated over the run (measured 1.4e-12).
        if integrator == Integrator::Midpoint {
            assert!(report.energy_drift < 1e-9, "{}", report.energy_drift);
        }
    }
}

/// The orientation of a tumbling asymmetric box after `seconds` at step `dt`.
fn tumbled(integrator: Integrator, dt: f64, seconds: f64) -> glam::DMat3 {
    let mut world = world_with(integrator, vec![]);
    let block = add(
        &mut world,
        BodyDesc::dynamic(Shape::cuboid(DVec3::new(0.1, 0.3, 0.6)))
            .with_angular_velocity(DVec3::new(1.0, 2.0, 10.0)),
    );
    run(&mut world, dt, (seconds / dt).round() as usize);
    world.body(block).orientation
}

#[test]
fn midpoint_orientation_is_second_order() {
    let reference = tumbled(Integrator::Midpoint, 1.0 / 3840.0, 2.0);
    let error = |dt: f64| {
        let difference = tumbled(Integrator::Midpoint, dt, 2.0) - reference;
        (difference.to_cols_array().iter()).fold(0.0f64, |m, x| m.max(x.abs()))
    };
    let (coarse, fine) = (error(1.0 / 120.0), error(1.0 / 240.0));
    let ratio = coarse / fine;
    println!("midpoint orientation error after 2 s: {coarse:.3e} -> {fine:.3e}, ratio {ratio:.2}");
    // Second order: halving dt divides the error by about 4 (accepted 3 to 5).
    assert!((3.0..5.0).contains(&ratio), "ratio {ratio}");
}

/// The largest relative change of the kinetic energy of a free asymmetric box spinning at
/// `spin` rad/s about a generic axis, over `seconds` at dt = 1/60, and its angular
/// momentum's largest relative error.
fn free_spin_drift(integrator: Integrator, spin: f64, seconds: f64) -> (f64, f64) {
    let mut world = world_with(integrator, vec![]);
    let omega0 = DVec3::new(0.3, 1.0, 0.6).normalize() * spin;
    let block = add(
        &mut world,
        BodyDesc::dynamic(Shape::cuboid(DVec3::new(0.1, 0.3, 0.6))).with_angular_velocity(omega0),
    );
    let (momentum0, energy0) = (
        world.body(block).angular_momentum,
        world.body(block).kinetic_energy(),
    );
    let dt = 1.0 / 60.0;
    let (mut drift, mut momentum_error) = (0.0f64, 0.0f64);
    for _ in 0..(seconds / dt).round() as usize {
        world.step(dt);
        let body = world.body(block);
        drift = drift.max((body.kinetic_energy() - energy0).abs() / energy0);
        let error = (body.angular_momentum - momentum0).length() / momentum0.length();
        momentum_error = momentum_error.max(error);
    }
    (drift, momentum_error)
}

#[test]
fn a_free_asymmetric_body_keeps_its_kinetic_energy_at_any_spin() {
    for integrator in Integrator::ALL {
        for spin in [10.0, 100.0, 1000.0] {
            let (drift, momentum_error) = free_spin_drift(integrator, spin, 100.0);
            println!(
                "{:>15} at {spin:>6} rad/s: max |ΔE|/E over 100 s = {drift:.3e}, |ΔA|/|A| = {momentum_error:.1e}",
                integrator.name()
            );
            assert!(momentum_error < 1e-14, "{integrator:?} at {spin} rad/s");
            // The default keeps the energy the torque-free motion conserves to 1e-6 (issue
            // 30's bar); the others are measured only.
            if integrator == Integrator::Midpoint {
                assert!(drift < 1e-6, "{spin} rad/s: {drift:.3e}");
            }
        }
    }
}

#[test]
fn orientation_stays_orthonormal_after_a_million_tumbling_steps() {
    for integrator in Integrator::ALL {
        let mut world = world_with(integrator, vec![]);
        let block = add(
            &mut world,
            BodyDesc::dynamic(Shape::cuboid(DVec3::new(0.2, 0.5, 0.9)))
                .rotated(DQuat::from_euler(glam::EulerRot::XYZ, 0.3, 1.1, -0.7))
                .with_angular_velocity(DVec3::new(3.0, -5.0, 7.0)),
        );
        run(&mut world, 1.0 / 120.0, 1_000_000);
        let error = orthonormality_error(world.body(block).orientation);
        println!(
            "{:>15}: max |RᵀR − I| after 1e6 steps = {error:.2e}",
            integrator.name()
        );
        // Re-orthonormalised every step: only the last step's round-off remains.
        assert!(error < 1e-14, "{integrator:?}: {error}");
        assert!((world.body(block).orientation.determinant() - 1.0).abs() < 1e-14);
    }
}

#[test]
fn a_force_at_a_point_adds_momentum_and_torque() {
    let mut world = world_with(Integrator::Midpoint, vec![]);
    let block = add(
        &mut world,
        BodyDesc::dynamic(Shape::cuboid(DVec3::new(1.0, 0.5, 0.25))),
    );
    let corner = DVec3::new(1.0, 0.5, 0.25);
    let force = DVec3::new(0.0, 0.0, 40.0);
    world.body_mut(block).apply_force_at(force, corner);
    let dt = 0.01;
    world.step(dt);
    let body = world.body(block);
    assert!((body.linear_momentum - force * dt).length() < 1e-15);
    // τ = (x − C) × F with C at the origin.
    assert!((body.angular_momentum - corner.cross(force) * dt).length() < 1e-15);
    // Accumulators are cleared after the step.
    assert_eq!(body.force, DVec3::ZERO);
    assert_eq!(body.torque, DVec3::ZERO);
}

#[test]
fn static_bodies_never_move() {
    let mut world = world_with(Integrator::Midpoint, gravity());
    let floor = add(
        &mut world,
        BodyDesc::fixed(Shape::cuboid(DVec3::new(5.0, 0.1, 5.0))),
    );
    world
        .body_mut(floor)
        .apply_impulse_at(DVec3::new(1e3, 1e3, 0.0), DVec3::new(4.0, 0.0, 0.0));
    run(&mut world, 1.0 / 60.0, 120);
    let body = world.body(floor);
    assert_eq!(body.position, DVec3::ZERO);
    assert_eq!(body.linear_momentum, DVec3::ZERO);
    assert_eq!(body.inv_mass, 0.0);
}

#[test]
fn drag_gives_the_analytic_terminal_velocity() {
    let mass = 2.0;
    // Linear drag: m g = k v_t.
    let k = 4.0;
    let mut world = world_with(
        Integrator::Midpoint,
        vec![
            EnvironmentForce::earth_gravity(),
            EnvironmentForce::LinearDrag { coefficient: k },
        ],
    );
    let ball = add(
        &mut world,
        BodyDesc::dynamic(Shape::sphere(0.1)).with_mass(mass),
    );
    run(&mut world, 1.0 / 120.0, 120 * 20);
    // After 20 s = 40 time constants (m/k = 0.5 s) the transient is below 1e-12 of v_t.
    let expected = -mass * G / k;
    assert!((world.body(ball).velocity().y - expected).abs() < 1e-9);

    // Quadratic drag: m g = c v_t².
    let c = 0.5;
    let mut world = world_with(
        Integrator::Midpoint,
        vec![
            EnvironmentForce::earth_gravity(),
            EnvironmentForce::QuadraticDrag { coefficient: c },
        ],
    );
    let ball = add(
        &mut world,
        BodyDesc::dynamic(Shape::sphere(0.1)).with_mass(mass),
    );
    run(&mut world, 1.0 / 120.0, 120 * 20);
    let expected = -(mass * G / c).sqrt();
    assert!((world.body(ball).velocity().y - expected).abs() < 1e-9);
}

#[test]
fn wind_carries_a_weightless_body_at_the_wind_speed() {
    let wind = DVec3::new(5.0, 0.0, -2.0);
    let mut world = world_with(
        Integrator::Midpoint,
        vec![EnvironmentForce::Wind {
            velocity: wind,
            coefficient: 3.0,
        }],
    );
    let leaf = add(
        &mut world,
        BodyDesc::dynamic(Shape::sphere(0.1)).with_mass(1.0),
    );
    run(&mut world, 1.0 / 120.0, 120 * 20);
    assert!((world.body(leaf).velocity() - wind).length() < 1e-9);
}

#[test]
fn forces_edited_mid_run_take_effect_on_the_next_step() {
    let mut world = world_with(Integrator::Midpoint, gravity());
    let ball = add(&mut world, BodyDesc::dynamic(Shape::sphere(0.1)));
    run(&mut world, 0.01, 10);
    let v_before = world.body(ball).velocity();
    // Lunar gravity from now on.
    world.forces[0] = EnvironmentForce::Gravity {
        acceleration: DVec3::new(0.0, -1.62, 0.0),
    };
    world.step(0.01);
    let dv = world.body(ball).velocity() - v_before;
    assert!((dv.y + 1.62 * 0.01).abs() < 1e-14);
    world.forces.clear();
    let v = world.body(ball).velocity();
    world.step(0.01);
    assert_eq!(world.body(ball).velocity(), v);
}

#[test]
fn a_body_that_goes_non_finite_is_isolated_the_same_step() {
    let mut world = world_with(Integrator::Midpoint, gravity());
    let healthy = add(
        &mut world,
        BodyDesc::dynamic(Shape::sphere(0.1)).named("healthy"),
    );
    let broken = add(
        &mut world,
        BodyDesc::dynamic(Shape::sphere(0.1)).named("broken"),
    );
    run(&mut world, 0.01, 5);
    world
        .body_mut(broken)
        .apply_force(DVec3::new(f64::NAN, 0.0, 0.0));
    world.step(0.01);
    assert_eq!(world.faults().len(), 1);
    let fault = &world.faults()[0];
    assert_eq!(
        (fault.body, fault.name.as_str(), fault.step),
        (broken, "broken", 5)
    );
    assert_eq!(world.body(broken).motion, rigid::physics::Motion::Isolated);
    // The others go on exactly as before, and the totals stay finite.
    run(&mut world, 0.01, 94);
    assert!((world.body(healthy).velocity().y + G * 1.0).abs() < 1e-12);
    let totals = world.totals();
    assert!(totals.kinetic_energy.is_finite() && totals.linear_momentum.is_finite());
    assert_eq!(world.faults().len(), 1, "reported once");
}

#[test]
fn what_rested_on_an_isolated_body_wakes_and_falls() {
    let mut world = world_with(Integrator::Midpoint, gravity());
    let floor = Shape::cuboid(DVec3::new(5.0, 0.5, 5.0));
    add(
        &mut world,
        BodyDesc::fixed(floor).at(DVec3::new(0.0, -0.5, 0.0)),
    );
    let cube = || Shape::cuboid(DVec3::splat(0.5));
    let support = add(
        &mut world,
        BodyDesc::dynamic(cube()).at(DVec3::new(0.0, 0.5, 0.0)),
    );
    let top = add(
        &mut world,
        BodyDesc::dynamic(cube()).at(DVec3::new(0.0, 1.5, 0.0)),
    );
    let dt = 1.0 / 60.0;
    run(&mut world, dt, 600);
    assert!(
        world.body(top).sleeping,
        "the stack sleeps before the fault"
    );
    world
        .body_mut(support)
        .apply_force(DVec3::new(f64::NAN, 0.0, 0.0));
    run(&mut world, dt, 60);
    assert_eq!(world.body(support).motion, rigid::physics::Motion::Isolated);
    // Without its support the top box falls 1 m onto the floor within the second (free
    // fall takes 0.45 s), as it does when the support is removed.
    let y = world.body(top).position.y;
    assert!((y - 0.5).abs() < 0.02, "the top box is at y = {y}");
}

/// The stage profile splits a soft step's integration from its contact solve; the classic
/// pipeline interleaves them, and counts both under solve. Unasked, no stage is timed.
#[test]
fn stage_times_split_integration_from_the_contact_solve() {
    let mut world = world_with(Integrator::Midpoint, gravity());
    add(&mut world, BodyDesc::dynamic(Shape::sphere(0.1)));
    world.step(0.01);
    assert_eq!(world.stage_times(), rigid::physics::StageTimes::default());
    world.set_stage_timing(true);
    world.step(0.01);
    let t = world.stage_times();
    assert!(t.integrate > 0.0, "{t:?}");
    let sum = t.broad_phase + t.narrow_phase + t.islands + t.solve + t.integrate + t.checks;
    assert_eq!(t.total(), sum);
    world.settings.pipeline = rigid::physics::Pipeline::Classic;
    world.step(0.01);
    assert_eq!(world.stage_times().integrate, 0.0);
}

/// A body whose mass cannot be inverted, or whose momentum overflows, is refused by the
/// world with an error naming the field, as the scene loader refuses it: a sphere of 1 mm at
/// 1e-320 kg/m³ weighs 4e-329 kg, below f64 (it rounds to 0) and without a finite inverse, and 1e300 m/s on a
/// body of 1e10 kg/m³ is a momentum beyond f64.
#[test]
fn the_world_refuses_a_mass_it_cannot_invert_or_a_momentum_that_overflows() {
    use rigid::physics::{AddBodyError, BodyError};
    let mut world = World::default();
    let mut dust = BodyDesc::dynamic(Shape::sphere(1e-3));
    dust.material.density = 1e-320;
    match world.add_body(dust).unwrap_err() {
        AddBodyError::Invalid(BodyError::MassNotInvertible { field, mass, .. }) => {
            assert_eq!(field, "material.density");
            assert!((1.0 / mass).is_infinite(), "{mass}");
        }
        other => panic!("{other:?}"),
    }
    let mut bullet = BodyDesc::dynamic(Shape::sphere(1.0)).with_velocity(DVec3::X * 1e300);
    bullet.material.density = 1e10;
    match world.add_body(bullet).unwrap_err() {
        AddBodyError::Invalid(BodyError::EnergyTooLarge { field, .. }) => {
            assert_eq!(field, "velocity")
        }
        other => panic!("{other:?}"),
    }
    assert!(world.bodies().is_empty());
    // The same sphere at a plain density and speed is accepted.
    let ball = BodyDesc::dynamic(Shape::sphere(1e-3)).with_velocity(DVec3::X * 1e3);
    assert!(world.add_body(ball).is_ok());
}

/// The checked accessors answer None for an id the world does not have, where `body` and
/// `body_mut` panic, and give the same body as they do otherwise.
#[test]
fn checked_accessors_answer_none_for_a_missing_body() {
    let mut world = World::default();
    let id = world
        .add_body(BodyDesc::dynamic(Shape::sphere(0.5)).at(DVec3::Y))
        .unwrap();
    let missing = BodyId(7);
    assert!(world.get_body(missing).is_none());
    assert!(world.get_body_mut(missing).is_none());
    assert_eq!(world.get_body(id).map(|b| b.position), Some(DVec3::Y));
    world.get_body_mut(id).unwrap().position.x = 2.0;
    assert_eq!(world.body(id).position, DVec3::new(2.0, 1.0, 0.0));
    let panicked = std::panic::catch_unwind(|| World::default().body(missing).position);
    assert!(panicked.is_err());
}

#[test]
fn a_body_released_at_rest_falls_on_long_steps_instead_of_sleeping_in_mid_air() {
    // With steps as long as the time to sleep (0.5 s), the body counted its first step, at
    // rest before it moved, as quiet and fell asleep at 100 m.
    for dt in [0.5, 1.0] {
        let mut world = world_with(
            Integrator::Midpoint,
            vec![EnvironmentForce::earth_gravity()],
        );
        let ball = add(
            &mut world,
            BodyDesc::dynamic(Shape::sphere(0.5)).at(DVec3::new(0.0, 100.0, 0.0)),
        );
        run(&mut world, dt, 2);
        let body = world.body(ball);
        // Semi-implicit Euler over the substeps h: after n of them the fall is g h² n(n+1)/2.
        let substeps = world.settings.solver.substeps as f64;
        let (h, n) = (dt / substeps, 2.0 * substeps);
        let fallen = 9.81 * h * h * n * (n + 1.0) / 2.0;
        assert!(!body.sleeping, "dt {dt}: asleep at y = {}", body.position.y);
        assert!(
            (100.0 - body.position.y - fallen).abs() < 1e-9 * fallen,
            "dt {dt}: fell {} m, expected {fallen} m",
            100.0 - body.position.y
        );
    }
}

/// A floor and a stack of five 1 m boxes, settled for a second; returns the boxes.
fn settled_stack(world: &mut World) -> Vec<BodyId> {
    let floor = Shape::cuboid(DVec3::new(5.0, 0.5, 5.0));
    add(world, BodyDesc::fixed(floor).at(DVec3::Y * -0.5));
    let boxes = (0..5)
        .map(|i| {
            let at = DVec3::Y * (0.5 + i as f64);
            add(
                world,
                BodyDesc::dynamic(Shape::cuboid(DVec3::splat(0.5))).at(at),
            )
        })
        .collect();
    run(world, 1.0 / 60.0, 60);
    boxes
}

/// A finite body beyond `MAX_CONTACT_SPEED`: aimed at a stack at 1e150 m/s, its contact
/// overflowed (the NaN reached all five boxes within the step, the bottom one too, which it
/// never touched); at 1e30 m/s the stack's energy grew 1e144-fold instead; passing far away
/// it must not matter either. It is isolated with its reason the step its box meets anything,
/// and the stack stands on, finite and at rest.
#[test]
fn a_body_beyond_contact_range_is_isolated_before_it_touches_a_stack() {
    use rigid::physics::{FaultReason, Motion};
    let aimed = DVec3::new(-3.0, 2.5, 0.0);
    for (start, speed) in [
        (aimed, 1e150),
        (aimed, 1e30),
        (DVec3::new(100.0, 1.0, 0.0), 1e150),
    ] {
        let mut world = world_with(Integrator::Midpoint, gravity());
        let boxes = settled_stack(&mut world);
        let bullet = BodyDesc::dynamic(Shape::sphere(0.5)).at(start);
        let bullet = add(&mut world, bullet.with_velocity(DVec3::X * speed));
        run(&mut world, 1.0 / 60.0, 30);
        let reasons: Vec<_> = world.faults().iter().map(|f| (f.body, f.reason)).collect();
        assert_eq!(reasons, [(bullet, FaultReason::BeyondContactRange)]);
        assert_eq!(world.body(bullet).motion, Motion::Isolated);
        for (i, &id) in boxes.iter().enumerate() {
            let body = world.body(id);
            assert_eq!(body.motion, Motion::Dynamic, "box {i}");
            let speed = body.velocity().length();
            let drift = (body.position - DVec3::Y * (0.5 + i as f64)).length();
            assert!(
                speed < 0.05 && drift < 0.01,
                "box {i}: {speed} m/s, {drift} m"
            );
        }
    }
}
