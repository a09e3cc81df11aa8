//! External programs the window and browser tests drive.

use std::process::Command;

/// Whether `tool` (a name on PATH or a path) can be run here.
pub fn have(tool: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {tool}")])
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Whether a test that needs `missing` (empty when everything is there) may run. Under CI
/// (`CI` set) a missing tool fails the test; elsewhere the test is skipped with a loud line
/// that names the command installing it. A test never passes silently without its tools.
pub fn tools_present(test: &str, missing: &[&str]) -> bool {
    if missing.is_empty() {
        return true;
    }
    let message = format!(
        "{test} needs {}: `cargo xtask setup` installs them",
        missing.join(", ")
    );
    assert!(std::env::var_os("CI").is_none(), "{message}");
    eprintln!("\n*** SKIPPED: {message} ***\n");
    false
}

/// The tools of `wanted` that are not here.
pub fn missing<'a>(wanted: &[&'a str]) -> Vec<&'a str> {
    wanted.iter().copied().filter(|t| !have(t)).collect()
}
