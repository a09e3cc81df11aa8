//! The window's GPU side: surface, scene renderer and egui renderer. It draws a frame to the
//! surface and, when asked, the same frame to an offscreen texture for a screenshot.
//!
//! Surface states are handled without crashing: a zero-size (minimised) window is not
//! configured and draws nothing, an outdated surface is reconfigured, a lost one recreated.

use std::sync::Arc;

use image::RgbaImage;
use winit::window::Window;

use crate::render::gpu::{Gpu, WindowSurface};
use crate::render::offscreen::OffscreenTarget;
use crate::render::{FrameInput, SceneRenderer};

/// What egui produced for one frame, ready to draw.
pub struct UiFrame {
    /// The tessellated panel, in egui points.
    pub paint_jobs: Vec<egui::ClippedPrimitive>,
    /// Texture uploads and frees to apply with this frame.
    pub textures: egui::TexturesDelta,
    /// Physical pixels per egui point (the window's scale factor).
    pub pixels_per_point: f32,
}

/// A window with everything needed to draw the scene and the panel into it.
pub struct Display {
    /// The window drawn into.
    pub window: Arc<Window>,
    gpu: Gpu,
    surface: WindowSurface,
    scene: SceneRenderer,
    egui: egui_wgpu::Renderer,
}

impl Display {
    /// Opens a device for `window` and configures its surface to the window's size. The
    /// error says what is missing (adapter, surface, colour format or device).
    pub async fn new(window: Arc<Window>) -> Result<Display, String> {
        let (gpu, mut surface) = Gpu::for_window(window.clone()).await?;
        let size = window.inner_size();
        surface.resize(&gpu, size.width, size.height);
        let scene = SceneRenderer::new(&gpu, surface.format);
        let egui = egui_wgpu::Renderer::new(
            &gpu.device,
            surface.format,
            egui_wgpu::RendererOptions::default(),
        );
        Ok(Display {
            window,
            gpu,
            surface,
            scene,
            egui,
        })
    }

    /// One line naming the graphics adapter.
    pub fn describe(&self) -> String {
        self.gpu.describe()
    }

    /// The largest 2D texture side the device allows, in pixels (egui sizes its font atlas
    /// to it).
    pub fn max_texture_side(&self) -> usize {
        self.gpu.device.limits().max_texture_dimension_2d as usize
    }

    /// Reconfigures the surface to the window's current size, after a resize or a scale
    /// change; a zero size leaves it unconfigured.
    pub fn resize(&mut self) {
        let size = self.window.inner_size();
        self.surface.resize(&self.gpu, size.width, size.height);
    }

    /// Window size in pixels.
    pub fn size(&self) -> (u32, u32) {
        let size = self.window.inner_size();
        (size.width, size.height)
    }

    /// Draws and presents one frame; with `capture`, also returns it as an image of the
    /// window's size. The error comes from reading the captured image back.
    pub fn draw(
        &mut self,
        frame: &FrameInput,
        mut ui: UiFrame,
        capture: bool,
    ) -> Result<Option<RgbaImage>, String> {
        for (id, deltas) in ui.textures.set.drain() {
            for delta in &deltas {
                self.egui
                    .update_texture(&self.gpu.device, &self.gpu.queue, id, delta);
            }
        }
        self.present(frame, &ui);
        let size = self.size();
        let image = if capture && size.0 > 0 && size.1 > 0 {
            let target = OffscreenTarget::new(&self.gpu, size, self.surface.format);
            self.encode(&target.view, frame, &ui, size);
            Some(target.read(&self.gpu))
        } else {
            None
        };
        // Every delta is applied (set above, freed here): egui checks it in debug builds.
        for id in ui.textures.free.drain() {
            self.egui.free_texture(&id);
        }
        image.transpose()
    }

    fn present(&mut self, frame: &FrameInput, ui: &UiFrame) {
        let Some(config) = &self.surface.config else {
            return;
        };
        let size = (config.width, config.height);
        match self.surface.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(texture) => {
                let view = texture.texture.create_view(&Default::default());
                self.encode(&view, frame, ui, size);
                self.gpu.queue.present(texture);
            }
            wgpu::CurrentSurfaceTexture::Suboptimal(texture) => {
                let view = texture.texture.create_view(&Default::default());
                self.encode(&view, frame, ui, size);
                self.gpu.queue.present(texture);
                self.resize();
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {}
            wgpu::CurrentSurfaceTexture::Outdated => self.resize(),
            wgpu::CurrentSurfaceTexture::Lost => self.recreate_surface(),
            wgpu::CurrentSurfaceTexture::Validation => {
                eprintln!("rigid: surface validation error; skipping a frame")
            }
        }
    }

    fn recreate_surface(&mut self) {
        match self.gpu.instance.create_surface(self.window.clone()) {
            Ok(surface) => {
                self.surface.surface = surface;
                self.resize();
            }
            Err(e) => eprintln!("rigid: cannot recreate the lost surface: {e}"),
        }
    }

    /// Scene then panel into `view`, a target of `size` pixels in the surface format.
    fn encode(
        &mut self,
        view: &wgpu::TextureView,
        frame: &FrameInput,
        ui: &UiFrame,
        size: (u32, u32),
    ) {
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        self.scene.prepare(&self.gpu, frame, size);
        let mut encoder = device.create_command_encoder(&Default::default());
        self.scene.encode(&mut encoder, view);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [size.0, size.1],
            pixels_per_point: ui.pixels_per_point,
        };
        let callbacks =
            self.egui
                .update_buffers(device, queue, &mut encoder, &ui.paint_jobs, &screen);
        {
            let mut pass = encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("egui"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Load,
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                })
                .forget_lifetime();
            self.egui.render(&mut pass, &ui.paint_jobs, &screen);
        }
        queue.submit(callbacks.into_iter().chain([encoder.finish()]));
    }
}
