//! Joints and kinematic bodies in scene files: a pendulum read from a file keeps the analytic
//! period, a chain generator joins the right bodies, scripted kinematic bodies are where their
//! scripts say, and every bad joint or script is a typed error naming file, joint and field.

use std::f64::consts::{PI, TAU};

use glam::{DQuat, DVec3};
use rigid::physics::{BodyId, JointKind, World};
use rigid::scene::{self, Scene, SceneError};
use rigid::sim::Simulation;

const FILE: &str = "scenes/joints_test.ron";

/// A scene with gravity, a static `top` at y = 2, three balls `ball_0`…`ball_2` on a row and
/// the given extra bodies and joints.
fn scene_with(bodies: &str, joints: &str) -> String {
    format!(
        r#"Scene(
    name: "joints test",
    forces: [Gravity(acceleration: (0.0, -9.81, 0.0))],
    bodies: [
        (name: "top", shape: Cuboid(half_extents: (1.0, 0.1, 1.0)), position: (0.0, 2.0, 0.0),
         static: true),
        (name: "ball", shape: Sphere(radius: 0.05), position: (0.0, 1.0, 0.0),
         repeat: Grid(count: (3, 1, 1), spacing: (0.5, 0.0, 0.0))),
        {bodies}
    ],
    joints: [{joints}],
)"#
    )
}

fn parse(text: &str) -> Scene {
    scene::parse(text, FILE).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn error_of(text: &str) -> SceneError {
    match scene::parse(text, FILE) {
        Ok(_) => panic!("accepted a bad scene:\n{text}"),
        Err(error) => error,
    }
}

/// A `SceneError::Joint` on this joint and field, whose message starts with the file.
fn assert_joint_error(error: &SceneError, joint: &str, field: &str) {
    let message = error.to_string();
    assert!(message.starts_with(FILE), "{message}");
    match error {
        SceneError::Joint {
            joint: j, field: f, ..
        } => assert!(
            j == joint && f == field,
            "expected {joint} {field}: {message}"
        ),
        other => panic!("expected a joint error on {joint} {field}, got: {other}"),
    }
}

/// Times of the upward zero crossings of `x(t)`, interpolated linearly within a step.
fn upward_crossings(samples: &[(f64, f64)]) -> Vec<f64> {
    samples
        .windows(2)
        .filter(|w| w[0].1 < 0.0 && w[1].1 >= 0.0)
        .map(|w| w[0].0 + (w[1].0 - w[0].0) * (-w[0].1) / (w[1].1 - w[0].1))
        .collect()
}

#[test]
fn pendulum_from_a_file_swings_with_the_small_angle_period() {
    // A dense 1 cm bob, 1 m under a static pivot on a distance joint to its centre (which lets
    // it turn freely: a point mass), started 3° out.
    let length = 1.0;
    let angle = 3f64.to_radians();
    let bob = DVec3::new(length * angle.sin(), 2.0 - length * angle.cos(), 0.0);
    let text = format!(
        r#"Scene(
    name: "pendulum",
    settings: (dt: 0.001),
    forces: [Gravity(acceleration: (0.0, -9.81, 0.0))],
    bodies: [
        (name: "pivot", shape: Sphere(radius: 0.01), position: (0.0, 2.0, 0.0), static: true),
        (name: "bob", shape: Sphere(radius: 0.01), position: ({}, {}, 0.0),
         material: (density: 20000.0, restitution: 0.0, friction: 0.5)),
    ],
    joints: [(name: "rod", body_a: "pivot", body_b: "bob",
              kind: Distance(anchor_a: (0.0, 2.0, 0.0), anchor_b: ({}, {}, 0.0)))],
)"#,
        bob.x, bob.y, bob.x, bob.y
    );
    let scene = parse(&text);
    let mut world = scene.build_world().unwrap();
    assert_eq!(world.joint_count(), 1);
    let dt = scene.settings.dt;
    let mut samples = Vec::new();
    for _ in 0..(8.5 / dt) as usize {
        world.step(dt);
        samples.push((world.time(), world.bodies()[1].position.x));
    }
    let crossings = upward_crossings(&samples);
    assert!(crossings.len() >= 4, "{crossings:?}");
    let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    // The 3° amplitude lengthens the period by θ²/16 = 1.7e-4, well inside the tolerance.
    let analytic = TAU * (length / 9.81).sqrt();
    let error = (period / analytic - 1.0).abs();
    assert!(
        error < 0.01,
        "period {period} s, analytic {analytic} s: {error:e}"
    );
}

