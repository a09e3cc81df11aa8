//! Scene files: every built-in scene builds the bodies its generators promise, and every class
//! of bad input is reported with the file, the body and the field, never with a panic.

mod common;

use common::garble::{apply, edit_strategy, number};
use glam::DVec3;
use proptest::prelude::*;
use rigid::physics::{MAX_COMPOUND_PARTS, Motion};
use rigid::scene::{self, DEFAULT_SCENE, MAX_BODIES, SceneError, builtin_scenes, find_builtin};

const FILE: &str = "scenes/test.ron";

/// A scene with a static floor then one body with `body` as its fields; `extra` adds scene
/// fields.
fn scene_with(extra: &str, body: &str) -> String {
    format!(
        r#"Scene(
    name: "test",
    forces: [Gravity(acceleration: (0.0, -9.81, 0.0))],
    materials: {{ "rubber": (density: 1100.0, restitution: 0.8, friction: 0.9) }},
    {extra}
    bodies: [
        (name: "floor", shape: Cuboid(half_extents: (5.0, 0.1, 5.0)), static: true),
        ({body}),
    ],
)"#
    )
}

fn body_error(body: &str) -> String {
    parse_error(&scene_with("", body))
}

fn parse_error(text: &str) -> String {
    match scene::parse(text, FILE) {
        Ok(_) => panic!("accepted a bad scene:\n{text}"),
        Err(error) => error.to_string(),
    }
}

/// The message starts with the file, then names the body, then the field.
fn assert_names(message: &str, body: &str, field: &str) {
    let file_at = message.find(FILE);
    let body_at = message.find(&format!("body {body}"));
    let field_at = message.find(&format!("field '{field}'"));
    assert!(
        file_at == Some(0) && body_at.is_some() && field_at.is_some() && body_at < field_at,
        "expected file, body {body} and field '{field}' in: {message}"
    );
}

fn built_count(name: &str) -> usize {
    let scene = find_builtin(name).expect("built-in").parse().unwrap();
    scene.build_world().unwrap().bodies().len()
}

#[test]
fn built_in_scenes_have_the_bodies_their_generators_promise() {
    assert_eq!(built_count("falling_box"), 3);
    assert_eq!(built_count("bounce"), 1 + 5);
    assert_eq!(built_count("stack"), 1 + 10);
    assert_eq!(built_count("pyramid"), 1 + 20 * 21 / 2);
    assert_eq!(built_count("pyramid"), 211);
    assert_eq!(built_count("dzhanibekov"), 1);
    // back plate, 2 walls, hidden glass, bottom, 13 dividers, 15 × 21 pins, 12 × 5 balls
    assert_eq!(built_count("pachinko"), 5 + 13 + 15 * 21 + 12 * 5);
    // 5 bin walls, then spheres, boxes, capsules, cylinders
    assert_eq!(
        built_count("rain"),
        5 + 6 * 4 * 6 + 5 * 4 * 5 + 5 * 3 * 5 + 4 * 3 * 4
    );
}

#[test]
fn hull_scene_builds() {
    assert_eq!(built_count("hulls"), 7);
}

#[test]
fn every_scene_file_is_built_in_and_the_default_exists() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes");
    let mut files: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|entry| entry.unwrap().file_name().into_string().unwrap())
        .filter_map(|name| name.strip_suffix(".ron").map(str::to_owned))
        .collect();
    files.sort();
    let mut builtin: Vec<String> = builtin_scenes().iter().map(|s| s.name.to_owned()).collect();
    builtin.sort();
    assert_eq!(files, builtin);
    assert!(find_builtin(DEFAULT_SCENE).is_some());
    for scene in builtin_scenes() {
        let path = format!("{dir}/{}.ron", scene.name);
        assert_eq!(std::fs::read_to_string(path).unwrap(), scene.source);
    }
}

