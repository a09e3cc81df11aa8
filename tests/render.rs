//! Offscreen render tests: the built-in scenes against golden images, and checks that fail
//! when something that should be drawn is not (a body, the AABB overlay, the sleep colour).
//!
//! Needs a graphics adapter; without a GPU, Mesa's lavapipe (`mesa-vulkan-drivers`) or
//! llvmpipe (GL) does. With no adapter at all the tests fail, they never pass silently.
//!
//! Regenerate the goldens with `UPDATE_GOLDEN=1 cargo test --test render`.

#![cfg(feature = "viewer")]

use std::path::PathBuf;

use glam::Vec3;
use image::codecs::gif::GifDecoder;
use image::{AnimationDecoder, Rgba, RgbaImage};
use rigid::physics::BroadPhaseKind;
use rigid::render::lines::{AABB_COLOR, BROAD_PHASE_COLOR, GRID_CELL_COLOR, JOINT_COLOR};
use rigid::render::renderer::{PALETTE, SLEEP_COLOR};
use rigid::render::{Gpu, OrbitCamera, Overlays, headless, record};
use rigid::sim::{Command, Simulation, Snapshot};

const SIZE: (u32, u32) = (480, 320);
/// A pixel differs from the golden when a channel differs by more than this (of 255):
/// absorbs rounding between drivers (lavapipe vs llvmpipe GL) on edges and gradients.
const CHANNEL_TOLERANCE: u8 = 24;
/// An image matches its golden when at most this fraction of its pixels differ.
const MAX_DIFFERING_FRACTION: f64 = 0.005;

fn gpu() -> Gpu {
    Gpu::offscreen().unwrap_or_else(|e| panic!("render tests need a graphics adapter: {e}"))
}

fn render(gpu: &Gpu, snapshot: &Snapshot, overlays: Overlays) -> RgbaImage {
    headless::render_snapshot(gpu, snapshot, overlays, SIZE).expect("offscreen render")
}

fn simulate(scene: &str, steps: u32) -> Snapshot {
    headless::simulate(scene, steps).expect("scene builds")
}

fn differs(a: &Rgba<u8>, b: &Rgba<u8>) -> bool {
    a.0.iter()
        .zip(b.0)
        .any(|(x, y)| x.abs_diff(y) > CHANNEL_TOLERANCE)
}

/// Pixels (x, y) where the two images differ beyond the tolerance.
fn differing_pixels(a: &RgbaImage, b: &RgbaImage) -> Vec<(u32, u32)> {
    assert_eq!(a.dimensions(), b.dimensions());
    a.enumerate_pixels()
        .filter(|(x, y, p)| differs(p, b.get_pixel(*x, *y)))
        .map(|(x, y, _)| (x, y))
        .collect()
}

fn golden_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/golden/{name}.png"))
}

/// Compares with `tests/golden/NAME.png`, or writes it when UPDATE_GOLDEN is set. On a
/// mismatch the rendered image is kept next to the test binary's temp dir for inspection.
fn check_golden(name: &str, image: &RgbaImage) {
    let path = golden_path(name);
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        image.save(&path).expect("write golden");
        return;
    }
    let golden = image::open(&path)
        .unwrap_or_else(|e| {
            panic!(
                "missing golden {}: {e}; run with UPDATE_GOLDEN=1",
                path.display()
            )
        })
        .to_rgba8();
    assert_eq!(golden.dimensions(), image.dimensions(), "{name}: size");
    let differing = differing_pixels(&golden, image).len();
    let fraction = differing as f64 / (SIZE.0 * SIZE.1) as f64;
    if fraction > MAX_DIFFERING_FRACTION {
        let actual = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{name}.actual.png"));
        image.save(&actual).expect("write actual image");
        panic!(
            "{name}: {differing} pixels ({:.2} %) differ from {} by more than {CHANNEL_TOLERANCE}/255 \
             (allowed {:.2} %); rendered image saved to {}",
            fraction * 100.0,
            path.display(),
            MAX_DIFFERING_FRACTION * 100.0,
            actual.display()
        );
    }
}

/// A built-in scene after 30 steps, without overlays, against its golden image.
fn check_scene_golden(gpu: &Gpu, scene: &str) {
    check_golden(
        scene,
        &render(gpu, &simulate(scene, 30), Overlays::default()),
    );
}