#[test]
fn chain_generator_joins_consecutive_links_and_pins_the_first() {
    let text = scene_with(
        r#"(name: "link", shape: Capsule(half_height: 0.05, radius: 0.02),
            position: (0.0, 1.8, 0.0), repeat: Grid(count: (1, 6, 1), spacing: (0.0, -0.14, 0.0))),"#,
        r#"(name: "chain", kind: Chain(links: "link", joint: Ball, pin: "top")),
           (name: "rods", kind: Chain(links: "ball", joint: Distance))"#,
    );
    let scene = parse(&text);
    let world = scene.build_world().unwrap();
    // Bodies: top (0), ball_0..2 (1..=3), link_0..5 (4..=9).
    let link = |k: u32| BodyId(4 + k);
    let joints: Vec<_> = world.joints().map(|(_, j)| *j).collect();
    assert_eq!(joints.len(), 1 + 5 + 2, "pin, 5 between 6 links, 2 rods");
    assert_eq!((joints[0].body_a, joints[0].body_b), (BodyId(0), link(0)));
    for k in 0..5 {
        let joint = &joints[1 + k as usize];
        assert_eq!((joint.body_a, joint.body_b), (link(k), link(k + 1)));
        assert_eq!(joint.kind, JointKind::Ball);
    }
    // A ball joint lies where two links meet: 7 cm above link k+1's origin (its anchor on
    // b is measured from b's centre, which is its origin for a capsule).
    for joint in &joints[..6] {
        assert!((joint.local_anchor_b - DVec3::new(0.0, 0.07, 0.0)).length() < 1e-12);
    }
    for (k, joint) in joints[6..].iter().enumerate() {
        assert_eq!(
            (joint.body_a, joint.body_b),
            (BodyId(1 + k as u32), BodyId(2 + k as u32))
        );
        assert_eq!(joint.kind, JointKind::Distance);
        assert!(
            (joint.length - 0.5).abs() < 1e-12,
            "rod {k}: {}",
            joint.length
        );
    }
}

#[test]
fn joint_options_reach_the_engine_in_its_units() {
    let text = scene_with(
        r#"(name: "door", shape: Cuboid(half_extents: (0.4, 0.5, 0.02)), position: (0.4, 0.5, 0.0)),"#,
        r#"(name: "hinge", body_a: "top", body_b: "door", limits: (-90.0, 45.0),
            kind: Hinge(anchor: (0.0, 0.5, 0.0), axis: (0.0, 2.0, 0.0)),
            motor: (speed: 1.5, max_force: 20.0), colliding: true),
           (body_a: "ball_0", body_b: "ball_1", kind: Distance(anchor_a: (0.0, 1.0, 0.0),
            anchor_b: (0.5, 1.0, 0.0)), limits: (0.2, 0.6), spring: (hertz: 3.0, damping_ratio: 0.5)),
           (body_a: "top", body_b: "ball_2", kind: Hinge(anchor: (1.0, 1.0, 0.0), axis: (0.0, 0.0, 1.0)),
            servo: (target: 30.0, hertz: 4.0, damping_ratio: 1.0, max_force: 5.0)),
           (body_a: "top", body_b: "door", kind: Slider(anchor: (0.4, 0.5, 0.0), axis: (1.0, 0.0, 0.0)),
            servo: (target: 0.25, hertz: 2.0, damping_ratio: 0.7, max_force: 50.0),
            breaking: (force: 500.0, torque: inf)),
           (body_a: "top", body_b: "ball_1", limits: (-30.0, 60.0),
            kind: ConeTwist(anchor: (0.5, 2.0, 0.0), axis: (0.0, -1.0, 0.0), cone: 45.0))"#,
    );
    let world = parse(&text).build_world().unwrap();
    let joints: Vec<_> = world.joints().map(|(_, j)| *j).collect();
    let hinge = joints[0];
    // Degrees in the file, radians in the engine.
    let (lo, hi) = hinge.limits.unwrap();
    assert!((lo + PI / 2.0).abs() < 1e-15 && (hi - PI / 4.0).abs() < 1e-15);
    assert_eq!(
        hinge.motor.map(|m| (m.speed, m.max_force)),
        Some((1.5, 20.0))
    );
    assert!(hinge.collide_connected && !joints[1].collide_connected);
    assert_eq!(joints[1].limits, Some((0.2, 0.6)));
    assert_eq!(
        joints[1].spring.map(|s| (s.hertz, s.damping_ratio)),
        Some((3.0, 0.5))
    );
    // A hinge servo's target in degrees becomes radians; a slider's stays in metres.
    let servo = joints[2].servo.unwrap();
    assert!((servo.target - PI / 6.0).abs() < 1e-15);
    assert_eq!(
        (servo.hertz, servo.damping_ratio, servo.max_force),
        (4.0, 1.0, 5.0)
    );
    assert_eq!(joints[3].servo.map(|s| s.target), Some(0.25));
    let breaking = joints[3].breaking.unwrap();
    assert_eq!((breaking.force, breaking.torque), (500.0, f64::INFINITY));
    // A cone-twist's cone and twist limits in degrees become radians.
    assert_eq!(joints[4].kind, JointKind::ConeTwist);
    assert!((joints[4].cone - PI / 4.0).abs() < 1e-15);
    let (lo, hi) = joints[4].limits.unwrap();
    assert!((lo + PI / 6.0).abs() < 1e-15 && (hi - PI / 3.0).abs() < 1e-15);
}