#[test]
fn built_in_scene_metadata_is_filled_in() {
    for builtin in builtin_scenes() {
        let scene = builtin.parse().unwrap();
        assert_eq!(scene.name, builtin.name);
        assert!(!scene.description.is_empty());
        assert_eq!(scene.origin, format!("scenes/{}.ron", builtin.name));
        assert!(scene.camera.eye.distance(scene.camera.target) > 0.5);
        assert!(scene::DT_RANGE.contains(&scene.settings.dt));
    }
}

#[test]
fn load_file_reads_a_scene_from_disk() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/stack.ron");
    let scene = scene::load_file(path).unwrap();
    assert_eq!(scene.origin, path);
    assert_eq!(scene.body_count(), 11);
    assert_eq!(scene::load("stack").unwrap().body_count(), 11);
    assert_eq!(scene::load(path).unwrap().body_count(), 11);
}

#[test]
fn pyramid_layers_are_centred_and_named_in_order() {
    let world = scene::load("pyramid").unwrap().build_world().unwrap();
    let boxes: Vec<_> = world.bodies().iter().filter(|b| b.is_dynamic()).collect();
    assert_eq!(boxes.len(), 210);
    assert_eq!(boxes[0].name, "box_0");
    assert_eq!(boxes[209].name, "box_209");
    // Bottom row from x = −9.975 to 9.975 at y = 0.5; the top box alone at x = 0, y = 19.5.
    assert!((boxes[0].position - DVec3::new(-9.975, 0.5, 0.0)).length() < 1e-12);
    assert!((boxes[19].position - DVec3::new(9.975, 0.5, 0.0)).length() < 1e-12);
    assert!((boxes[209].position - DVec3::new(0.0, 19.5, 0.0)).length() < 1e-12);
}

#[test]
fn stack_boxes_touch_face_to_face_on_the_floor() {
    let world = scene::load("stack").unwrap().build_world().unwrap();
    let boxes: Vec<_> = world.bodies().iter().filter(|b| b.is_dynamic()).collect();
    for (i, body) in boxes.iter().enumerate() {
        assert!((body.position - DVec3::new(0.0, 0.5 + i as f64, 0.0)).length() < 1e-12);
    }
}

#[test]
fn pachinko_pins_point_along_z_and_balls_start_above_them() {
    let world = scene::load("pachinko").unwrap().build_world().unwrap();
    let pins: Vec<_> = world
        .bodies()
        .iter()
        .filter(|b| b.name.starts_with("pin_"))
        .collect();
    assert_eq!(pins.len(), 315);
    for pin in &pins {
        assert_eq!(pin.motion, Motion::Static);
        // The cylinder's own axis is local y.
        assert!((pin.orientation * DVec3::Y - DVec3::Z).length() < 1e-12);
    }
    let top_pin = pins.iter().map(|p| p.position.y).fold(f64::MIN, f64::max);
    let balls: Vec<_> = world.bodies().iter().filter(|b| b.is_dynamic()).collect();
    assert_eq!(balls.len(), 60);
    assert!(balls.iter().all(|b| b.position.y - 0.018 > top_pin + 0.006));
    // Odd rows are staggered by half the pin spacing.
    assert!((pins[15].position.x - pins[0].position.x - 0.04).abs() < 1e-12);
}

#[test]
fn dzhanibekov_spins_about_the_intermediate_axis_without_gravity() {
    let world = scene::load("dzhanibekov").unwrap().build_world().unwrap();
    assert!(world.forces.is_empty());
    let body = &world.bodies()[0];
    let inertia = body.inv_inertia_local.inverse();
    let (ix, iy, iz) = (inertia.x_axis.x, inertia.y_axis.y, inertia.z_axis.z);
    assert!(
        ix < iz && iz < iy,
        "z must be the intermediate axis: {ix} {iy} {iz}"
    );
    let omega = body.angular_velocity();
    assert!(omega.z > 100.0 * omega.x.abs().max(omega.y.abs()));
}

