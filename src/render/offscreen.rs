//! A texture to render into without a window, and its read-back to an RGBA image.

use std::path::Path;

use image::{ImageFormat, RgbaImage};

use crate::output_file::write_atomically_with;
use crate::render::gpu::Gpu;

/// A 2D colour texture to draw into and read back.
pub struct OffscreenTarget {
    /// The texture; a render attachment and a copy source.
    pub texture: wgpu::Texture,
    /// The view to pass as the render target.
    pub view: wgpu::TextureView,
    /// Width and height in pixels.
    pub size: (u32, u32),
}

impl OffscreenTarget {
    /// A target of `size` pixels (width, height; both above zero). `format` must be an
    /// 8-bit RGBA or BGRA format (the window's, for screenshots).
    pub fn new(gpu: &Gpu, size: (u32, u32), format: wgpu::TextureFormat) -> Self {
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("offscreen"),
            size: extent(size),
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        OffscreenTarget {
            texture,
            view,
            size,
        }
    }

    /// Copies the texture back to the CPU as an RGBA image, whatever the channel order of
    /// the format. Blocks until the GPU has finished; the error says which step failed.
    pub fn read(&self, gpu: &Gpu) -> Result<RgbaImage, String> {
        let (width, height) = self.size;
        // Rows of a texture-to-buffer copy must be multiples of 256 bytes.
        let padded_row = (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("read-back"),
            size: padded_row as u64 * height as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            self.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row),
                    rows_per_image: Some(height),
                },
            },
            extent(self.size),
        );
        gpu.queue.submit([encoder.finish()]);
        let slice = buffer.slice(..);
        let (sender, receiver) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |result| {
            let _ = sender.send(result);
        });
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| format!("waiting for the GPU: {e}"))?;
        receiver
            .recv()
            .map_err(|e| e.to_string())?
            .map_err(|e| format!("mapping the read-back buffer: {e}"))?;
        let mapped = slice
            .get_mapped_range()
            .map_err(|e| format!("reading the read-back buffer: {e}"))?;
        let mut pixels = Vec::with_capacity((width * height * 4) as usize);
        for row in mapped.chunks(padded_row as usize) {
            pixels.extend_from_slice(&row[..(width * 4) as usize]);
        }
        drop(mapped);
        buffer.unmap();
        if is_bgra(self.texture.format()) {
            for pixel in pixels.chunks_mut(4) {
                pixel.swap(0, 2);
            }
        }
        RgbaImage::from_raw(width, height, pixels).ok_or_else(|| "bad image size".to_string())
    }
}

/// Saves `image` as a PNG at `path`, whole or not at all (see `output_file`); the error
/// names the path.
pub fn save_png(image: &RgbaImage, path: &Path) -> Result<(), String> {
    write_atomically_with(path, |file| {
        image
            .write_to(file, ImageFormat::Png)
            .map_err(std::io::Error::other)
    })
    .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn is_bgra(format: wgpu::TextureFormat) -> bool {
    matches!(
        format,
        wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
    )
}

fn extent((width, height): (u32, u32)) -> wgpu::Extent3d {
    wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: 1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output_file::tests::{assert_only_one_file, scratch_dir};

    #[test]
    fn a_saved_png_reads_back_pixel_for_pixel() {
        let dir = scratch_dir("png-round-trip");
        let path = dir.join("shot.png");
        let image = RgbaImage::from_fn(7, 5, |x, y| {
            image::Rgba([x as u8 * 30, y as u8 * 50, 9, 255])
        });
        save_png(&image, &path).unwrap();
        assert_eq!(image::open(&path).unwrap().to_rgba8(), image);
        assert_only_one_file(&dir);
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn a_png_that_cannot_be_written_is_an_error_naming_the_path() {
        let dir = scratch_dir("png-missing-folder");
        let path = dir.join("no-such-folder").join("shot.png");
        let error = save_png(&RgbaImage::new(2, 2), &path).unwrap_err();
        assert!(error.contains("no-such-folder"), "{error}");
        assert!(!path.exists());
        std::fs::remove_dir_all(dir).unwrap();
    }
}
