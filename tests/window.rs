//! The viewer in a real window under a virtual X server (Xvfb). Needs `xvfb-run` and
//! `xdotool` (`cargo xtask setup` installs them): without them the tests fail under CI and
//! are skipped, loudly, elsewhere.

#![cfg(feature = "viewer")]

mod common;

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::process::Command;

use common::tools::{missing, tools_present};

const XVFB_SCREEN: &str = "-screen 0 1280x720x24";

fn screenshot_path(name: &str) -> PathBuf {
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_file(&path);
    path
}

/// Runs a shell script under xvfb-run (bounded by `timeout`); $RIGID is the viewer binary.
fn run_in_xvfb(script: &str) -> std::process::Output {
    Command::new("timeout")
        .args([
            "120",
            "xvfb-run",
            "-a",
            "-s",
            XVFB_SCREEN,
            "sh",
            "-c",
            script,
        ])
        .env("RIGID", env!("CARGO_BIN_EXE_rigid"))
        .output()
        .expect("run xvfb-run")
}

/// Asserts the run succeeded and its screenshot shows a real frame, not a blank one.
fn assert_rich_screenshot(output: &std::process::Output, path: &Path) -> image::RgbaImage {
    let log = format!(
        "stdout:\n{}\nstderr:\n{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        output.status.success(),
        "viewer failed ({}):\n{log}",
        output.status
    );
    let image = image::open(path)
        .unwrap_or_else(|e| panic!("no screenshot at {}: {e}\n{log}", path.display()))
        .to_rgba8();
    let colours: HashSet<[u8; 4]> = image.pixels().map(|p| p.0).collect();
    assert!(
        colours.len() > 500,
        "only {} distinct colours: blank frame?",
        colours.len()
    );
    image
}

#[test]
fn viewer_opens_runs_and_saves_a_screenshot() {
    if !tools_present("the window test", &missing(&["xvfb-run"])) {
        return;
    }
    let shot = screenshot_path("window.png");
    let script = format!(
        "\"$RIGID\" --exit-after 3 --screenshot '{}'",
        shot.display()
    );
    let image = assert_rich_screenshot(&run_in_xvfb(&script), &shot);
    assert_eq!(image.dimensions(), (1280, 720));
}

#[test]
fn viewer_survives_resizing_and_unmapping() {
    if !tools_present("the window test", &missing(&["xvfb-run", "xdotool"])) {
        return;
    }
    let shot = screenshot_path("window_resized.png");
    // Without a window manager, unmapping stands in for minimising; a 1×1 window is the
    // smallest X allows.
    let script = format!(
        "\"$RIGID\" --scene pachinko --exit-after 5 --screenshot '{}' & pid=$!
         sleep 2
         w=$(xdotool search --sync --name '^rigid$' | head -n 1)
         xdotool windowsize $w 700 450; sleep 0.4
         xdotool windowsize $w 1 1; sleep 0.4
         xdotool windowunmap $w; sleep 0.4
         xdotool windowmap $w; sleep 0.2
         xdotool windowsize $w 900 600
         wait $pid",
        shot.display()
    );
    let image = assert_rich_screenshot(&run_in_xvfb(&script), &shot);
    assert_eq!(image.dimensions(), (900, 600));
}

/// Where egui lays out the panel's buttons in a 1280×720 window: "Pause" in the scene row,
/// "box" in the spawn row (23 pixels lower than in tests/web/smoke.mjs: the desktop panel
/// has a row of save and load buttons more).
const PAUSE_BUTTON: (u32, u32) = (33, 59);
const SPAWN_BOX_BUTTON: (u32, u32) = (90, 302);

/// Fewest pixels of the spawn highlight a new box must add to the frame. The 0.6 m box
/// covers thousands of pixels in most scenes and about 250 on top of the pyramid, 30 m from
/// the camera; a box out of view adds none.
const MIN_SPAWNED_PIXELS: usize = 100;

/// A pixel of the highlight given to new bodies (`SPAWN_COLOR`, magenta) on a lit or shaded
/// face: red and blue strong, green weak. No palette colour, the sleep colour, the sky or
/// the panel comes near it.
fn is_spawn_highlight(pixel: &image::Rgba<u8>) -> bool {
    let [r, g, b, _] = pixel.0.map(u32::from);
    r >= 60 && 2 * b >= r && 3 * g < r
}

fn count_highlight(path: &Path) -> usize {
    highlight_pixels(path).len()
}

/// Where the highlight's pixels are, (x, y) from the top-left.
fn highlight_pixels(path: &Path) -> Vec<(u32, u32)> {
    let image = image::open(path)
        .unwrap_or_else(|e| panic!("no screenshot at {}: {e}", path.display()))
        .to_rgba8();
    image
        .enumerate_pixels()
        .filter(|(_, _, p)| is_spawn_highlight(p))
        .map(|(x, y, _)| (x, y))
        .collect()
}