#[test]
fn falling_box_starts_above_the_fixed_cube_off_centre_and_tilted() {
    let world = scene::load(DEFAULT_SCENE).unwrap().build_world().unwrap();
    let [platform, cube, falling] = world.bodies() else {
        panic!("three bodies expected");
    };
    assert!(!platform.is_dynamic() && !cube.is_dynamic() && falling.is_dynamic());
    assert!(falling.position.y > cube.position.y + 2.0);
    let offset = (falling.position - cube.position) * DVec3::new(1.0, 0.0, 1.0);
    assert!(offset.length() > 0.1 && offset.length() < 0.5);
    assert!(falling.rotation().angle_between(glam::DQuat::IDENTITY) > 0.1);
}

#[test]
fn bounce_balls_have_distinct_restitutions() {
    let world = scene::load("bounce").unwrap().build_world().unwrap();
    let e: Vec<f64> = world
        .bodies()
        .iter()
        .filter(|b| b.is_dynamic())
        .map(|b| b.material.restitution)
        .collect();
    assert_eq!(e, [0.0, 0.25, 0.5, 0.75, 1.0]);
}

// ---- bad input, one test per class ----

#[test]
fn syntax_error_gives_line_and_column() {
    let text = "Scene(\n    name: \"test\"\n    bodies: [],\n)";
    let error = scene::parse(text, FILE).unwrap_err();
    let SceneError::Format { line, .. } = error else {
        panic!("expected a format error, got {error}");
    };
    assert_eq!(line, 3);
    assert!(
        error.to_string().starts_with("scenes/test.ron:3:"),
        "{error}"
    );
}

