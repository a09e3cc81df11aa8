//! The viewer. With no arguments it opens a window on the default scene; `rigid render`
//! draws a scene to a PNG without a window.
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
    use std::path::PathBuf;
    use std::process::ExitCode;

    use clap::{Parser, Subcommand};

    use rigid::render::Overlays;
    use rigid::render::gpu::Gpu;
    use rigid::render::headless;
    use rigid::sim::{DEFAULT_SCENE, FileCommands, scene_names};

    #[derive(Parser)]
    #[command(version, about = "Real-time rigid-body physics viewer")]
    struct Cli {
        /// Scene to open (see `rigid scenes`).
        #[arg(long, default_value = DEFAULT_SCENE)]
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
            #[arg(long, default_value = DEFAULT_SCENE)]
            scene: String,
            /// Fixed steps (of 1/120 s) to simulate before drawing.
            #[arg(long, default_value_t = 0)]
            steps: u32,
            #[arg(long, default_value_t = 1280)]
            width: u32,
            #[arg(long, default_value_t = 720)]
            height: u32,
            /// Draw bounding boxes.
            #[arg(long)]
            aabbs: bool,
            /// Draw velocity vectors.
            #[arg(long)]
            velocities: bool,
        },
        /// List the built-in scenes.
        Scenes,
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
            }) => {
                let overlays = Overlays {
                    aabbs,
                    velocities,
                    ..Overlays::default()
                };
                render(&scene, steps, (width, height), overlays, &output)
            }
            None => rigid::ui::app::run(rigid::ui::app::AppOptions {
                scene: cli.scene,
                exit_after: cli.exit_after,
                screenshot: cli.screenshot,
                replay: cli.replay,
                replay_files: if cli.allow_file_commands {
                    FileCommands::Allow
                } else {
                    FileCommands::Refuse
                },
            }),
        };
        match result {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("rigid: {e}");
                ExitCode::FAILURE
            }
        }
    }

    fn render(
        scene: &str,
        steps: u32,
        size: (u32, u32),
        overlays: Overlays,
        output: &PathBuf,
    ) -> Result<(), String> {
        let snapshot = headless::simulate(scene, steps)?;
        let gpu = Gpu::offscreen()?;
        let image = headless::render_snapshot(&gpu, &snapshot, overlays, size)?;
        image
            .save(output)
            .map_err(|e| format!("cannot write {}: {e}", output.display()))
    }
}