#[test]
fn bad_joints_name_the_file_joint_and_field() {
    let hinge = |options: &str| {
        scene_with(
            "",
            &format!(
                r#"(name: "h", body_a: "top", body_b: "ball_0",
                   kind: Hinge(anchor: (0.0, 1.0, 0.0), axis: (0.0, 0.0, 1.0)){options})"#
            ),
        )
    };
    let cases: &[(String, &str, &str, &str)] = &[
        (
            scene_with(
                "",
                r#"(name: "a", body_a: "top", body_b: "bob", kind: Ball(anchor: (0.0, 1.0, 0.0)))"#,
            ),
            "'a'",
            "body_b",
            "no body is named 'bob'",
        ),
        (
            // A generated body is named by its copy; the template's name alone is not a body.
            scene_with(
                "",
                r#"(body_a: "top", body_b: "ball", kind: Ball(anchor: (0.0, 1.0, 0.0)))"#,
            ),
            "#0",
            "body_b",
            "'ball_0', 'ball_1'",
        ),
        (
            scene_with(
                r#"(name: "twin", shape: Sphere(radius: 0.1), position: (3.0, 1.0, 0.0)),
                   (name: "twin", shape: Sphere(radius: 0.1), position: (4.0, 1.0, 0.0)),"#,
                r#"(name: "t", body_a: "twin", body_b: "top", kind: Ball(anchor: (3.0, 1.0, 0.0)))"#,
            ),
            "'t'",
            "body_a",
            "2 bodies are named 'twin'",
        ),
        (
            scene_with(
                "",
                r#"(name: "m", body_b: "top", kind: Ball(anchor: (0.0, 1.0, 0.0)))"#,
            ),
            "'m'",
            "body_a",
            "missing",
        ),
        (
            hinge(", limits: (30.0, -30.0)"),
            "'h'",
            "limits",
            "must be in order",
        ),
        (
            hinge(", spring: (hertz: 2.0, damping_ratio: 1.0)"),
            "'h'",
            "spring",
            "no such spring",
        ),
        (
            hinge(", motor: (speed: 1.0, max_force: -2.0)"),
            "'h'",
            "motor.max_force",
            "must not be negative",
        ),
        (hinge(", limits: (NaN, 1.0)"), "'h'", "limits.0", "finite"),
        (
            scene_with(
                "",
                r#"(name: "s", body_a: "ball_1", body_b: "ball_1", kind: Ball(anchor: (0.5, 1.0, 0.0)))"#,
            ),
            "'s'",
            "body_b",
            "two bodies",
        ),
        (
            scene_with(
                "",
                r#"(name: "d", body_a: "top", body_b: "ball_0", kind: Distance(anchor_a: (0.0, 1.0, 0.0), anchor_b: (0.0, 1.0, 0.0)))"#,
            ),
            "'d'",
            "kind.anchor_b",
            "must not coincide",
        ),
        (
            scene_with(
                "",
                r#"(name: "i", body_a: "top", body_b: "ball_0", kind: Ball(anchor: (0.0, inf, 0.0)))"#,
            ),
            "'i'",
            "kind.anchor.y",
            "finite",
        ),
        (
            scene_with(
                r#"(name: "floor", shape: Sphere(radius: 0.1), position: (5.0, 0.0, 0.0), static: true),"#,
                r#"(name: "n", body_a: "top", body_b: "floor", kind: Ball(anchor: (0.0, 1.0, 0.0)))"#,
            ),
            "'n'",
            "body_b",
            "neither body",
        ),
        (
            scene_with(
                "",
                r#"(name: "c", kind: Chain(links: "ball", joint: Ball, pin: "roof"))"#,
            ),
            "'c'",
            "kind.pin",
            "no body is named 'roof'",
        ),
        (
            scene_with("", r#"(name: "c", kind: Chain(links: "top", joint: Ball))"#),
            "'c'",
            "kind.links",
            "has a repeat",
        ),
        (
            // Limits on a chain of ball joints: the first joint it makes is named.
            scene_with(
                "",
                r#"(name: "c", kind: Chain(links: "ball", joint: Ball), limits: (0.0, 1.0))"#,
            ),
            "'c'[0]",
            "limits",
            "no such limits",
        ),
        (
            scene_with(
                "",
                r#"(name: "c", body_a: "top", kind: Chain(links: "ball", joint: Ball))"#,
            ),
            "'c'",
            "body_a",
            "kind.links",
        ),
    ];
    for (text, joint, field, words) in cases {
        let error = error_of(text);
        assert_joint_error(&error, joint, field);
        assert!(
            error.to_string().contains(words),
            "'{words}' not in: {error}"
        );
    }
    // A zero hinge axis.
    let error = error_of(&scene_with(
        "",
        r#"(name: "z", body_a: "top", body_b: "ball_0",
            kind: Hinge(anchor: (0.0, 1.0, 0.0), axis: (0.0, 0.0, 0.0)))"#,
    ));
    assert_joint_error(&error, "'z'", "kind.axis");
    assert!(
        error.to_string().contains("axis must not be zero"),
        "{error}"
    );
}