/// The viewer on `scene`, paused by a click on "Pause" after its first frames, then (with
/// `spawn`) a click on the "box" spawn button; it saves its last frame to `shot`.
fn pause_and_maybe_spawn(scene: &str, spawn: bool, shot: &Path) -> std::process::Output {
    let click = |(x, y): (u32, u32)| format!("xdotool mousemove --window $w {x} {y} click 1");
    let spawn_click = if spawn {
        click(SPAWN_BOX_BUTTON)
    } else {
        String::new()
    };
    let script = format!(
        "\"$RIGID\" --scene {scene} --exit-after 6 --screenshot '{}' & pid=$!
         w=$(xdotool search --sync --name '^rigid$' | head -n 1)
         sleep 2
         {}
         sleep 0.5
         {spawn_click}
         wait $pid",
        shot.display(),
        click(PAUSE_BUTTON),
    );
    run_in_xvfb(&script)
}

#[test]
fn a_spawn_button_puts_the_body_in_view_in_every_scene() {
    if !tools_present("the window test", &missing(&["xvfb-run", "xdotool"])) {
        return;
    }
    let mut failures = Vec::new();
    for scene in rigid::sim::scene_names() {
        let before = screenshot_path(&format!("spawn_{scene}_before.png"));
        let after = screenshot_path(&format!("spawn_{scene}_after.png"));
        assert_rich_screenshot(&pause_and_maybe_spawn(scene, false, &before), &before);
        assert_rich_screenshot(&pause_and_maybe_spawn(scene, true, &after), &after);
        let (without, with) = (count_highlight(&before), count_highlight(&after));
        println!("{scene}: {without} highlight pixels before the spawn, {with} after");
        if with < without + MIN_SPAWNED_PIXELS {
            failures.push(format!(
                "{scene}: the spawned box adds {} highlight pixels (< {MIN_SPAWNED_PIXELS}); see {}",
                with.saturating_sub(without),
                after.display()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn a_key_spawns_at_the_cursor() {
    if !tools_present("the window test", &missing(&["xvfb-run", "xdotool"])) {
        return;
    }
    // falling_box: this pixel lies on the platform's top face, left of the cube.
    let cursor = (620, 505);
    let shot = screenshot_path("spawn_at_cursor.png");
    // Without a window manager the window gets the keyboard only once focused; the second
    // move makes sure the viewer saw the cursor inside its view.
    let script = format!(
        "\"$RIGID\" --scene falling_box --exit-after 6 --screenshot '{}' & pid=$!
         w=$(xdotool search --sync --name '^rigid$' | head -n 1)
         sleep 2
         xdotool mousemove --window $w {} {} click 1
         xdotool windowfocus --sync $w
         xdotool mousemove --window $w {} {}; sleep 0.3
         xdotool mousemove --window $w {} {}; sleep 0.3
         xdotool key 2
         wait $pid",
        shot.display(),
        PAUSE_BUTTON.0,
        PAUSE_BUTTON.1,
        cursor.0 - 1,
        cursor.1 - 1,
        cursor.0,
        cursor.1,
    );
    assert_rich_screenshot(&run_in_xvfb(&script), &shot);
    let pixels = highlight_pixels(&shot);
    let count = pixels.len() as u32;
    println!("spawn at the cursor: {count} highlight pixels");
    assert!(
        count as usize >= MIN_SPAWNED_PIXELS,
        "{count} highlight pixels"
    );
    // The box rests on the face under the cursor: its picture lies just above the cursor.
    let sum = pixels
        .iter()
        .fold((0, 0), |(sx, sy), &(x, y)| (sx + x, sy + y));
    let centre = (sum.0 / count, sum.1 / count);
    let off = (centre.0.abs_diff(cursor.0), centre.1.abs_diff(cursor.1));
    assert!(
        off.0 < 40 && centre.1 < cursor.1 && off.1 < 100,
        "the box is drawn around {centre:?}, the cursor was at {cursor:?}"
    );
}

/// The panel's Screenshot button, right of Reset.
const SCREENSHOT_BUTTON: (u32, u32) = (210, 59);

#[test]
fn the_screenshot_button_saves_the_window_in_the_working_directory() {
    if !tools_present("the window test", &missing(&["xvfb-run", "xdotool"])) {
        return;
    }
    let folder = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("screenshot-button");
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).expect("a scratch folder");
    let script = format!(
        "cd '{}' && \"$RIGID\" --exit-after 4 & pid=$!
         w=$(xdotool search --sync --name '^rigid$' | head -n 1)
         sleep 2
         xdotool mousemove --window $w {} {} click 1
         wait $pid",
        folder.display(),
        SCREENSHOT_BUTTON.0,
        SCREENSHOT_BUTTON.1,
    );
    let output = run_in_xvfb(&script);
    let saved: Vec<PathBuf> = std::fs::read_dir(&folder)
        .expect("the scratch folder")
        .map(|entry| entry.expect("an entry").path())
        .collect();
    assert_eq!(saved.len(), 1, "{saved:?}");
    let name = saved[0].file_name().unwrap().to_string_lossy().into_owned();
    assert!(
        name.starts_with("rigid-screenshot-") && name.ends_with(".png"),
        "{name}"
    );
    let image = assert_rich_screenshot(&output, &saved[0]);
    assert_eq!(image.dimensions(), (1280, 720));
}
