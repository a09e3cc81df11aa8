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
    Ok(still_snapshot(&sim))
}

/// The simulation's state to draw as a still image: the newest state, not a blend with the
/// step before.
pub fn still_snapshot(sim: &Simulation) -> Snapshot {
    let mut snapshot = sim.snapshot(Instant::now());
    for body in &mut snapshot.bodies {
        body.previous = body.pose;
    }
    snapshot
}

/// The largest width or height `rigid render` takes before it opens a device: the largest
/// 2D texture that desktop adapters commonly offer. An adapter offering less refuses more
/// (see `check_size`).
pub const MAX_IMAGE_SIZE: u32 = 16384;

/// Whether `gpu` can draw an image of `size` pixels: each side at least 1 and at most its
/// largest 2D texture; wgpu would panic on either.
pub fn check_size(gpu: &Gpu, (width, height): (u32, u32)) -> Result<(), String> {
    let max = gpu.device.limits().max_texture_dimension_2d;
    for (side, value) in [("width", width), ("height", height)] {
        if !(1..=max).contains(&value) {
            return Err(format!(
                "image {side} must lie in [1, {max}] pixels on this graphics adapter, got {value}"
            ));
        }
    }
    Ok(())
}

/// Draws `snapshot` from its scene's camera into an image of `size` pixels; a size the
/// adapter cannot draw is an error (see `check_size`).
pub fn render_snapshot(
    gpu: &Gpu,
    snapshot: &Snapshot,
    overlays: Overlays,
    size: (u32, u32),
) -> Result<RgbaImage, String> {
    OffscreenPainter::new(gpu, size)?.paint(gpu, snapshot, overlays)
}

/// A renderer and its target kept from one image to the next, so that a run of frames (a
/// recording) builds its pipelines and texture once.
pub struct OffscreenPainter {
    renderer: SceneRenderer,
    target: OffscreenTarget,
}

impl OffscreenPainter {
    /// A painter of images of `size` pixels; a size the adapter cannot draw is an error.
    pub fn new(gpu: &Gpu, size: (u32, u32)) -> Result<Self, String> {
        check_size(gpu, size)?;
        Ok(OffscreenPainter {
            renderer: SceneRenderer::new(gpu, FORMAT),
            target: OffscreenTarget::new(gpu, size, FORMAT),
        })
    }

    /// Draws `snapshot` from its scene's camera and reads the image back.
    pub fn paint(
        &mut self,
        gpu: &Gpu,
        snapshot: &Snapshot,
        overlays: Overlays,
    ) -> Result<RgbaImage, String> {
        let size = self.target.size;
        let poses: Vec<_> = snapshot.bodies.iter().map(|b| b.pose).collect();
        let mut camera = OrbitCamera::from_hint(&snapshot.camera);
        camera.target += snapshot.camera.follow_shift(&poses);
        let frame = FrameInput {
            snapshot,
            poses: &poses,
            camera: &camera,
            overlays,
            selected: None,
            extra_lines: &[],
            viewport: Viewport::full(size),
        };
        self.renderer.prepare(gpu, &frame, size);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        self.renderer.encode(&mut encoder, &self.target.view);
        gpu.queue.submit([encoder.finish()]);
        self.target.read(gpu)
    }
}