#[test]
fn unknown_joint_fields_are_format_errors_naming_the_joint_and_field() {
    let text = scene_with(
        "",
        r#"(name: "a", body_a: "top", body_b: "ball_0", kind: Ball(anchor: (0.0, 1.0, 0.0))),
           (name: "b", body_a: "top", body_b: "ball_1", kind: Ball(anchor: (0.5, 1.0, 0.0)), stiffness: 3.0)"#,
    );
    match error_of(&text) {
        SceneError::Format {
            file, field, line, ..
        } => {
            assert_eq!(file, FILE);
            assert_eq!(field.as_deref(), Some("joints[1].stiffness"));
            assert_eq!(line, 12, "the line of the unknown field");
        }
        other => panic!("expected a format error, got {other}"),
    }
    let text = scene_with(
        "",
        r#"(body_a: "top", body_b: "ball_0", kind: Hinge(anchor: (0.0, 1.0, 0.0), axle: (0.0, 0.0, 1.0)))"#,
    );
    let message = error_of(&text).to_string();
    assert!(
        message.starts_with(FILE) && message.contains("field 'joints[0].kind.axle'"),
        "{message}"
    );
}

/// A scene whose only moving body is the kinematic `platform`, with this script.
fn kinematic_scene(script: &str) -> Scene {
    parse(&format!(
        r#"Scene(
    name: "kinematic test",
    settings: (dt: 0.01),
    bodies: [(name: "platform", shape: Cuboid(half_extents: (0.5, 0.1, 0.5)),
              position: (1.0, 2.0, 3.0), rotation: Euler(0.0, 30.0, 0.0), kinematic: {script})],
)"#
    ))
}

/// Steps the scene's world `steps` times, driving its scripts as the viewer and headless do.
fn run(scene: &Scene, steps: usize) -> World {
    let mut world = scene.build_world().unwrap();
    let scripts = scene.scripted_motions().unwrap();
    for _ in 0..steps {
        scene::drive(&scripts, &mut world, scene.settings.dt);
        world.step(scene.settings.dt);
    }
    world
}

/// The platform's shape origin and rotation (its shape is centred, so its origin is its
/// centre of mass).
fn platform_pose(world: &World) -> (DVec3, DQuat) {
    let body = &world.bodies()[0];
    (body.position, body.rotation())
}

