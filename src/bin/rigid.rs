//! The viewer. With no arguments it opens a window on the default scene; `rigid render`
//! draws a scene to a PNG and `rigid record` a run to an animated GIF, without a window.
//! Built for the browser (wasm32), it runs the same viewer in the page `web/index.html`.

#[cfg(target_arch = "wasm32")]
fn main() {
    rigid::ui::app::run_in_browser();
}

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    desktop::main()
}

#[cfg(not(target_arch = "wasm32"))]
mod desktop {
    use std::path::{Path, PathBuf};
    use std::process::ExitCode;

    use clap::{Parser, Subcommand};

    use rigid::cli_arg::Utf8Text;
    use rigid::progress::Progress;
    use rigid::render::Overlays;
    use rigid::render::gpu::Gpu;
    use rigid::render::headless;
    use rigid::render::offscreen::save_png;
    use rigid::render::record;
    use rigid::sim::{DEFAULT_SCENE, FileCommands, scene_names};

    #[derive(Parser)]
    #[command(version, about = "Real-time rigid-body physics viewer")]
    struct Cli {
        /// Scene to open (see `rigid scenes`).
        #[arg(long, default_value = DEFAULT_SCENE, value_parser = Utf8Text)]
        scene: String,
        /// Close the window after this many seconds (for scripted runs and tests).
        #[arg(long)]
        exit_after: Option<f64>,
        /// Save the last frame, panel included, to this PNG before exiting.
        #[arg(long)]
        screenshot: Option<PathBuf>,
        /// Replay a recording saved from the panel ("Save recording").
        #[arg(long, conflicts_with = "scene")]
        replay: Option<PathBuf>,
        /// Let the replay run the recording's commands that save or load files (SaveWorld,
        /// SaveRecording, LoadWorld, LoadScene of a file); without it such a recording is
        /// refused.
        #[arg(long, requires = "replay")]
        allow_file_commands: bool,
        #[command(subcommand)]
        command: Option<Command>,
    }

