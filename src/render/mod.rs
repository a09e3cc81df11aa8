//! GPU rendering with wgpu: device setup (window or offscreen), meshes per shape, the lit
//! body pipeline and line overlays, the orbit camera.
//!
//! Reading order: `gpu` → `mesh` / `lines` (CPU geometry) → `pipelines` → `renderer`
//! (one frame) → `offscreen` / `headless` (images without a window) → `record`
//! (animations without a window) → `camera`.

pub mod camera;
pub mod gpu;
pub mod headless;
pub mod lines;
pub mod mesh;
pub mod offscreen;
pub mod pipelines;
#[cfg(not(target_arch = "wasm32"))]
pub mod record;
pub mod renderer;

pub use camera::{OrbitCamera, Ray};
pub use gpu::{Gpu, WindowSurface};
pub use renderer::{FrameInput, Overlays, SceneRenderer, Viewport};