#[test]
fn falling_box_matches_golden() {
    check_scene_golden(&gpu(), "falling_box");
}

#[test]
fn pachinko_matches_golden() {
    check_scene_golden(&gpu(), "pachinko");
}

#[test]
fn hulls_match_golden() {
    check_scene_golden(&gpu(), "hulls");
}

#[test]
fn bounce_stack_spin_and_rain_match_goldens() {
    let gpu = gpu();
    for scene in ["bounce", "stack", "dzhanibekov", "rain"] {
        check_scene_golden(&gpu, scene);
    }
}

/// The scenes of joints and kinematic bodies: the cradle's pulled ball, the chain with its
/// paddle, which only moves if the simulation drives its script, the rope bridge's
/// sagging deck with its hinges drawn, the car on its wheels' hinges before its hill, the
/// door with the ball thrown at it, the ragdolls falling, and the pachinko's windmills.
#[test]
fn joint_scenes_match_goldens() {
    let gpu = gpu();
    let scenes = [
        "cradle_strings",
        "chain",
        "rope_bridge",
        "car",
        "door",
        "ragdolls",
        "windmills",
    ];
    for scene in scenes {
        check_scene_golden(&gpu, scene);
    }
}

/// The pyramid once every box sleeps, in the sleep colour: a golden that fails if the tint
/// is lost.
#[test]
fn sleeping_pyramid_matches_golden() {
    let gpu = gpu();
    let snapshot = simulate("pyramid", 1200);
    let dynamic: Vec<_> = snapshot.bodies.iter().filter(|b| b.is_dynamic).collect();
    assert_eq!(dynamic.len(), 210);
    let awake = dynamic.iter().filter(|b| !b.sleeping).count();
    assert_eq!(awake, 0, "{awake} boxes still awake after 1200 steps");
    let image = render(&gpu, &snapshot, Overlays::default());
    let region = ((0.0, 0.0), (SIZE.0 as f32, SIZE.1 as f32));
    assert!(
        count_sleep_hue(&image, region) > 5000,
        "the sleeping pyramid is not drawn in the sleep colour"
    );
    check_golden("pyramid_asleep", &image);
}

#[test]
fn contact_overlay_draws_the_contact_normals_only_when_on() {
    let gpu = gpu();
    let snapshot = simulate("pachinko", 240);
    let normal_colour = snapshot
        .lines
        .last()
        .expect("balls touch pins after 2 s")
        .color;
    let on = Overlays {
        contacts: true,
        ..Overlays::default()
    };
    let off = Overlays {
        contacts: false,
        ..Overlays::default()
    };
    let with = count_near(&render(&gpu, &snapshot, on), normal_colour);
    let without = count_near(&render(&gpu, &snapshot, off), normal_colour);
    assert!(
        with > without + 100,
        "contact overlay drew {with} pixels of the normal colour, {without} without it"
    );
}

/// The bodies in front of a contact hide it, unless in x-ray: in the rain's pile, seen over
/// the bin's front wall, the contacts inside the pile and behind the wall are hidden by
/// default, while those on the pile's top still show.
#[test]
fn bodies_hide_the_contacts_behind_them_unless_in_x_ray() {
    let gpu = gpu();
    let snapshot = simulate("rain", 600);
    let normal_colour = snapshot.lines.last().expect("the pile touches").color;
    let x_ray = Overlays {
        x_ray: true,
        ..Overlays::default()
    };
    let tested = count_near(&render(&gpu, &snapshot, Overlays::default()), normal_colour);
    let through = count_near(&render(&gpu, &snapshot, x_ray), normal_colour);
    println!("contact pixels: {tested} with the bodies hiding them, {through} in x-ray");
    assert!(
        tested > 30,
        "only {tested} contact pixels on the pile's top"
    );
    assert!(
        through > 2 * tested,
        "{through} contact pixels in x-ray, {tested} with the bodies hiding them"
    );
}