#[test]
fn a_sinusoidal_kinematic_body_is_at_its_analytic_pose() {
    let scene = kinematic_scene(
        "Sinusoid(axis: (0.0, 0.0, 2.0), amplitude: 0.4, angle_axis: (1.0, 0.0, 0.0), \
         angle_amplitude: 25.0, frequency: 0.7, phase: 30.0)",
    );
    let rest = DQuat::from_rotation_y(30f64.to_radians());
    let pose = |t: f64| {
        let s = (TAU * 0.7 * t + 30f64.to_radians()).sin();
        let turn = DQuat::from_rotation_x((25.0 * s).to_radians());
        (DVec3::new(1.0, 2.0, 3.0 + 0.4 * s), turn * rest)
    };
    for steps in [0, 1, 37, 250] {
        let world = run(&scene, steps);
        let t = steps as f64 * 0.01;
        let (position, rotation) = platform_pose(&world);
        let (expected, expected_rotation) = pose(t);
        let error = position.distance(expected);
        assert!(
            error < 1e-9,
            "after {steps} steps: {position} vs {expected} ({error:e} m)"
        );
        let angle = rotation.angle_between(expected_rotation);
        assert!(
            angle < 1e-9,
            "after {steps} steps: rotation off by {angle:e} rad"
        );
    }
}

#[test]
fn a_constant_velocity_kinematic_body_moves_v_t() {
    let scene = kinematic_scene("Velocity(linear: (0.5, -0.25, 2.0), angular: (0.0, 1.2, 0.0))");
    let world = run(&scene, 300);
    let t = 3.0;
    let (position, rotation) = platform_pose(&world);
    let expected = DVec3::new(1.0, 2.0, 3.0) + DVec3::new(0.5, -0.25, 2.0) * t;
    assert!(
        position.distance(expected) < 1e-9,
        "{position} vs {expected}"
    );
    let expected_rotation = DQuat::from_rotation_y(30f64.to_radians() + 1.2 * t);
    let angle = rotation.angle_between(expected_rotation);
    assert!(angle < 1e-9, "rotation off by {angle:e} rad");
    assert_eq!(world.bodies()[0].velocity(), DVec3::new(0.5, -0.25, 2.0));
}

#[test]
fn bad_scripts_name_the_file_body_and_field() {
    let scene = |script: &str, extra: &str| {
        format!(
            r#"Scene(name: "k", bodies: [(name: "p", shape: Sphere(radius: 0.1), kinematic: {script}{extra})])"#
        )
    };
    let cases = [
        (
            scene("Sinusoid(amplitude: 1.0, frequency: -1.0)", ""),
            "kinematic.frequency",
            "must not be negative",
        ),
        (
            scene("Sinusoid(amplitude: 1.0, frequency: inf)", ""),
            "kinematic.frequency",
            "finite",
        ),
        (
            scene("Sinusoid(amplitude: NaN, frequency: 1.0)", ""),
            "kinematic.amplitude",
            "finite",
        ),
        (
            scene("Sinusoid(angle_amplitude: inf, frequency: 1.0)", ""),
            "kinematic.angle_amplitude",
            "finite",
        ),
        (
            scene(
                "Sinusoid(amplitude: 1.0, axis: (0.0, 0.0, 0.0), frequency: 1.0)",
                "",
            ),
            "kinematic.axis",
            "must not be zero",
        ),
        (
            scene("Sinusoid(frequency: 1.0, phase: NaN)", ""),
            "kinematic.phase",
            "finite",
        ),
        (
            scene("Velocity(linear: (1.0, inf, 0.0))", ""),
            "kinematic.linear.y",
            "finite",
        ),
        (
            scene("Velocity(angular: (1.0, 0.0, 0.0))", ", static: true"),
            "kinematic",
            "static or kinematic",
        ),
        (
            scene(
                "Velocity(angular: (1.0, 0.0, 0.0))",
                ", velocity: (1.0, 0.0, 0.0)",
            ),
            "velocity",
            "give its velocity in kinematic",
        ),
    ];
    for (text, field, words) in cases {
        let error = scene::parse(&text, FILE).expect_err(&text);
        let message = error.to_string();
        assert!(
            matches!(&error, SceneError::Body { file, body, field: f, .. }
                if file == FILE && body == "'p'" && f == field),
            "expected body 'p' field '{field}': {message}"
        );
        assert!(message.contains(words), "'{words}' not in: {message}");
    }
    let text = scene("Sinusoid(frequency: 1.0, speed: 2.0)", "");
    let message = scene::parse(&text, FILE).expect_err(&text).to_string();
    assert!(
        message.contains("body 'p' field 'kinematic.speed'"),
        "{message}"
    );
}