#[test]
fn unknown_body_field_names_body_and_field() {
    let message = body_error(r#"name: "crate", shape: Sphere(radius: 1.0), colour: 3"#);
    assert_names(&message, "'crate'", "colour");
    assert!(message.contains("scenes/test.ron:"), "{message}");
}

#[test]
fn unknown_shape_field_names_the_path() {
    let message = body_error(r#"name: "ball", shape: Sphere(radius: 1.0, diameter: 2.0)"#);
    assert_names(&message, "'ball'", "shape.diameter");
}

#[test]
fn unknown_shape_kind_lists_the_known_ones() {
    let message = body_error(r#"name: "ball", shape: Shpere(radius: 1.0)"#);
    assert_names(&message, "'ball'", "shape");
    assert!(
        message.contains("unknown variant `Shpere`, expected one of `Sphere`"),
        "{message}"
    );
    assert!(!message.contains("ShapeSpec"), "{message}");
}

#[test]
fn unknown_field_in_unnamed_body_names_its_index() {
    let message = body_error(r#"shape: Sphere(radius: 1.0), spin: 3"#);
    assert_names(&message, "#1", "spin");
}

#[test]
fn wrong_type_names_body_and_field() {
    let message = body_error(r#"name: "ball", shape: Sphere(radius: "big")"#);
    assert_names(&message, "'ball'", "shape.radius");
}

#[test]
fn missing_shape_names_body_and_field() {
    let message = body_error(r#"name: "ghost", position: (0.0, 1.0, 0.0)"#);
    assert_names(&message, "'ghost'", "shape");
}

#[test]
fn nan_and_infinity_are_rejected() {
    let cases = [
        (r#"position: (0.0, NaN, 0.0)"#, "position.y"),
        (r#"velocity: (inf, 0.0, 0.0)"#, "velocity.x"),
        (
            r#"angular_velocity: (0.0, 0.0, -inf)"#,
            "angular_velocity.z",
        ),
        (r#"rotation: Euler(0.0, -inf, 0.0)"#, "rotation.y"),
        (r#"mass: NaN"#, "mass"),
        (
            r#"material: (density: NaN, restitution: 0.5, friction: 0.5)"#,
            "material.density",
        ),
    ];
    for (field_text, field) in cases {
        let message = body_error(&format!(
            r#"name: "ball", shape: Sphere(radius: 1.0), {field_text}"#
        ));
        assert_names(&message, "'ball'", field);
    }
    let message = body_error(r#"name: "ball", shape: Sphere(radius: NaN)"#);
    assert_names(&message, "'ball'", "shape.radius");
}

#[test]
fn non_positive_size_reads_as_documented() {
    let message = body_error(r#"name: "crate_3", shape: Cuboid(half_extents: (-1.0, 0.5, 0.5))"#);
    assert_eq!(
        message,
        "scenes/test.ron: body 'crate_3' field 'shape.half_extents.x': must be positive, got -1"
    );
    let message = body_error(r#"name: "pill", shape: Capsule(half_height: 0.0, radius: 0.1)"#);
    assert_names(&message, "'pill'", "shape.half_height");
}

#[test]
fn non_positive_mass_and_density_are_rejected() {
    let message = body_error(r#"name: "ball", shape: Sphere(radius: 1.0), mass: 0.0"#);
    assert_names(&message, "'ball'", "mass");
    assert!(message.ends_with("must be positive, got 0"), "{message}");
    let message = body_error(r#"name: "ball", shape: Sphere(radius: 1.0), mass: -2.0"#);
    assert_names(&message, "'ball'", "mass");
    let message =
        body_error(r#"name: "ball", shape: Sphere(radius: 1.0), material: (density: 0.0)"#);
    assert_names(&message, "'ball'", "material.density");
}

#[test]
fn density_too_small_for_a_finite_inverse_mass_is_rejected() {
    let message =
        body_error(r#"name: "dust", shape: Sphere(radius: 0.001), material: (density: 1e-310)"#);
    assert_names(&message, "'dust'", "material.density");
}

#[test]
fn restitution_outside_unit_interval_is_rejected() {
    let message =
        body_error(r#"name: "ball", shape: Sphere(radius: 1.0), material: (restitution: 1.5)"#);
    assert_names(&message, "'ball'", "material.restitution");
    assert!(message.contains("must lie in [0, 1], got 1.5"), "{message}");
    let text = scene_with(
        "",
        r#"name: "ball", shape: Sphere(radius: 1.0), material: "rubber""#,
    )
    .replace("restitution: 0.8", "restitution: -0.1");
    let message = parse_error(&text);
    assert!(
        message.starts_with("scenes/test.ron: material 'rubber' field 'restitution'"),
        "{message}"
    );
}

#[test]
fn negative_friction_is_rejected() {
    let message = body_error(
        r#"name: "ice", shape: Cuboid(half_extents: (1.0, 1.0, 1.0)), material: (friction: -0.2)"#,
    );
    assert_names(&message, "'ice'", "material.friction");
}

#[test]
fn unknown_material_name_is_rejected() {
    let message = body_error(r#"name: "ball", shape: Sphere(radius: 1.0), material: "rubbr""#);
    assert_names(&message, "'ball'", "material");
    assert!(
        message.contains("unknown material 'rubbr' (defined: rubber)"),
        "{message}"
    );
}

#[test]
fn unknown_field_in_inline_material_is_named() {
    let message =
        body_error(r#"name: "ball", shape: Sphere(radius: 1.0), material: (densty: 5.0)"#);
    assert_names(&message, "'ball'", "material.densty");
}

#[test]
fn degenerate_hull_is_rejected() {
    let message = body_error(
        r#"name: "sheet", shape: Hull(points: [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 1.0)])"#,
    );
    assert_names(&message, "'sheet'", "shape.points");
    assert!(message.contains("degenerate"), "{message}");
}

#[test]
fn non_finite_hull_point_is_named() {
    let message = body_error(
        r#"name: "rock", shape: Hull(points: [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, NaN, 1.0), (0.0, 1.0, 0.0)])"#,
    );
    assert_names(&message, "'rock'", "shape.points[2].y");
}

#[test]
fn bad_compound_part_is_named_by_its_path() {
    let message = body_error(
        r#"name: "l", shape: Compound(parts: [(shape: Sphere(radius: 0.5)), (shape: Cuboid(half_extents: (0.1, -0.5, 0.1)))])"#,
    );
    assert_names(&message, "'l'", "shape.parts[1].shape.half_extents.y");
    let message = body_error(
        r#"name: "nest", shape: Compound(parts: [(shape: Compound(parts: [(shape: Sphere(radius: 0.5))]))])"#,
    );
    assert_names(&message, "'nest'", "shape.parts[0].shape");
    let message = body_error(r#"name: "empty", shape: Compound(parts: [])"#);
    assert_names(&message, "'empty'", "shape.parts");
}

#[test]
fn absurd_sizes_are_rejected() {
    let message = body_error(r#"name: "planet", shape: Sphere(radius: 1e6)"#);
    assert_names(&message, "'planet'", "shape.radius");
    assert!(
        message.contains("must lie in [0.0001, 10000] m, got 1000000"),
        "{message}"
    );
    let message = body_error(r#"name: "mote", shape: Sphere(radius: 1e-6)"#);
    assert_names(&message, "'mote'", "shape.radius");
}

#[test]
fn too_many_bodies_after_generators_is_rejected() {
    let message = body_error(
        r#"name: "sand", shape: Sphere(radius: 0.01), repeat: Grid(count: (1000, 1000, 1), spacing: (0.1, 0.1, 0.1))"#,
    );
    assert!(message.starts_with(FILE), "{message}");
    assert!(message.contains("1000001 bodies"), "{message}");
    assert!(message.contains(&MAX_BODIES.to_string()), "{message}");
    // u32::MAX³ must neither overflow nor allocate.
    let message = body_error(
        r#"name: "sand", shape: Sphere(radius: 0.01), repeat: Grid(count: (4294967295, 4294967295, 4294967295), spacing: (0.1, 0.1, 0.1))"#,
    );
    assert!(message.contains("bodies after generators"), "{message}");
}

#[test]
fn a_scene_just_under_the_body_limit_is_accepted() {
    let text = scene_with(
        "",
        r#"name: "sand", shape: Sphere(radius: 0.01), repeat: Grid(count: (333, 300, 1), spacing: (0.1, 0.1, 0.1))"#,
    );
    let scene = scene::parse(&text, FILE).unwrap();
    assert_eq!(scene.body_count(), 1 + 99_900);
}

#[test]
fn bad_generator_is_named() {
    let message = body_error(
        r#"name: "pin", shape: Sphere(radius: 0.01), repeat: Grid(count: (3, 0, 1), spacing: (0.1, 0.1, 0.1))"#,
    );
    assert_names(&message, "'pin'", "repeat.count.y");
    let message = body_error(
        r#"name: "pin", shape: Sphere(radius: 0.01), repeat: Grid(count: (3, 2, 1), spacing: (0.1, NaN, 0.1))"#,
    );
    assert_names(&message, "'pin'", "repeat.spacing.y");
    let message = body_error(
        r#"name: "far", shape: Sphere(radius: 0.01), position: (1e308, 0.0, 0.0), repeat: Grid(count: (3, 1, 1), spacing: (1e308, 0.0, 0.0))"#,
    );
    assert_names(&message, "'far'", "repeat.spacing");
}

#[test]
fn zero_rotation_axis_is_rejected() {
    let message = body_error(
        r#"name: "ball", shape: Sphere(radius: 1.0), rotation: AxisAngle(axis: (0.0, 0.0, 0.0), degrees: 30.0)"#,
    );
    assert_names(&message, "'ball'", "rotation.axis");
}

#[test]
fn dt_outside_the_sane_range_is_rejected() {
    for dt in ["0.5", "0.0", "-0.01", "1e-9", "NaN", "inf"] {
        let text = scene_with(
            &format!("settings: (dt: {dt}),"),
            r#"shape: Sphere(radius: 1.0)"#,
        );
        let message = parse_error(&text);
        assert!(
            message.starts_with("scenes/test.ron: field 'settings.dt'"),
            "{message}"
        );
    }
}

#[test]
fn bad_forces_and_camera_are_named() {
    let text = scene_with("", r#"shape: Sphere(radius: 1.0)"#).replace(
        "forces: [Gravity(acceleration: (0.0, -9.81, 0.0))]",
        "forces: [Gravity(acceleration: (0.0, -9.81, 0.0)), LinearDrag(coefficient: -1.0)]",
    );
    let message = parse_error(&text);
    assert!(
        message.starts_with("scenes/test.ron: field 'forces[1].coefficient'"),
        "{message}"
    );
    let text = scene_with(
        "camera: (eye: (1.0, 1.0, 1.0), target: (1.0, 1.0, 1.0)),",
        r#"shape: Sphere(radius: 1.0)"#,
    );
    let message = parse_error(&text);
    assert!(
        message.starts_with("scenes/test.ron: field 'camera.target'"),
        "{message}"
    );
}

/// `camera.follow` names a body the scene makes; a name it does not make, or makes twice,
/// is refused naming the field.
#[test]
fn the_followed_body_must_exist_once() {
    let follow = |name: &str| {
        format!("camera: (eye: (0.0, 2.0, 9.0), target: (0.0, 0.0, 0.0), follow: \"{name}\"),")
    };
    let ball = r#"name: "ball", shape: Sphere(radius: 1.0)"#;
    let scene = scene::parse(&scene_with(&follow("ball"), ball), FILE).unwrap();
    assert_eq!(scene.followed_body().unwrap(), Some(1));
    let message = parse_error(&scene_with(&follow("bal"), ball));
    assert_eq!(
        message,
        "scenes/test.ron: field 'camera.follow': no body is named 'bal'"
    );
    let two = r#"name: "ball", shape: Sphere(radius: 1.0),
        repeat: Grid(count: (2, 1, 1), spacing: (3.0, 0.0, 0.0))"#;
    let message = parse_error(&scene_with(&follow("ball"), two));
    assert!(message.contains("'ball_0', 'ball_1'"), "{message}");
}

#[test]
fn unknown_scene_field_and_trailing_text_are_rejected() {
    let message = parse_error(&scene_with(
        "gravity: 9.81,",
        r#"shape: Sphere(radius: 1.0)"#,
    ));
    assert!(message.contains("field 'gravity'"), "{message}");
    let text = format!("{} extra", scene_with("", r#"shape: Sphere(radius: 1.0)"#));
    let message = parse_error(&text);
    assert!(message.starts_with("scenes/test.ron:"), "{message}");
}

#[test]
fn missing_file_and_unknown_scene_are_reported() {
    let error = scene::load_file("/nonexistent/dir/scene.ron").unwrap_err();
    assert!(
        error
            .to_string()
            .starts_with("/nonexistent/dir/scene.ron: cannot read"),
        "{error}"
    );
    assert!(matches!(
        scene::load("no_such_scene"),
        Err(SceneError::UnknownScene { .. })
    ));
}

// ---- no input panics ----

/// Every built-in scene's text, the fuzz's starting points.
fn sources() -> Vec<&'static str> {
    builtin_scenes().iter().map(|scene| scene.source).collect()
}

/// A two-template scene with every number a user can write taken from the arguments.
fn numeric_scene(numbers: &[f64; 15], count: u32) -> String {
    let [
        dt,
        radius,
        mass,
        density,
        restitution,
        friction,
        px,
        py,
        pz,
        vx,
        vy,
        vz,
        hx,
        hy,
        hz,
    ] = numbers.map(|x| format!("{x:?}"));
    format!(
        r#"Scene(
    name: "random",
    settings: (dt: {dt}),
    forces: [Gravity(acceleration: (0.0, -9.81, 0.0))],
    bodies: [
        (name: "ball", shape: Sphere(radius: {radius}), mass: {mass},
         position: ({px}, {py}, {pz}), velocity: ({vx}, {vy}, {vz}),
         material: (density: {density}, restitution: {restitution}, friction: {friction}),
         repeat: Grid(count: ({count}, 1, {count}), spacing: ({px}, 1.0, 1.0))),
        (name: "crate", shape: Cuboid(half_extents: ({hx}, {hy}, {hz})),
         material: (density: {density})),
    ],
)"#
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn garbled_scene_text_never_panics(
        source in 0..sources().len(),
        edits in prop::collection::vec(edit_strategy(), 1..4),
    ) {
        let mut text = sources()[source].to_owned();
        for edit in &edits {
            text = apply(&text, edit);
        }
        if let Ok(scene) = scene::parse(&text, FILE) {
            prop_assert!(scene.build_world().is_ok());
        }
    }

    #[test]
    fn random_numbers_never_panic_and_accepted_worlds_are_finite(
        numbers in prop::array::uniform15(number()),
        count in prop_oneof![0..6u32, Just(u32::MAX)],
    ) {
        match scene::parse(&numeric_scene(&numbers, count), FILE) {
            Ok(scene) => {
                let world = scene.build_world().unwrap();
                prop_assert_eq!(world.bodies().len() as u64, count as u64 * count as u64 + 1);
                prop_assert!(world.bodies().iter().all(|b| b.is_finite() && b.inv_mass.is_finite()));
            }
            Err(error) => prop_assert!(error.to_string().starts_with(FILE), "{}", error),
        }
    }
}

#[test]
fn a_field_given_twice_names_the_body_and_the_field_not_a_rust_type() {
    let message =
        body_error(r#"name: "ball", shape: Sphere(radius: 1.0), shape: Sphere(radius: 2.0)"#);
    assert_names(&message, "'ball'", "shape");
    assert!(message.ends_with("given twice"), "{message}");
    assert!(!message.contains("BodySpec"), "{message}");
    // A second name still leaves the first to name the body by.
    let message = body_error(r#"name: "ball", name: "other", shape: Sphere(radius: 1.0)"#);
    assert_names(&message, "'ball'", "name");
}

#[test]
fn a_byte_order_mark_at_the_start_of_a_scene_file_is_skipped() {
    let path = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bom.ron");
    let text = scene_with("", r#"name: "ball", shape: Sphere(radius: 1.0)"#);
    std::fs::write(&path, format!("\u{feff}{text}")).unwrap();
    let scene = scene::load_file(&path).unwrap();
    assert_eq!(scene.name, "test");
    assert_eq!(scene.build_world().unwrap().bodies().len(), 2);
}

#[test]
fn an_unknown_material_in_a_scene_without_materials_says_so() {
    let text = r#"Scene(name: "bare", bodies: [(name: "ball", shape: Sphere(radius: 1.0), material: "steel")])"#;
    let message = parse_error(text);
    assert_names(&message, "'ball'", "material");
    assert!(
        message.ends_with("unknown material 'steel' (the scene defines no materials)"),
        "{message}"
    );
    let message = body_error(r#"name: "ball", shape: Sphere(radius: 1.0), material: "steel""#);
    assert!(message.ends_with("(defined: rubber)"), "{message}");
}

/// A compound of more than `MAX_COMPOUND_PARTS` parts is refused, naming the body and the
/// field: two compounds of 3 000 parts once took 0.75 s a step.
#[test]
fn too_many_compound_parts_are_refused() {
    let part = "(shape: Sphere(radius: 0.1))";
    let parts = |count: usize| vec![part; count].join(", ");
    let message = body_error(&format!(
        r#"name: "cloud", shape: Compound(parts: [{}])"#,
        parts(MAX_COMPOUND_PARTS + 1)
    ));
    assert_names(&message, "'cloud'", "shape.parts");
    assert!(
        message.contains(&format!(
            "{} parts, more than MAX_COMPOUND_PARTS",
            MAX_COMPOUND_PARTS + 1
        )),
        "{message}"
    );
    // The most allowed builds.
    let text = scene_with(
        "",
        &format!(
            r#"name: "cloud", shape: Compound(parts: [{}])"#,
            parts(MAX_COMPOUND_PARTS)
        ),
    );
    assert!(scene::parse(&text, FILE).is_ok());
}

/// A finite speed whose kinetic energy ½ m v² is not: 1e160 m/s on a 4 kg ball gives a
/// momentum of 4e160 kg·m/s but 2e320 J, beyond f64 (it was accepted before, and the totals
/// read infinity). A spin the same; 1e150 m/s (2e300 J, below `MAX_BODY_ENERGY`) is still
/// accepted.
#[test]
fn a_speed_whose_kinetic_energy_overflows_is_refused() {
    let ball = r#"name: "bullet", shape: Sphere(radius: 0.1)"#;
    for (field, value) in [("velocity", "1e160"), ("angular_velocity", "1e162")] {
        let message = body_error(&format!("{ball}, {field}: ({value}, 0.0, 0.0)"));
        assert_names(&message, "'bullet'", field);
        assert!(message.contains("kinetic energy"), "{message}");
    }
    let text = scene_with("", &format!("{ball}, velocity: (1e150, 0.0, 0.0)"));
    let world = scene::parse(&text, FILE).unwrap().build_world().unwrap();
    assert!(world.totals().kinetic_energy.is_finite());
}

/// Twelve 7.4 m spheres spinning at 1e150 rad/s: each one's energy, 1.9e307 J, is finite,
/// but their sum overflowed and the world's totals read infinity. Each body's energy is
/// bounded by `MAX_BODY_ENERGY` (1e303 J), so that no world of accepted bodies overflows:
/// at 1e148 rad/s (1.9e303 J each, at the default density of 1000 kg/m³) the spheres are
/// refused, and at 1e147 rad/s (1.9e301 J each, 2.3e302 J in all) accepted.
#[test]
fn bodies_whose_energies_only_overflow_together_are_refused() {
    let spinning = |spin: &str| {
        let body = format!(
            r#"name: "top", shape: Sphere(radius: 7.417668584464596), position: (0.0, 20.0, 0.0),
            angular_velocity: (0.0, {spin}, 0.0),
            repeat: Grid(count: (1, 3, 4), spacing: (0.0, 20.0, 20.0))"#
        );
        scene_with("", &body)
    };
    for spin in ["1e150", "1e148"] {
        let message = parse_error(&spinning(spin));
        assert_names(&message, "'top'", "angular_velocity");
        assert!(message.contains("above 1e303"), "{message}");
    }
    let world = scene::parse(&spinning("1e147"), FILE)
        .unwrap()
        .build_world()
        .unwrap();
    let energy = world.totals().kinetic_energy;
    assert!(energy.is_finite() && energy > 1e302, "{energy:e}");
}

/// Gravity, wind and drag beyond their documented limits are refused with the force and
/// field named, as snapshots refuse them; at the limits they are accepted.
#[test]
fn forces_beyond_their_limits_are_refused() {
    use rigid::physics::{MAX_DRAG_COEFFICIENT, MAX_GRAVITY, MAX_WIND_SPEED};
    let gravity = "Gravity(acceleration: (0.0, -9.81, 0.0))";
    let cases = [
        ("Gravity(acceleration: (0.0, -1e12, 0.0))", "acceleration"),
        ("Gravity(acceleration: (0.0, -1e308, 0.0))", "acceleration"),
        (
            "Wind(velocity: (1e300, 0.0, 0.0), coefficient: 1.0)",
            "velocity",
        ),
        (
            "Wind(velocity: (1.0, 0.0, 0.0), coefficient: 1e9)",
            "coefficient",
        ),
        ("LinearDrag(coefficient: 1e9)", "coefficient"),
        ("QuadraticDrag(coefficient: 1e9)", "coefficient"),
    ];
    for (force, field) in cases {
        let text = scene_with("", r#"shape: Sphere(radius: 1.0)"#)
            .replace(gravity, &format!("{gravity}, {force}"));
        let message = parse_error(&text);
        let expected = format!("scenes/test.ron: field 'forces[1].{field}'");
        assert!(message.starts_with(&expected), "{force}: {message}");
        assert!(message.contains("at most"), "{message}");
    }
    let at_limits = format!(
        "{gravity}, Gravity(acceleration: (0.0, -{}, 0.0)), Wind(velocity: ({MAX_WIND_SPEED:e}, \
         0.0, 0.0), coefficient: {MAX_DRAG_COEFFICIENT:e}), LinearDrag(coefficient: \
         {MAX_DRAG_COEFFICIENT:e})",
        MAX_GRAVITY - 9.81
    );
    let text = scene_with("", r#"shape: Sphere(radius: 1.0)"#).replace(gravity, &at_limits);
    assert!(scene::parse(&text, FILE).is_ok());
}