/// `rigid render` draws what the library draws: its PNG matches the same golden.
#[test]
fn the_render_command_writes_the_scene_as_a_png() {
    let output_path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("render-command.png");
    let _ = std::fs::remove_file(&output_path);
    let (width, height) = (SIZE.0.to_string(), SIZE.1.to_string());
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_rigid"))
        .arg("render")
        .arg(&output_path)
        .args(["--scene", "pachinko", "--steps", "30"])
        .args(["--width", &width, "--height", &height])
        .output()
        .expect("run rigid render");
    assert!(
        run.status.success(),
        "rigid render failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let image = image::open(&output_path).expect("a PNG").to_rgba8();
    check_golden("pachinko", &image);

    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_rigid"))
        .arg("render")
        .arg(&output_path)
        .args(["--scene", "no_such_scene"])
        .output()
        .expect("run rigid render");
    assert!(!bad.status.success());
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert!(stderr.contains("no_such_scene"), "{stderr}");
}

#[test]
fn overlays_match_golden() {
    let gpu = gpu();
    let overlays = Overlays {
        aabbs: true,
        velocities: true,
        ..Overlays::default()
    };
    check_golden(
        "falling_box_overlays",
        &render(&gpu, &simulate("falling_box", 30), overlays),
    );
}

/// The screen rectangle (min, max pixel) covering body `index`'s bounding box, widened by a
/// few pixels for antialiased edges.
fn screen_region(snapshot: &Snapshot, index: usize) -> ((f32, f32), (f32, f32)) {
    let camera = OrbitCamera::from_hint(&snapshot.camera);
    let view_proj = camera.view_projection(SIZE.0 as f32 / SIZE.1 as f32);
    let (min, max) = snapshot.bodies[index].aabb;
    let mut lo = (f32::MAX, f32::MAX);
    let mut hi = (f32::MIN, f32::MIN);
    for i in 0..8 {
        let corner = Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        );
        let ndc = view_proj.project_point3(corner);
        let x = (ndc.x + 1.0) / 2.0 * SIZE.0 as f32;
        let y = (1.0 - ndc.y) / 2.0 * SIZE.1 as f32;
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    ((lo.0 - 3.0, lo.1 - 3.0), (hi.0 + 3.0, hi.1 + 3.0))
}

fn area(((x0, y0), (x1, y1)): ((f32, f32), (f32, f32))) -> f32 {
    (x1 - x0) * (y1 - y0)
}

fn inside(region: ((f32, f32), (f32, f32)), (x, y): (u32, u32)) -> bool {
    let (lo, hi) = region;
    (lo.0..=hi.0).contains(&(x as f32)) && (lo.1..=hi.1).contains(&(y as f32))
}

#[test]
fn removing_a_body_changes_exactly_its_region() {
    let gpu = gpu();
    let snapshot = simulate("falling_box", 30);
    let full = render(&gpu, &snapshot, Overlays::default());
    let box_index = 2;
    let region = screen_region(&snapshot, box_index);
    let mut without = snapshot.clone();
    without.bodies.remove(box_index);
    let missing = render(&gpu, &without, Overlays::default());
    let changed = differing_pixels(&full, &missing);
    // A box fills well over a quarter of its bounding box's screen rectangle.
    assert!(
        changed.len() as f32 > area(region) / 4.0,
        "only {} pixels changed in a region of {}",
        changed.len(),
        area(region)
    );
    let outside = changed.iter().filter(|p| !inside(region, **p)).count();
    assert_eq!(
        outside, 0,
        "{outside} changed pixels lie outside the body's screen region"
    );
}

/// Pixels within 40/255 per channel of a gamma-encoded overlay colour.
fn count_near(image: &RgbaImage, color: [f32; 3]) -> usize {
    let target = color.map(|c| (c * 255.0).round() as u8);
    image
        .pixels()
        .filter(|p| (0..3).all(|k| p.0[k].abs_diff(target[k]) <= 40))
        .count()
}

/// Asserts that the overlay `on` turns on draws more than `at_least` pixels of its colour,
/// and that with it off (`off`) fewer than 20 pixels have that colour.
fn assert_overlay_draws(
    snapshot: &Snapshot,
    (on, off): (Overlays, Overlays),
    colour: [f32; 3],
    at_least: usize,
    what: &str,
) {
    let gpu = gpu();
    let with = count_near(&render(&gpu, snapshot, on), colour);
    let without = count_near(&render(&gpu, snapshot, off), colour);
    assert!(
        with > at_least,
        "{what} drew only {with} pixels of its colour"
    );
    assert!(without < 20, "{without} {what}-coloured pixels with it off");
}

/// The joint overlay, on by default, draws the cradle's strings (ten 1 m strings, the balls'
/// anchors between them) in the joint colour; off, none of it.
#[test]
fn joint_overlay_draws_the_cradles_strings_only_when_on() {
    let snapshot = simulate("cradle_strings", 30);
    let on = Overlays::default();
    let off = Overlays {
        joints: false,
        ..Overlays::default()
    };
    assert_overlay_draws(&snapshot, (on, off), JOINT_COLOR, 300, "joint overlay");
}

#[test]
fn aabb_overlay_draws_its_colour_only_when_on() {
    let snapshot = simulate("falling_box", 30);
    let on = Overlays {
        aabbs: true,
        ..Overlays::default()
    };
    let off = Overlays {
        aabbs: false,
        ..Overlays::default()
    };
    assert_overlay_draws(&snapshot, (on, off), AABB_COLOR, 500, "AABB overlay");
}

#[test]
fn broad_phase_overlay_draws_the_awake_boxes_only_when_on() {
    // The box is still falling, so it is awake and has a broad-phase box.
    let snapshot = simulate("falling_box", 30);
    assert!(!snapshot.broad_phase_boxes.is_empty());
    let on = Overlays {
        broad_phase: true,
        ..Overlays::default()
    };
    let overlays = (on, Overlays::default());
    assert_overlay_draws(
        &snapshot,
        overlays,
        BROAD_PHASE_COLOR,
        200,
        "broad-phase overlay",
    );
}

#[test]
fn broad_phase_overlay_draws_the_uniform_grid_cells_in_use() {
    let mut sim = Simulation::new("falling_box").unwrap();
    sim.apply(Command::SetBroadPhase(BroadPhaseKind::UniformGrid {
        cell_size: 1.0,
    }));
    for _ in 0..30 {
        sim.step();
    }
    let snapshot = sim.snapshot(web_time::Instant::now());
    // The falling box (1 m, tumbling) overlaps a few 1 m cells; the platform is oversized.
    let cells = snapshot.broad_phase_cells.len();
    assert!((1..=27).contains(&cells), "{cells} cells");
    let on = Overlays {
        broad_phase: true,
        ..Overlays::default()
    };
    let overlays = (on, Overlays::default());
    assert_overlay_draws(
        &snapshot,
        overlays,
        GRID_CELL_COLOR,
        200,
        "grid-cell overlay",
    );
}

/// Pixels in `region` whose hue is the sleep colour's: blue well above red and green (the
/// sky is bluish but far less saturated, the body palette has no blue).
fn count_sleep_hue(image: &RgbaImage, region: ((f32, f32), (f32, f32))) -> usize {
    const { assert!(SLEEP_COLOR[2] > SLEEP_COLOR[0] + 0.5 && SLEEP_COLOR[2] > SLEEP_COLOR[1] + 0.5) };
    image
        .enumerate_pixels()
        .filter(|(x, y, _)| inside(region, (*x, *y)))
        .filter(|(_, _, p)| {
            let [r, g, b, _] = p.0.map(i32::from);
            b > r + 70 && b > g + 70
        })
        .count()
}

#[test]
fn sleeping_bodies_are_drawn_in_the_sleep_colour_only_when_on() {
    let gpu = gpu();
    let mut snapshot = simulate("falling_box", 30);
    let box_index = 2;
    snapshot.bodies[box_index].sleeping = true;
    let region = screen_region(&snapshot, box_index);
    let on = Overlays {
        sleep_tint: true,
        ..Overlays::default()
    };
    let off = Overlays {
        sleep_tint: false,
        ..Overlays::default()
    };
    let tinted = count_sleep_hue(&render(&gpu, &snapshot, on), region);
    let plain = count_sleep_hue(&render(&gpu, &snapshot, off), region);
    assert!(
        tinted as f32 > area(region) / 4.0,
        "sleeping body shows only {tinted} sleep-coloured pixels"
    );
    assert!(
        plain < 20,
        "{plain} sleep-coloured pixels with the tint off"
    );
}

/// Sizes wgpu cannot draw are refused with exit code 2 before any device is opened, so this
/// needs no adapter.
#[test]
fn the_render_command_refuses_impossible_sizes_with_exit_code_2() {
    let output_path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("render-bad-size.png");
    for (flag, value) in [
        ("--width", "0"),
        ("--width", "100000"),
        ("--height", "4294967295"),
        ("--height", "-1"),
    ] {
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_rigid"))
            .arg("render")
            .arg(&output_path)
            .args([flag, value])
            .output()
            .expect("run rigid render");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{flag} {value}: {stderr}");
        assert!(stderr.contains(flag), "{flag} {value}: {stderr}");
        assert!(stderr.contains("[1, 16384]"), "{flag} {value}: {stderr}");
        assert!(!stderr.contains("panicked"), "{flag} {value}: {stderr}");
        assert!(!output_path.exists());
    }
}

#[test]
fn render_snapshot_refuses_sizes_the_adapter_cannot_draw() {
    let gpu = gpu();
    let snapshot = simulate("falling_box", 0);
    let max = gpu.device.limits().max_texture_dimension_2d;
    for size in [(0, 10), (10, 0), (max + 1, 10), (10, u32::MAX)] {
        let error = headless::render_snapshot(&gpu, &snapshot, Overlays::default(), size)
            .expect_err("an impossible size");
        assert!(
            error.contains(&format!("must lie in [1, {max}]")),
            "{size:?}: {error}"
        );
    }
    let image = headless::render_snapshot(&gpu, &snapshot, Overlays::default(), (1, 1)).unwrap();
    assert_eq!(image.dimensions(), (1, 1));
}

/// One second of falling_box at 10 fps, 160×120.
const RECORD_TAKE: record::Take = record::Take {
    seconds: 1.0,
    fps: 10,
    size: (160, 120),
};

fn decode_gif(path: &std::path::Path) -> Vec<RgbaImage> {
    let file = std::io::BufReader::new(std::fs::File::open(path).expect("the GIF exists"));
    let decoder = GifDecoder::new(file).expect("a GIF");
    let frames = decoder.into_frames().collect_frames().expect("GIF frames");
    frames.into_iter().map(|f| f.into_buffer()).collect()
}

/// Mean absolute difference per channel between two images of one size, of 255.
fn mean_abs_difference(a: &RgbaImage, b: &RgbaImage) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    let total: u64 = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(x, y)| u64::from(x.abs_diff(*y)))
        .sum();
    total as f64 / a.as_raw().len() as f64
}

