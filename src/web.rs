//! The page around the viewer in the browser: the canvas it draws on, what the address asks
//! for (`?scene=pachinko`, `?backend=webgl`), messages shown in place of the canvas when
//! something fails, and the counters the page exposes (for its own tests) as attributes of
//! `<body>`. The page itself is `web/index.html`.

use wasm_bindgen::JsCast;
use web_sys::{Document, HtmlCanvasElement};

use crate::sim::{DEFAULT_SCENE, Snapshot};

/// The id of the canvas in `web/index.html`.
const CANVAS_ID: &str = "rigid-canvas";
/// The id of the element that shows failures.
const MESSAGE_ID: &str = "rigid-message";

fn document() -> Option<Document> {
    web_sys::window()?.document()
}

/// The value of `name` in the page address's query, if present.
fn query(name: &str) -> Option<String> {
    let search = web_sys::window()?.location().search().ok()?;
    web_sys::UrlSearchParams::new_with_str(&search)
        .ok()?
        .get(name)
}

/// The scene the address names, or the default one.
pub fn requested_scene() -> String {
    query("scene").unwrap_or_else(|| DEFAULT_SCENE.to_string())
}

/// `?backend=webgpu` or `?backend=webgl` restricts the graphics backend; by default WebGPU
/// is used where it works and WebGL2 otherwise.
pub fn requested_backends() -> wgpu::Backends {
    match query("backend").as_deref() {
        Some("webgpu") => wgpu::Backends::BROWSER_WEBGPU,
        Some("webgl") => wgpu::Backends::GL,
        _ => wgpu::Backends::BROWSER_WEBGPU | wgpu::Backends::GL,
    }
}

/// The page's canvas the viewer draws on, if the page has one.
pub fn canvas() -> Option<HtmlCanvasElement> {
    document()?
        .get_element_by_id(CANVAS_ID)?
        .dyn_into::<HtmlCanvasElement>()
        .ok()
}

/// Shows `text` over the page, hides the canvas and marks the page failed. The first
/// failure is kept: what follows it (a panic on a lost device) is a consequence.
pub fn show_failure(text: &str) {
    let Some(document) = document() else {
        return;
    };
    if has_failed(&document) {
        return;
    }
    if let Some(message) = document.get_element_by_id(MESSAGE_ID) {
        message.set_text_content(Some(text));
        let _ = message.set_attribute("style", "display:block");
    }
    if let Some(canvas) = document.get_element_by_id(CANVAS_ID) {
        let _ = canvas.set_attribute("style", "display:none");
    }
    set_status("state", "failed");
}

fn has_failed(document: &Document) -> bool {
    document
        .body()
        .and_then(|body| body.get_attribute("data-rigid-state"))
        .is_some_and(|state| state == "failed")
}

/// Names the graphics adapter the viewer draws with, once it has one.
pub fn publish_adapter(adapter: &str) {
    set_status("adapter", adapter);
}

/// Publishes what the viewer is doing, once a frame.
pub fn publish_status(snapshot: &Snapshot) {
    if document().is_none_or(|d| has_failed(&d)) {
        return;
    }
    set_status("state", "running");
    set_status("scene", &snapshot.scene);
    set_status("bodies", &snapshot.bodies.len().to_string());
    set_status("steps", &snapshot.counters.steps.to_string());
    set_status("paused", &snapshot.settings.paused.to_string());
}

fn set_status(name: &str, value: &str) {
    if let Some(body) = document().and_then(|d| d.body()) {
        let _ = body.set_attribute(&format!("data-rigid-{name}"), value);
    }
}