    #[derive(Subcommand)]
    enum Command {
        /// Step a scene and draw it offscreen to a PNG, without a window.
        Render {
            /// Output PNG.
            output: PathBuf,
            #[arg(long, default_value = DEFAULT_SCENE, value_parser = Utf8Text)]
            scene: String,
            /// Fixed steps (of 1/120 s) to simulate before drawing.
            #[arg(long, default_value_t = 0)]
            steps: u32,
            /// Image width, pixels, in [1, 16384] (less where the adapter offers less).
            #[arg(
                long,
                default_value_t = 1280,
                value_parser = image_side,
                allow_negative_numbers = true
            )]
            width: u32,
            /// Image height, pixels, in [1, 16384] (less where the adapter offers less).
            #[arg(
                long,
                default_value_t = 720,
                value_parser = image_side,
                allow_negative_numbers = true
            )]
            height: u32,
            /// Draw bounding boxes.
            #[arg(long)]
            aabbs: bool,
            /// Draw velocity vectors.
            #[arg(long)]
            velocities: bool,
            /// Draw the overlays through the bodies in front of them.
            #[arg(long)]
            x_ray: bool,
        },
        /// Run a scene and record it offscreen to an animated GIF, without a window.
        Record {
            /// Output GIF.
            output: PathBuf,
            #[arg(long, default_value = DEFAULT_SCENE, value_parser = Utf8Text)]
            scene: String,
            /// Simulated seconds to record; seconds × fps may be at most 1800 frames.
            #[arg(long, default_value_t = 5.0, allow_negative_numbers = true)]
            seconds: f64,
            /// Frames per simulated second, in [1, 50].
            #[arg(long, default_value_t = record::DEFAULT_FPS)]
            fps: u32,
            /// Frame width, pixels, in [1, 16384] (less where the adapter offers less).
            #[arg(
                long,
                default_value_t = 480,
                value_parser = image_side,
                allow_negative_numbers = true
            )]
            width: u32,
            /// Frame height, pixels, in [1, 16384] (less where the adapter offers less).
            #[arg(
                long,
                default_value_t = 320,
                value_parser = image_side,
                allow_negative_numbers = true
            )]
            height: u32,
        },
        /// List the built-in scenes.
        Scenes,
    }

    fn note_shadowed_file(scene: &str) {
        if let Some(note) = rigid::scene::shadowed_file_note(scene) {
            eprintln!("rigid: note: {note}");
        }
    }

    /// Checked before any device exists, so a bad size needs no graphics adapter to be told.
    fn image_side(text: &str) -> Result<u32, String> {
        let max = headless::MAX_IMAGE_SIZE;
        match text.parse::<u64>() {
            Ok(value) if (1..=u64::from(max)).contains(&value) => Ok(value as u32),
            _ => Err(format!("must be a whole number of pixels in [1, {max}]")),
        }
    }

    /// Why the command failed, and its exit code: 2 for what the user asked wrong, as clap
    /// gives for bad arguments, 1 for anything else.
    struct Failure {
        code: u8,
        message: String,
    }

    impl From<String> for Failure {
        fn from(message: String) -> Self {
            Failure { code: 1, message }
        }
    }

    pub fn main() -> ExitCode {
        let cli = Cli::parse();
        let result = match cli.command {
            Some(Command::Scenes) => {
                println!("{}", scene_names().collect::<Vec<_>>().join("\n"));
                Ok(())
            }
            Some(Command::Render {
                output,
                scene,
                steps,
                width,
                height,
                aabbs,
                velocities,
                x_ray,
            }) => {
                let overlays = Overlays {
                    aabbs,
                    velocities,
                    x_ray,
                    ..Overlays::default()
                };
                render(&scene, steps, (width, height), overlays, &output)
            }
            Some(Command::Record {
                output,
                scene,
                seconds,
                fps,
                width,
                height,
            }) => {
                let take = record::Take {
                    seconds,
                    fps,
                    size: (width, height),
                };
                record(&scene, take, &output)
            }
            None => {
                note_shadowed_file(&cli.scene);
                rigid::ui::app::run(rigid::ui::app::AppOptions {
                    scene: cli.scene,
                    exit_after: cli.exit_after,
                    screenshot: cli.screenshot,
                    replay: cli.replay,
                    replay_files: if cli.allow_file_commands {
                        FileCommands::Allow
                    } else {
                        FileCommands::Refuse
                    },
                })
                .map_err(Failure::from)
            }
        };
        match result {
            Ok(()) => ExitCode::SUCCESS,
            Err(failure) => {
                eprintln!("rigid: {}", failure.message);
                ExitCode::from(failure.code)
            }
        }
    }

    fn render(
        scene: &str,
        steps: u32,
        size: (u32, u32),
        overlays: Overlays,
        output: &Path,
    ) -> Result<(), Failure> {
        note_shadowed_file(scene);
        let snapshot = headless::simulate(scene, steps)?;
        let gpu = Gpu::offscreen()?;
        headless::check_size(&gpu, size).map_err(|message| Failure { code: 2, message })?;
        let image = headless::render_snapshot(&gpu, &snapshot, overlays, size)?;
        save_png(&image, output).map_err(Failure::from)
    }

    fn record(scene: &str, take: record::Take, output: &Path) -> Result<(), Failure> {
        note_shadowed_file(scene);
        let user_error = |message| Failure { code: 2, message };
        let frames = take.frame_count().map_err(user_error)?;
        let gpu = Gpu::offscreen()?;
        headless::check_size(&gpu, take.size).map_err(user_error)?;
        let mut progress = Progress::new("frames", u64::from(frames));
        let mut on_frame = |done: u32, _total: u32| progress.update(u64::from(done));
        record::record(&gpu, scene, take, output, &mut on_frame)?;
        progress.finish();
        println!(
            "wrote {}: {frames} frames of {}x{}, {} s at {} fps",
            output.display(),
            take.size.0,
            take.size.1,
            take.seconds,
            take.fps
        );
        Ok(())
    }
}