/// The pixels of the lit colour `color` (gamma-encoded): lighting scales a colour, so a
/// pixel counts when it is `color` scaled by 0.4 to 1.2, within 25/255 per channel.
fn shades_of(image: &RgbaImage, color: [f32; 3]) -> Vec<(u32, u32)> {
    let norm: f32 = color.iter().map(|c| c * c).sum();
    image
        .enumerate_pixels()
        .filter(|(_, _, p)| {
            let pixel = [0, 1, 2].map(|k| f32::from(p.0[k]) / 255.0);
            let scale = (0..3).map(|k| pixel[k] * color[k]).sum::<f32>() / norm;
            (0.4..=1.2).contains(&scale)
                && (0..3).all(|k| (pixel[k] - scale * color[k]).abs() <= 25.0 / 255.0)
        })
        .map(|(x, y, _)| (x, y))
        .collect()
}

fn mean_row(pixels: &[(u32, u32)]) -> f64 {
    pixels.iter().map(|&(_, y)| f64::from(y)).sum::<f64>() / pixels.len() as f64
}

/// One second of falling_box at 10 fps, 160×120: ten frames in which the box falls onto its
/// pedestal.
#[test]
fn a_recording_holds_seconds_times_fps_frames_of_the_moving_scene() {
    let gpu = gpu();
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("falling_box.gif");
    let _ = std::fs::remove_file(&path);
    let mut reported = Vec::new();
    let frames = record::record(
        &gpu,
        "falling_box",
        RECORD_TAKE,
        &path,
        &mut |done, total| reported.push((done, total)),
    )
    .expect("record");
    let images = decode_gif(&path);
    assert_eq!(frames, 10, "1 s × 10 fps");
    assert_eq!(images.len(), 10, "frames in the GIF");
    assert_eq!(reported.last(), Some(&(10, 10)));
    assert!(images.iter().all(|i| i.dimensions() == RECORD_TAKE.size));

    let (first, last) = (&images[0], &images[9]);
    let difference = mean_abs_difference(first, last);
    let falling = simulate("falling_box", 0)
        .bodies
        .iter()
        .position(|b| b.is_dynamic)
        .expect("a dynamic body");
    let colour = PALETTE[falling % PALETTE.len()];
    let (body_first, body_last) = (shades_of(first, colour), shades_of(last, colour));
    eprintln!(
        "first vs last frame: mean difference {difference:.2}/255; body pixels {} then {}, \
         mean row {:.1} then {:.1}",
        body_first.len(),
        body_last.len(),
        mean_row(&body_first),
        mean_row(&body_last)
    );
    assert!(
        difference > 0.5,
        "first and last frames differ by {difference:.2}/255"
    );
    assert!(body_first.len() > 80, "{} body pixels", body_first.len());
    assert!(body_last.len() > 80, "{} body pixels", body_last.len());
    // The box falls about 2 m: tens of rows at this size.
    let fallen = mean_row(&body_last) - mean_row(&body_first);
    assert!(fallen > 20.0, "the box moved {fallen:.1} rows down");
}

