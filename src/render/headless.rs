//! Rendering without a window: step a scene, draw the newest snapshot offscreen, return the
//! image. Used by `rigid render` and by the render tests.

use web_time::Instant;

use image::RgbaImage;

use crate::render::camera::OrbitCamera;
use crate::render::gpu::Gpu;
use crate::render::offscreen::OffscreenTarget;
use crate::render::renderer::{FrameInput, Overlays, SceneRenderer, Viewport};
use crate::sim::{Simulation, Snapshot};

/// The format of offscreen images (gamma-encoded, as on screen).
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// Builds `scene`, takes `steps` fixed steps, and returns the snapshot.
pub fn simulate(scene: &str, steps: u32) -> Result<Snapshot, String> {
    let mut sim = Simulation::new(scene)?;
    for _ in 0..steps {
        sim.step();
    }
    let mut snapshot = sim.snapshot(Instant::now());
    // A still image shows the newest state, not a blend with the step before.
    for body in &mut snapshot.bodies {
        body.previous = body.pose;
    }
    Ok(snapshot)
}

/// Draws `snapshot` from its scene's camera into an image of `size` pixels.
pub fn render_snapshot(
    gpu: &Gpu,
    snapshot: &Snapshot,
    overlays: Overlays,
    size: (u32, u32),
) -> Result<RgbaImage, String> {
    let camera = OrbitCamera::from_hint(&snapshot.camera);
    let poses: Vec<_> = snapshot.bodies.iter().map(|b| b.pose).collect();
    let frame = FrameInput {
        snapshot,
        poses: &poses,
        camera: &camera,
        overlays,
        selected: None,
        extra_lines: &[],
        viewport: Viewport::full(size),
    };
    let target = OffscreenTarget::new(gpu, size, FORMAT);
    let mut renderer = SceneRenderer::new(gpu, FORMAT);
    renderer.prepare(gpu, &frame, size);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    renderer.encode(&mut encoder, &target.view);
    gpu.queue.submit([encoder.finish()]);
    target.read(gpu)
}