#[test]
fn the_built_in_joint_scenes_hold_their_joints_and_run() {
    let scenes = [
        ("cradle_strings", 10, 0),
        ("chain", 20, 1),
        ("rope_bridge", 15, 0),
        ("car", 4, 0),
        ("door", 1, 0),
        ("ragdolls", 80, 0),
        ("windmills", 0, 3),
    ];
    for (name, joints, kinematic) in scenes {
        let (scene, mut world) = built_in(name);
        let scripts = scene.scripted_motions().unwrap();
        assert_eq!(scripts.len(), kinematic, "{name}");
        assert_eq!(world.joint_count(), joints, "{name}");
        for _ in 0..600 {
            scene::drive(&scripts, &mut world, scene.settings.dt);
            world.step(scene.settings.dt);
        }
        assert!(world.faults().is_empty(), "{name}: {:?}", world.faults());
        // No joint came apart: each anchor pair within 2 mm after 2.5 s.
        for (id, joint) in world.joints() {
            let gap = anchor_gap(&world, joint);
            assert!(gap < 2e-3, "{name}: joint {id:?} apart by {gap} m");
        }
    }
}

/// The rope bridge catches the three crates dropped on it and holds them on its deck: after
/// 10 s each crate's centre is between 1 and 2 m up (on the deck, which hangs from 2 m and
/// sags about 0.8 m; a crate on the ground would be at 0.2 m) and within the deck's 1 m
/// width.
#[test]
fn the_rope_bridge_catches_its_crates() {
    let (scene, mut world) = built_in("rope_bridge");
    for _ in 0..2400 {
        world.step(scene.settings.dt);
    }
    for name in ["crate_a", "crate_b", "crate_c"] {
        let crate_body = world.bodies().iter().find(|b| b.name == name).unwrap();
        let p = crate_body.position;
        assert!(p.y > 1.0 && p.y < 2.0, "{name} at height {} m", p.y);
        assert!(
            p.x.abs() < 2.85 && p.z.abs() < 0.5,
            "{name} off the deck at {p}"
        );
    }
}

/// The car drives over its hill. On the flat, its motors (10 rad/s on wheels of 0.3 m)
/// roll it at ω r = 3 m/s: within 1 % at 1.5 s, 1 s after it reached that speed. It climbs
/// the 0.8 m hill, its chassis rising by more than 0.7 m, tilts no further than 25° (the
/// slopes are 15°), and is past the hill's far foot (x = 10) within 6 s.
#[test]
fn the_car_drives_over_its_hill() {
    let (scene, mut world) = built_in("car");
    let chassis = body_named(&world, "chassis");
    let dt = scene.settings.dt;
    let start_height = world.bodies()[chassis].position.y;
    let (mut highest, mut steepest, mut past_hill) = (start_height, 0.0f64, false);
    for step in 1..=(6.0 / dt).round() as usize {
        world.step(dt);
        let body = &world.bodies()[chassis];
        if step == (1.5 / dt).round() as usize {
            let speed = body.velocity().x;
            assert!((speed - 3.0).abs() < 0.03, "speed on the flat {speed} m/s");
        }
        highest = highest.max(body.position.y);
        steepest = steepest.max((body.orientation * DVec3::Y).angle_between(DVec3::Y));
        past_hill |= body.position.x > 10.0;
    }
    let rise = highest - start_height;
    assert!(rise > 0.7, "the chassis rose {rise} m");
    assert!(
        steepest.to_degrees() < 25.0,
        "tilted {}°",
        steepest.to_degrees()
    );
    assert!(past_hill, "not past the hill after 6 s");
}

