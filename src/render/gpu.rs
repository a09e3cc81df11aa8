//! Adapter and device setup, for a window surface or for offscreen rendering. Both paths
//! give the same `Gpu`, so the renderer code does not know which one it draws for.

use std::sync::Arc;

use winit::window::Window;

pub struct Gpu {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
}

/// A window's surface with its current configuration. `config` is None while the window has
/// zero size (minimised): a surface may not be configured to 0×0.
pub struct WindowSurface {
    pub surface: wgpu::Surface<'static>,
    pub format: wgpu::TextureFormat,
    pub config: Option<wgpu::SurfaceConfiguration>,
}

impl Gpu {
    /// A device with no surface (tests, headless renders). Software adapters (lavapipe,
    /// llvmpipe) are accepted; `WGPU_BACKEND` picks a backend.
    pub fn offscreen() -> Result<Gpu, String> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|e| no_adapter_message(&e.to_string()))?;
        Self::with_adapter(instance, adapter)
    }

    /// A device that can present to `window`, and the window's surface (not yet configured).
    pub fn for_window(window: Arc<Window>) -> Result<(Gpu, WindowSurface), String> {
        // The GL backend needs the display handle at instance creation to share it with EGL.
        let instance = wgpu::Instance::new(
            wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(window.clone())),
        );
        let surface = instance
            .create_surface(window)
            .map_err(|e| format!("cannot create a surface for the window: {e}"))?;
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: Some(&surface),
            apply_limit_buckets: false,
        }))
        .map_err(|e| no_adapter_message(&e.to_string()))?;
        let format = pick_surface_format(&surface.get_capabilities(&adapter).formats)
            .ok_or("the surface supports no colour format this viewer can draw to")?;
        let gpu = Self::with_adapter(instance, adapter)?;
        Ok((
            gpu,
            WindowSurface {
                surface,
                format,
                config: None,
            },
        ))
    }

    fn with_adapter(instance: wgpu::Instance, adapter: wgpu::Adapter) -> Result<Gpu, String> {
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("rigid"),
            // Software adapters and GL offer little; ask for what they all have.
            required_limits:
                wgpu::Limits::downlevel_webgl2_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(|e| format!("cannot open a device on the graphics adapter: {e}"))?;
        Ok(Gpu {
            instance,
            adapter,
            device,
            queue,
        })
    }

    /// One line naming the adapter, for logs and test failures.
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type)
    }
}

impl WindowSurface {
    /// (Re)configures for a new size; a zero size leaves the surface unconfigured.
    pub fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) {
        if width == 0 || height == 0 {
            self.config = None;
            return;
        }
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format: self.format,
            color_space: wgpu::SurfaceColorSpace::Auto,
            width,
            height,
            desired_maximum_frame_latency: 2,
            present_mode: wgpu::PresentMode::AutoVsync,
            alpha_mode: wgpu::CompositeAlphaMode::Auto,
            view_formats: vec![],
        };
        self.surface.configure(&gpu.device, &config);
        self.config = Some(config);
    }
}

/// egui and our shaders write gamma-encoded colours: prefer a non-sRGB 8-bit format.
fn pick_surface_format(formats: &[wgpu::TextureFormat]) -> Option<wgpu::TextureFormat> {
    let preferred = [
        wgpu::TextureFormat::Bgra8Unorm,
        wgpu::TextureFormat::Rgba8Unorm,
    ];
    preferred
        .into_iter()
        .find(|f| formats.contains(f))
        .or_else(|| formats.first().copied())
}

fn no_adapter_message(detail: &str) -> String {
    format!(
        "no graphics adapter found ({detail}). Without a GPU install a software one: \
         `apt-get install mesa-vulkan-drivers libvulkan1` (lavapipe), or use the GL backend \
         with Mesa llvmpipe (WGPU_BACKEND=gl)"
    )
}
