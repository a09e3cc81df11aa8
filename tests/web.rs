//! The browser build: the viewer compiled to wasm32, served on 127.0.0.1 and driven in
//! Debian's headless Chromium by `tests/web/smoke.mjs` (first frames drawn, a panel button
//! clicked, pachinko, a clear message without WebGL2). Needs what `cargo xtask setup`
//! installs: without it the test fails under CI and is skipped, loudly, elsewhere.

#![cfg(feature = "viewer")]

mod common;

use std::io::{BufRead, BufReader, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::Command;

use common::tools::{missing, tools_present};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// What is missing to run the browser test, if anything.
fn missing_tools() -> Vec<&'static str> {
    let mut missing = missing(&["wasm-bindgen", "node", "/usr/bin/chromium"]);
    if !Path::new(ROOT)
        .join("tests/web/node_modules/playwright-core")
        .is_dir()
    {
        missing.push("tests/web/node_modules (npm ci)");
    }
    missing
}

/// Serves the files of `root` (one folder, no subfolders) over HTTP on a free loopback port.
fn serve(root: PathBuf) -> SocketAddr {
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind a loopback port");
    let address = listener.local_addr().unwrap();
    std::thread::spawn(move || {
        for stream in listener.incoming().flatten() {
            let root = root.clone();
            std::thread::spawn(move || respond(stream, &root));
        }
    });
    address
}

fn respond(mut stream: TcpStream, root: &Path) {
    let mut reader = BufReader::new(&stream);
    let mut request = String::new();
    if reader.read_line(&mut request).is_err() {
        return;
    }
    // The headers say nothing this server uses.
    let mut header = String::new();
    while reader.read_line(&mut header).is_ok_and(|n| n > 2) {
        header.clear();
    }
    let target = request.split_whitespace().nth(1).unwrap_or("/");
    let path = target
        .split('?')
        .next()
        .unwrap_or("/")
        .trim_start_matches('/');
    let name = if path.is_empty() { "index.html" } else { path };
    let body = (!name.contains('/') && !name.contains(".."))
        .then(|| std::fs::read(root.join(name)).ok())
        .flatten();
    let response = match &body {
        Some(body) => format!(
            "HTTP/1.1 200 OK\r\nContent-Type: {}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
            content_type(name),
            body.len()
        ),
        None => "HTTP/1.1 404 Not Found\r\nContent-Length: 0\r\nConnection: close\r\n\r\n".into(),
    };
    let _ = stream.write_all(response.as_bytes());
    if let Some(body) = body {
        let _ = stream.write_all(&body);
    }
}

/// `application/wasm` lets the browser compile the module while it downloads.
fn content_type(name: &str) -> &'static str {
    match name.rsplit('.').next() {
        Some("html") => "text/html; charset=utf-8",
        Some("js") => "text/javascript",
        Some("wasm") => "application/wasm",
        _ => "application/octet-stream",
    }
}

#[test]
fn the_viewer_runs_in_headless_chromium() {
    if !tools_present("the browser test", &missing_tools()) {
        return;
    }
    let site = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("web-site");
    let built = Command::new("bash")
        .arg(Path::new(ROOT).join("web/build.sh"))
        .arg(&site)
        .status()
        .expect("run web/build.sh");
    assert!(built.success(), "web/build.sh failed ({built})");

    let address = serve(site);
    let shots = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("web-screenshots");
    let output = Command::new("timeout")
        .arg("600")
        .arg("node")
        .arg(Path::new(ROOT).join("tests/web/smoke.mjs"))
        .arg(format!("http://{address}/"))
        .arg(&shots)
        .output()
        .expect("run node");
    let log = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    println!("{log}");
    assert!(
        output.status.success(),
        "browser checks failed ({}), screenshots in {}:\n{log}",
        output.status,
        shots.display()
    );
}