/// The door's hinge holds its limits: the thrown ball knocks the door open to its 100° stop
/// (past 95°) and no further than 1° beyond it, nor ever more than 1° behind its shut
/// position, 0°; the ball goes through, and the closer (a servo toward 0°) has the door
/// back within 5° of shut after 4 s, and asleep within 0.1° of shut after 6 s.
#[test]
fn the_door_swings_within_its_limits() {
    let (scene, mut world) = built_in("door");
    let ball = body_named(&world, "ball");
    let dt = scene.settings.dt;
    let angle = |world: &World| world.joints().next().unwrap().1.angle.to_degrees();
    let (mut widest, mut narrowest) = (0.0f64, 0.0f64);
    for _ in 0..(4.0 / dt).round() as usize {
        world.step(dt);
        widest = widest.max(angle(&world));
        narrowest = narrowest.min(angle(&world));
    }
    assert!(widest > 95.0 && widest < 101.0, "opened to {widest}°");
    assert!(narrowest > -1.0, "swung to {narrowest}°");
    let ball_z = world.bodies()[ball].position.z;
    assert!(ball_z < -1.0, "the ball is at z = {ball_z} m");
    assert!(
        angle(&world) < 5.0,
        "still open {}° after 4 s",
        angle(&world)
    );
    // The closer's last creep is far below the sleep speed: it must still shut the door
    // before the door sleeps (it stopped 1.15° ajar when it slept at the sleep speed).
    for _ in 0..(2.0 / dt).round() as usize {
        world.step(dt);
    }
    let door = body_named(&world, "door");
    assert!(world.bodies()[door].sleeping, "the door is awake after 6 s");
    assert!(
        angle(&world).abs() < 0.1,
        "asleep {}° ajar after 6 s",
        angle(&world)
    );
}

/// The ragdolls' limbs bend only within their limits while they fall into a pile: over 6 s,
/// no elbow or knee hinge leaves its 0–140° by more than 3°, and no cone-twist joint swings
/// past its cone by more than 3°; at the end every part rests above the floor.
#[test]
fn the_ragdolls_bend_within_their_limits() {
    let (scene, mut world) = built_in("ragdolls");
    let dt = scene.settings.dt;
    let (mut past_hinge, mut past_cone) = (0.0f64, 0.0f64);
    for _ in 0..(6.0 / dt).round() as usize {
        world.step(dt);
        for (_, joint) in world.joints() {
            match joint.kind {
                JointKind::Hinge => {
                    let (lo, hi) = joint.limits.unwrap();
                    past_hinge = past_hinge.max(lo - joint.angle).max(joint.angle - hi);
                }
                JointKind::ConeTwist => {
                    let swing = swing(&world, joint);
                    past_cone = past_cone.max(swing - joint.cone);
                }
                _ => unreachable!("the ragdolls have hinges and cone-twists only"),
            }
        }
    }
    assert!(
        past_hinge.to_degrees() < 3.0,
        "a hinge {}° past its limit",
        past_hinge.to_degrees()
    );
    assert!(
        past_cone.to_degrees() < 3.0,
        "a cone {}° past its limit",
        past_cone.to_degrees()
    );
    assert!(world.faults().is_empty(), "{:?}", world.faults());
    for body in world.bodies().iter().filter(|b| b.is_dynamic()) {
        assert!(body.position.y > 0.0, "{} at {}", body.name, body.position);
    }
}

/// The angle between a cone-twist joint's two axes, each carried by its body.
fn swing(world: &World, joint: &rigid::physics::Joint) -> f64 {
    let a = &world.bodies()[joint.body_a.index()];
    let b = &world.bodies()[joint.body_b.index()];
    let axis_a = a.orientation * joint.local_axis_a;
    let axis_b = b.orientation * joint.local_axis_b;
    axis_a.angle_between(axis_b)
}

/// A built-in scene and the world it builds.
fn built_in(name: &str) -> (Scene, World) {
    let scene = scene::find_builtin(name).unwrap().parse().unwrap();
    let world = scene.build_world().unwrap();
    (scene, world)
}

/// The index of the body called `name`.
fn body_named(world: &World, name: &str) -> usize {
    let index = world.bodies().iter().position(|b| b.name == name);
    index.unwrap_or_else(|| panic!("no body called {name}"))
}

/// How far a joint's anchors are from where it holds them: coinciding (ball), or its length
/// apart (distance).
fn anchor_gap(world: &World, joint: &rigid::physics::Joint) -> f64 {
    let a = &world.bodies()[joint.body_a.index()];
    let b = &world.bodies()[joint.body_b.index()];
    let pa = a.position + a.orientation * joint.local_anchor_a;
    let pb = b.position + b.orientation * joint.local_anchor_b;
    match joint.kind {
        JointKind::Distance => (pa.distance(pb) - joint.length).abs(),
        _ => pa.distance(pb),
    }
}

