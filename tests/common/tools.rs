//! External programs the window and browser tests drive.

use std::process::Command;

/// Whether `tool` (a name on PATH or a path) can be run here.
pub fn have(tool: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {tool}")])
        .output()
        .is_ok_and(|o| o.status.success())
}
