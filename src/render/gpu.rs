//! Adapter and device setup, for a window surface or for offscreen rendering. Both paths
//! give the same `Gpu`, so the renderer code does not know which one it draws for.

use std::sync::Arc;

use winit::window::Window;

/// The wgpu handles every renderer needs. The device asks only for WebGL2-level limits,
/// so the same code runs on software adapters and in the browser.
pub struct Gpu {
    /// The instance the adapter came from; also creates a window's surface again when it is
    /// lost.
    pub instance: wgpu::Instance,
    /// The graphics adapter in use.
    pub adapter: wgpu::Adapter,
    /// The logical device: creates buffers, textures and pipelines.
    pub device: wgpu::Device,
    /// Where command buffers are submitted and buffers written.
    pub queue: wgpu::Queue,
}

/// A window's surface with its current configuration. `config` is None while the window has
/// zero size (minimised): a surface may not be configured to 0×0.
pub struct WindowSurface {
    /// The surface presented to the window.
    pub surface: wgpu::Surface<'static>,
    /// Its colour format: `Bgra8Unorm` or `Rgba8Unorm` where offered, since the shaders
    /// write gamma-encoded colours, else the first format the surface supports.
    pub format: wgpu::TextureFormat,
    /// The configuration in force, or None while the surface is unconfigured.
    pub config: Option<wgpu::SurfaceConfiguration>,
}

impl Gpu {
    /// A device with no surface (tests, headless renders). Software adapters (lavapipe,
    /// llvmpipe) are accepted; `WGPU_BACKEND` picks a backend. The error says why no
    /// adapter or device could be had, and how to install a software adapter.
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
        pollster::block_on(Self::with_adapter(instance, adapter))
    }

    /// A device that can present to `window`, and the window's surface (not yet configured).
    /// Asynchronous because the browser answers adapter and device requests later; native
    /// callers block on it. The error says what is missing: an adapter, a surface, a
    /// supported colour format or a device.
    pub async fn for_window(window: Arc<Window>) -> Result<(Gpu, WindowSurface), String> {
        let instance = window_instance(&window).await;
        let surface = instance
            .create_surface(window)
            .map_err(|e| no_surface_message(&e.to_string()))?;
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: Some(&surface),
                apply_limit_buckets: false,
            })
            .await
            .map_err(|e| no_adapter_message(&e.to_string()))?;
        let format = pick_surface_format(&surface.get_capabilities(&adapter).formats)
            .ok_or("the surface supports no colour format this viewer can draw to")?;
        let gpu = Self::with_adapter(instance, adapter).await?;
        Ok((
            gpu,
            WindowSurface {
                surface,
                format,
                config: None,
            },
        ))
    }

    async fn with_adapter(instance: wgpu::Instance, adapter: wgpu::Adapter) -> Result<Gpu, String> {
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("rigid"),
                // Software adapters, GL and WebGL2 offer little; ask for what they all have.
                required_limits: wgpu::Limits::downlevel_webgl2_defaults()
                    .using_resolution(adapter.limits()),
                ..Default::default()
            })
            .await
            .map_err(|e| format!("cannot open a device on the graphics adapter: {e}"))?;
        // A browser can take the device away (its GPU process restarted); say so on the page
        // rather than fail later on a dead device.
        #[cfg(target_arch = "wasm32")]
        device.set_device_lost_callback(|reason, message| {
            crate::web::show_failure(&format!(
                "The graphics device was lost ({reason:?}): {message}. Reload the page."
            ))
        });
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
    /// (Re)configures for a new size in pixels, with vsync; a zero size leaves the surface
    /// unconfigured.
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

/// The instance for a window. The GL backend needs the display handle at instance creation
/// to share it with EGL; `WGPU_BACKEND` picks a backend.
#[cfg(not(target_arch = "wasm32"))]
async fn window_instance(window: &Arc<Window>) -> wgpu::Instance {
    wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
        Box::new(window.clone()),
    ))
}

/// In the browser: WebGPU where the browser really offers an adapter, WebGL2 otherwise (or
/// when the page asks for one backend, see `web::requested_backends`).
#[cfg(target_arch = "wasm32")]
async fn window_instance(_window: &Arc<Window>) -> wgpu::Instance {
    let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
    descriptor.backends = crate::web::requested_backends();
    wgpu::util::new_instance_with_webgpu_detection(descriptor).await
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

#[cfg(not(target_arch = "wasm32"))]
fn no_adapter_message(detail: &str) -> String {
    format!(
        "no graphics adapter found ({detail}). Without a GPU install a software one: \
         `apt-get install mesa-vulkan-drivers libvulkan1` (lavapipe), or use the GL backend \
         with Mesa llvmpipe (WGPU_BACKEND=gl)"
    )
}

#[cfg(not(target_arch = "wasm32"))]
fn no_surface_message(detail: &str) -> String {
    format!("cannot create a surface for the window: {detail}")
}

/// In the browser a canvas without a surface means it has no WebGL2 (and no WebGPU).
#[cfg(target_arch = "wasm32")]
fn no_surface_message(detail: &str) -> String {
    no_adapter_message(detail)
}

#[cfg(target_arch = "wasm32")]
fn no_adapter_message(detail: &str) -> String {
    format!(
        "this browser offers neither WebGPU nor WebGL2 ({detail}). Try a current Chrome, \
         Edge, Firefox or Safari, with hardware acceleration switched on"
    )
}
