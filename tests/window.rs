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