/// Lengths, rates and sizes a recording cannot have are errors that name the limit, and
/// leave no file.
#[test]
fn record_refuses_impossible_takes_and_writes_nothing() {
    let gpu = gpu();
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("refused.gif");
    let _ = std::fs::remove_file(&path);
    let max = gpu.device.limits().max_texture_dimension_2d;
    let takes = [
        (
            record::Take {
                seconds: 61.0,
                fps: 30,
                ..RECORD_TAKE
            },
            "at most 1800",
        ),
        (
            record::Take {
                seconds: 1e300,
                ..RECORD_TAKE
            },
            "at most 1800",
        ),
        (
            record::Take {
                fps: 0,
                ..RECORD_TAKE
            },
            "[1, 50]",
        ),
        (
            record::Take {
                fps: 51,
                ..RECORD_TAKE
            },
            "[1, 50]",
        ),
        (
            record::Take {
                seconds: 0.0,
                ..RECORD_TAKE
            },
            "at least one frame",
        ),
        (
            record::Take {
                seconds: -1.0,
                ..RECORD_TAKE
            },
            "at least one frame",
        ),
        (
            record::Take {
                seconds: f64::NAN,
                ..RECORD_TAKE
            },
            "at least one frame",
        ),
        (
            record::Take {
                size: (0, 10),
                ..RECORD_TAKE
            },
            "must lie in [1,",
        ),
        (
            record::Take {
                size: (10, max + 1),
                ..RECORD_TAKE
            },
            "must lie in [1,",
        ),
    ];
    for (take, expected) in takes {
        let error = record::record(&gpu, "falling_box", take, &path, &mut |_, _| {})
            .expect_err("an impossible take");
        assert!(error.contains(expected), "{take:?}: {error}");
        assert!(!path.exists(), "{take:?} wrote a file");
    }
    let error = record::record(&gpu, "no_such_scene", RECORD_TAKE, &path, &mut |_, _| {})
        .expect_err("an unknown scene");
    assert!(error.contains("no_such_scene"), "{error}");
    assert!(!path.exists());
}

/// Frame counts over the limit and bad sizes are refused with exit code 2 before any device
/// is opened, so this needs no adapter.
#[test]
fn the_record_command_refuses_impossible_takes_with_exit_code_2() {
    let output_path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("record-refused.gif");
    let _ = std::fs::remove_file(&output_path);
    let cases: [(&[&str], &str); 5] = [
        (&["--seconds", "61", "--fps", "30"], "at most 1800"),
        (&["--seconds", "-1"], "at least one frame"),
        (&["--fps", "0"], "[1, 50]"),
        (&["--width", "0"], "[1, 16384]"),
        (&["--height", "100000"], "[1, 16384]"),
    ];
    for (args, expected) in cases {
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_rigid"))
            .arg("record")
            .arg(&output_path)
            .args(args)
            .output()
            .expect("run rigid record");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(!output_path.exists());
    }
}