#[test]
fn the_viewer_simulation_drives_the_scripts() {
    // The viewer steps at its own dt (1/120 s), not the scene's; the paddle follows its
    // script at the world's time all the same.
    let scene = scene::find_builtin("chain").unwrap().parse().unwrap();
    let script = scene.scripted_motions().unwrap()[0];
    let mut sim = Simulation::new("chain").unwrap();
    for _ in 0..90 {
        sim.step();
    }
    let world = sim.world();
    assert!((world.time() - 0.75).abs() < 1e-12);
    let (expected, _) = script.pose_at(world.time());
    let paddle = &world.bodies()[script.body.index()];
    let error = paddle.position.distance(expected);
    assert!(
        error < 1e-9,
        "paddle at {} vs {expected}: {error:e} m",
        paddle.position
    );
    // Started at the far left (phase −90°), it has moved 0.5 (1 − cos(2π 0.25 0.75)) m.
    let travel = 0.5 * (1.0 - (TAU * 0.25 * 0.75).cos());
    assert!((paddle.position.x - (-0.5 + travel)).abs() < 1e-9);
}

#[test]
fn the_string_cradle_passes_the_striker_speed_to_the_last_ball() {
    let (scene, mut world) = built_in("cradle_strings");
    let speed = |world: &World, name: &str| {
        let body = world.bodies().iter().find(|b| b.name == name).unwrap();
        body.velocity().x
    };
    let (mut striker, mut last) = (0f64, 0f64);
    for _ in 0..(1.5 / scene.settings.dt) as usize {
        world.step(scene.settings.dt);
        striker = striker.max(speed(&world, "striker"));
        last = last.max(speed(&world, "ball_3"));
    }
    // Four impacts at e = 0.95 between equal balls leave 0.975⁴ = 0.90 of the speed.
    let ratio = last / striker;
    assert!(
        ratio > 0.85,
        "last ball {last} m/s, striker {striker} m/s: {ratio}"
    );
}

/// The windmills turn at their set rates while the balls fall through them: after 12 s each
/// windmill has turned by exactly ω t about the board's normal (3 rad/s, the middle one
/// −3 rad/s: within 1e-9 rad, a kinematic body follows its velocity exactly); at least 10
/// balls were batted by a blade; no ball left the board (inside the walls, above the bottom,
/// between the back plate and the glass); nothing was isolated; and at least 50 of the 60
/// balls are in the bins (some jam among the pins, as in a real machine).
#[test]
fn the_windmills_turn_at_their_rates_and_bat_the_balls() {
    let (scene, mut world) = built_in("windmills");
    let scripts = scene.scripted_motions().unwrap();
    let dt = scene.settings.dt;
    let windmills = [
        ("left_windmill", 3.0),
        ("middle_windmill", -3.0),
        ("right_windmill", 3.0),
    ]
    .map(|(name, spin)| (body_named(&world, name), spin));
    let mut batted = std::collections::BTreeSet::<usize>::new();
    let steps = (12.0 / dt).round() as usize;
    for _ in 0..steps {
        scene::drive(&scripts, &mut world, dt);
        world.step(dt);
        for manifold in world.contacts() {
            let pair = [manifold.body_a.index(), manifold.body_b.index()];
            if windmills.iter().any(|&(w, _)| pair.contains(&w)) {
                let balls = pair
                    .iter()
                    .filter(|&&i| world.bodies()[i].name.starts_with("ball"));
                batted.extend(balls);
            }
        }
    }
    let time = steps as f64 * dt;
    for &(index, spin) in &windmills {
        let body = &world.bodies()[index];
        let expected = DQuat::from_rotation_z(spin * time);
        let turned = DQuat::from_mat3(&body.orientation);
        let error = turned.angle_between(expected);
        assert!(error < 1e-9, "{} is {error} rad off its turn", body.name);
    }
    assert!(
        batted.len() >= 10,
        "only {} balls met a windmill",
        batted.len()
    );
    assert!(world.faults().is_empty(), "{:?}", world.faults());
    let balls: Vec<_> = (world.bodies().iter())
        .filter(|b| b.name.starts_with("ball"))
        .collect();
    assert_eq!(balls.len(), 60);
    for ball in &balls {
        let p = ball.position;
        let on_board = p.x.abs() < 0.66 && p.y > 0.0 && p.y < 3.0 && p.z > 0.0 && p.z < 0.05;
        assert!(on_board, "{} left the board: {p}", ball.name);
    }
    let binned = balls.iter().filter(|b| b.position.y < 0.16).count();
    assert!(binned >= 50, "{binned} balls in the bins");
}
