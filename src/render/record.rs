//! A run recorded to an animated GIF without a window: the scene steps at its own dt, a frame
//! is drawn every 1/fps s of simulated time and encoded as it comes, so memory stays at one
//! frame whatever the length. Used by `rigid record` and the render tests.

use std::path::Path;

use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame};

use crate::output_file::write_atomically_with;
use crate::render::gpu::Gpu;
use crate::render::headless::{self, OffscreenPainter};
use crate::render::renderer::Overlays;
use crate::sim::Simulation;

/// The most frames one recording may hold (a minute at 30 fps): each costs a render, a
/// read-back and a colour quantisation, and the file grows with every one.
pub const MAX_FRAMES: u64 = 1800;

/// The highest frame rate: GIF delays are hundredths of a second, and browsers play delays
/// under two hundredths at ten.
pub const MAX_FPS: u32 = 50;

/// The default frame rate: 25 fps is a whole 4 hundredths per frame, so the GIF plays at
/// the simulation's speed exactly.
pub const DEFAULT_FPS: u32 = 25;

/// The quantiser's speed, 1 (best colours, slowest) to 30: 10 keeps the bodies' shading
/// smooth at a tenth of the cost of 1.
const QUANTISER_SPEED: i32 = 10;

/// What a recording draws: the bodies on the grid, and the joints that hold them. Contact
/// markers and the sleep colour show the solver's state, which flickers from frame to frame
/// and hides the motion.
const RECORDED_OVERLAYS: Overlays = Overlays {
    grid: true,
    aabbs: false,
    velocities: false,
    contacts: false,
    joints: true,
    broad_phase: false,
    sleep_tint: false,
    x_ray: false,
};

/// What to record: how long, how often and how large.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Take {
    /// Simulated seconds to record.
    pub seconds: f64,
    /// Frames per simulated (and played) second.
    pub fps: u32,
    /// Width and height of each frame, pixels.
    pub size: (u32, u32),
}

impl Take {
    /// The frames the recording holds, seconds × fps rounded: one at t = 0 and one every
    /// 1/fps s after. A length or rate that makes none, or more than `MAX_FRAMES`, is
    /// refused before any work is done.
    pub fn frame_count(&self) -> Result<u32, String> {
        if !(1..=MAX_FPS).contains(&self.fps) {
            return Err(format!(
                "--fps must lie in [1, {MAX_FPS}] frames per second, got {}",
                self.fps
            ));
        }
        let frames = self.seconds * f64::from(self.fps);
        if !(frames.is_finite() && frames.round() >= 1.0) {
            return Err(format!(
                "--seconds must give at least one frame at {} fps, got {}",
                self.fps, self.seconds
            ));
        }
        if frames.round() > MAX_FRAMES as f64 {
            return Err(format!(
                "{} s at {} fps is {frames:.0} frames; a recording holds at most {MAX_FRAMES}: \
                 shorten it or lower --fps",
                self.seconds, self.fps
            ));
        }
        Ok(frames.round() as u32)
    }
}

/// Records `scene` to the GIF `output`, calling `on_frame(done, total)` after each frame.
/// Returns the number of frames. The file is written whole or not at all: any failure
/// leaves what was at `output` before.
pub fn record(
    gpu: &Gpu,
    scene: &str,
    take: Take,
    output: &Path,
    on_frame: &mut dyn FnMut(u32, u32),
) -> Result<u32, String> {
    let frames = take.frame_count()?;
    let mut sim = Simulation::new(scene)?;
    let mut painter = OffscreenPainter::new(gpu, take.size)?;
    let delay = Delay::from_numer_denom_ms(1000, take.fps);
    let written = write_atomically_with(output, |file| {
        let mut encoder = GifEncoder::new_with_speed(file, QUANTISER_SPEED);
        encoder.set_repeat(Repeat::Infinite).map_err(image_error)?;
        for index in 0..frames {
            step_to(&mut sim, f64::from(index) / f64::from(take.fps));
            if let Some(failure) = sim.failure() {
                return Err(RecordError::Other(format!(
                    "the simulation stopped: {failure}"
                )));
            }
            let snapshot = headless::still_snapshot(&sim);
            let image = painter
                .paint(gpu, &snapshot, RECORDED_OVERLAYS)
                .map_err(RecordError::Other)?;
            encoder
                .encode_frame(Frame::from_parts(image, 0, 0, delay))
                .map_err(image_error)?;
            on_frame(index + 1, frames);
        }
        Ok(())
    });
    written.map_err(|e| match e {
        RecordError::Io(e) => format!("cannot write {}: {e}", output.display()),
        RecordError::Other(message) => message,
    })?;
    Ok(frames)
}

/// Steps `sim` until its clock is nearest `time` (s); a frame time between two steps takes
/// the nearer one.
fn step_to(sim: &mut Simulation, time: f64) {
    let target_ticks = (time / sim.settings().dt).round() as u64;
    while sim.ticks() < target_ticks && sim.failure().is_none() {
        sim.step();
    }
}

/// Why a recording stopped: the file, or the simulation or rendering.
enum RecordError {
    Io(std::io::Error),
    Other(String),
}

impl From<std::io::Error> for RecordError {
    fn from(e: std::io::Error) -> Self {
        RecordError::Io(e)
    }
}

fn image_error(e: image::ImageError) -> RecordError {
    match e {
        image::ImageError::IoError(e) => RecordError::Io(e),
        other => RecordError::Other(format!("encoding the GIF: {other}")),
    }
}
