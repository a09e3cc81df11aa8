//! The control panel on the left: scene, time, spawning, world settings, overlays, counters
//! and plots. It turns widget changes into simulation commands and never touches the world.

use glam::DVec3;

use crate::physics::{BroadPhaseKind, Integrator, JointDrives, Pipeline, StageTimes};
use crate::render::Overlays;
use crate::sim::{Command, Snapshot, SpawnKind, scene_names};
use crate::ui::plots;

/// Width of the control panel, egui points.
pub const PANEL_WIDTH: f32 = 290.0;

/// Below this width, points, the panel starts closed: on a phone it would hide most of the
/// scene. A button opens it, and one in it closes it again.
pub const NARROW_WIDTH: f32 = 2.5 * PANEL_WIDTH;

/// The panel on the left, or, when closed, a button that opens it. `open` is None until
/// the first frame decides it from the window's width. Returns what the panel asked for
/// and its right edge, points (0 when closed).
pub fn show_or_open_button(
    ui: &mut egui::Ui,
    panel: &mut Panel,
    open: &mut Option<bool>,
    snapshot: &Snapshot,
    stats: FrameStats,
) -> (PanelRequests, f32) {
    let is_open = open.get_or_insert_with(|| ui.ctx().content_rect().width() >= NARROW_WIDTH);
    if !*is_open {
        egui::Area::new(egui::Id::unique("open panel"))
            .fixed_pos(egui::pos2(8.0, 8.0))
            .show(ui.ctx(), |ui| {
                if ui.button("» Controls").clicked() {
                    *is_open = true;
                }
            });
        return (PanelRequests::default(), 0.0);
    }
    let shown = egui::Panel::left("controls")
        .resizable(false)
        .exact_size(PANEL_WIDTH)
        .show(ui, |ui| panel.show(ui, snapshot, stats));
    if shown.inner.hide {
        *is_open = false;
    }
    (shown.inner, shown.response.rect.right())
}

/// Where the panel's buttons save (and load) the world and the session's recording, relative
/// to the directory the viewer was started in.
#[cfg(not(target_arch = "wasm32"))]
const SAVED_WORLD_FILE: &str = "rigid-world.ron";
#[cfg(not(target_arch = "wasm32"))]
const RECORDING_FILE: &str = "rigid-recording.ron";

/// Where the Screenshot button saves the view at `step`, relative to the directory the viewer
/// was started in: one file per step, so later shots keep the earlier ones.
pub fn screenshot_file(step: u64) -> std::path::PathBuf {
    std::path::PathBuf::from(format!("rigid-screenshot-{step}.png"))
}

/// Rates measured on the render side.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameStats {
    /// Frames drawn per second, over the last quarter-second window.
    pub frames_per_second: f64,
}

/// What the panel's widgets asked for in one frame.
#[derive(Debug, Default)]
pub struct PanelRequests {
    /// Commands to send as they are.
    pub commands: Vec<Command>,
    /// Spawn buttons pressed. The panel has no camera, so the viewer aims them (see
    /// `ui::aim`) before sending them as commands.
    pub spawns: Vec<SpawnKind>,
    /// The Screenshot button was pressed: the viewer saves this frame (see `screenshot_file`)
    /// and reports back with `Panel::set_screenshot_note`.
    pub screenshot: bool,
    /// The button beside the title was pressed: fold the panel away.
    pub hide: bool,
}

/// The values the widgets edit. They are copied from the snapshot whenever the world is
/// rebuilt (reset, scene change), so the panel always shows what the simulation uses.
pub struct Panel {
    /// The overlay switches; the viewer draws with these.
    pub overlays: Overlays,
    /// Whether the camera moves with the body the scene names (`CameraHint::follow`).
    pub follow_camera: bool,
    scene: String,
    gravity: [f64; 3],
    restitution: f64,
    friction: f64,
    /// Steps per simulated second (1/dt): easier to read than milliseconds.
    rate_hz: f64,
    time_scale: f64,
    integrator: Integrator,
    pipeline: Pipeline,
    broad_phase: BroadPhaseKind,
    substeps: u32,
    sleeping: bool,
    synced_generation: Option<u64>,
    /// Where the last screenshot went, or why it failed.
    screenshot_note: Option<String>,
}

impl Default for Panel {
    fn default() -> Self {
        Panel {
            overlays: Overlays::default(),
            follow_camera: true,
            scene: String::new(),
            gravity: [0.0; 3],
            restitution: 0.0,
            friction: 0.0,
            rate_hz: 120.0,
            time_scale: 1.0,
            integrator: Integrator::default(),
            pipeline: Pipeline::default(),
            broad_phase: BroadPhaseKind::default(),
            substeps: crate::physics::solver::soft::SoftSolverSettings::default().substeps,
            sleeping: true,
            synced_generation: None,
            screenshot_note: None,
        }
    }
}

impl Panel {
    /// Draws the panel; returns what its widgets asked for this frame.
    pub fn show(
        &mut self,
        ui: &mut egui::Ui,
        snapshot: &Snapshot,
        stats: FrameStats,
    ) -> PanelRequests {
        self.sync(snapshot);
        let mut requests = PanelRequests::default();
        egui::ScrollArea::vertical().show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.heading("rigid");
                let hide = ui.small_button("«").on_hover_text("Hide the controls");
                requests.hide = hide.clicked();
                left_world(ui, snapshot);
            });
            // Errors first: a stopped simulation must be noticed.
            if let Some(message) = &snapshot.message {
                ui.colored_label(egui::Color32::LIGHT_RED, message);
            }
            faults(ui, snapshot);
            self.scene_section(ui, snapshot, &mut requests);
            ui.separator();
            self.time_section(ui, &mut requests.commands);
            ui.separator();
            spawn_section(ui, &mut requests.spawns);
            ui.separator();
            self.world_section(ui, &mut requests.commands);
            materials_section(ui, snapshot, &mut requests.commands);
            joints_section(ui, snapshot, &mut requests.commands);
            ui.separator();
            self.overlay_section(ui, snapshot);
            ui.separator();
            counters(ui, snapshot, stats);
            ui.separator();
            egui::CollapsingHeader::new("Energy (J)")
                .default_open(true)
                .show(ui, |ui| plots::energy(ui, &snapshot.history));
            egui::CollapsingHeader::new("Momentum (N·s, N·m·s)")
                .default_open(true)
                .show(ui, |ui| plots::momentum(ui, &snapshot.history));
            egui::CollapsingHeader::new("Deepest overlap (mm)")
                .default_open(false)
                .show(ui, |ui| plots::penetration(ui, &snapshot.history));
        });
        requests
    }

    /// Shows `note` (where the screenshot was saved, or why it was not) under the button.
    pub fn set_screenshot_note(&mut self, note: String) {
        self.screenshot_note = Some(note);
    }

    fn sync(&mut self, snapshot: &Snapshot) {
        if self.synced_generation == Some(snapshot.world_generation) {
            return;
        }
        let s = &snapshot.settings;
        self.scene = snapshot.scene.clone();
        self.gravity = s.gravity.to_array();
        self.restitution = s.restitution;
        self.friction = s.friction;
        self.rate_hz = 1.0 / s.dt;
        self.time_scale = s.time_scale;
        self.integrator = s.integrator;
        self.pipeline = s.pipeline;
        self.broad_phase = s.broad_phase;
        self.substeps = s.substeps;
        self.sleeping = s.sleeping;
        self.synced_generation = Some(snapshot.world_generation);
    }

    fn scene_section(
        &mut self,
        ui: &mut egui::Ui,
        snapshot: &Snapshot,
        requests: &mut PanelRequests,
    ) {
        let out = &mut requests.commands;
        egui::ComboBox::from_label("scene")
            .selected_text(self.scene.as_str())
            .show_ui(ui, |ui| {
                for name in scene_names() {
                    if ui.selectable_label(self.scene == name, name).clicked() {
                        self.scene = name.to_string();
                        out.push(Command::LoadScene(name.to_string()));
                    }
                }
            });
        ui.horizontal(|ui| {
            let paused = snapshot.settings.paused;
            if ui.button(if paused { "Run" } else { "Pause" }).clicked() {
                out.push(Command::SetPaused(!paused));
            }
            if ui.button("Step").clicked() {
                out.push(Command::SetPaused(true));
                out.push(Command::StepOnce);
            }
            if ui.button("Reset").clicked() {
                out.push(Command::Reset);
            }
            #[cfg(not(target_arch = "wasm32"))]
            {
                let hover = "saves the window to rigid-screenshot-STEP.png";
                requests.screenshot |= ui.button("Screenshot").on_hover_text(hover).clicked();
            }
        });
        #[cfg(not(target_arch = "wasm32"))]
        files_row(ui, &mut requests.commands);
        // Only once there is one, so that no widget moves before the first screenshot.
        if let Some(note) = &self.screenshot_note {
            ui.label(note);
        }
    }

    fn time_section(&mut self, ui: &mut egui::Ui, out: &mut Vec<Command>) {
        let scale = egui::Slider::new(&mut self.time_scale, 0.0..=4.0).text("time scale");
        if ui.add(scale).changed() {
            out.push(Command::SetTimeScale(self.time_scale));
        }
        let rate = egui::Slider::new(&mut self.rate_hz, 30.0..=1000.0)
            .logarithmic(true)
            .suffix(" Hz")
            .text("step rate (1/dt)");
        if ui.add(rate).changed() {
            out.push(Command::SetDt(1.0 / self.rate_hz));
        }
        egui::ComboBox::from_label("integrator")
            .selected_text(self.integrator.name())
            .show_ui(ui, |ui| {
                for integrator in Integrator::ALL {
                    let selected = self.integrator == integrator;
                    if ui.selectable_label(selected, integrator.name()).clicked() {
                        self.integrator = integrator;
                        out.push(Command::SetIntegrator(integrator));
                    }
                }
            });
        egui::ComboBox::from_label("pipeline")
            .selected_text(pipeline_name(self.pipeline))
            .show_ui(ui, |ui| {
                for pipeline in [Pipeline::Soft, Pipeline::Classic] {
                    let selected = self.pipeline == pipeline;
                    if ui
                        .selectable_label(selected, pipeline_name(pipeline))
                        .clicked()
                    {
                        self.pipeline = pipeline;
                        out.push(Command::SetPipeline(pipeline));
                    }
                }
            });
        egui::ComboBox::from_label("broad phase")
            .selected_text(broad_phase_name(self.broad_phase))
            .show_ui(ui, |ui| {
                for kind in BROAD_PHASE_CHOICES {
                    let selected = self.broad_phase == kind;
                    if ui
                        .selectable_label(selected, broad_phase_name(kind))
                        .clicked()
                    {
                        self.broad_phase = kind;
                        out.push(Command::SetBroadPhase(kind));
                    }
                }
            });
        let substeps = egui::Slider::new(&mut self.substeps, 1..=32).text("substeps");
        if ui.add(substeps).changed() {
            out.push(Command::SetSubsteps(self.substeps));
        }
        if ui.checkbox(&mut self.sleeping, "sleeping").changed() {
            out.push(Command::SetSleeping(self.sleeping));
        }
    }

    fn world_section(&mut self, ui: &mut egui::Ui, out: &mut Vec<Command>) {
        let mut changed = false;
        ui.horizontal(|ui| {
            ui.label("gravity");
            for (name, g) in [("Earth", -9.81), ("Moon", -1.62), ("Zero", 0.0)] {
                if ui.button(name).clicked() {
                    self.gravity = [0.0, g, 0.0];
                    changed = true;
                }
            }
        });
        ui.horizontal(|ui| {
            for (value, axis) in self.gravity.iter_mut().zip(["x", "y", "z"]) {
                let drag = egui::DragValue::new(value)
                    .speed(0.05)
                    .range(-50.0..=50.0)
                    .fixed_decimals(2)
                    .prefix(format!("{axis} "));
                changed |= ui.add(drag).changed();
            }
            ui.label("m/s²");
        });
        if changed {
            out.push(Command::SetGravity(DVec3::from_array(self.gravity)));
        }
        let e = egui::Slider::new(&mut self.restitution, 0.0..=1.0).text("restitution");
        if ui.add(e).changed() {
            out.push(Command::SetRestitution(self.restitution));
        }
        let mu = egui::Slider::new(&mut self.friction, 0.0..=2.0).text("friction");
        if ui.add(mu).changed() {
            out.push(Command::SetFriction(self.friction));
        }
    }

    fn overlay_section(&mut self, ui: &mut egui::Ui, snapshot: &Snapshot) {
        let followed = (snapshot.camera.follow).and_then(|f| snapshot.names.get(f.index));
        if let Some(name) = followed {
            ui.checkbox(&mut self.follow_camera, format!("camera follows {name}"))
                .on_hover_text("Move the camera with this body, as the scene asks");
        }
        let o = &mut self.overlays;
        ui.horizontal_wrapped(|ui| {
            ui.checkbox(&mut o.grid, "grid");
            ui.checkbox(&mut o.aabbs, "AABBs");
            ui.checkbox(&mut o.velocities, "velocities");
            ui.checkbox(&mut o.contacts, "contacts");
            ui.checkbox(&mut o.joints, "joints");
            ui.checkbox(&mut o.broad_phase, "broad phase");
            ui.checkbox(&mut o.sleep_tint, "sleeping colour");
            ui.checkbox(&mut o.x_ray, "x-ray").on_hover_text(
                "Draw boxes, velocities, contacts and joints through the bodies in front",
            );
        });
    }
}

/// The spawn buttons. Their bodies appear in view, above what the view's centre shows; keys
/// 1 to 5 spawn the same kinds at the cursor.
fn spawn_section(ui: &mut egui::Ui, out: &mut Vec<SpawnKind>) {
    ui.label("Spawn in view")
        .on_hover_text("keys 1 to 5 spawn these at the cursor");
    ui.horizontal_wrapped(|ui| {
        for kind in SpawnKind::ALL {
            if ui.button(kind.name()).clicked() {
                out.push(kind);
            }
        }
    });
}

/// Save and load buttons, for a viewer with a file system (not the browser's).
#[cfg(not(target_arch = "wasm32"))]
fn files_row(ui: &mut egui::Ui, out: &mut Vec<Command>) {
    ui.horizontal(|ui| {
        let world = std::path::PathBuf::from(SAVED_WORLD_FILE);
        if ui
            .button("Save world")
            .on_hover_text(SAVED_WORLD_FILE)
            .clicked()
        {
            out.push(Command::SaveWorld(world.clone()));
        }
        if ui
            .button("Load world")
            .on_hover_text(SAVED_WORLD_FILE)
            .clicked()
        {
            out.push(Command::LoadWorld(world));
        }
        let recording = "replay with: rigid --replay rigid-recording.ron";
        if ui
            .button("Save recording")
            .on_hover_text(recording)
            .clicked()
        {
            out.push(Command::SaveRecording(std::path::PathBuf::from(
                RECORDING_FILE,
            )));
        }
    });
}

/// Restitution and friction per material of the scene, folded by default (the sliders
/// above set every body at once).
fn materials_section(ui: &mut egui::Ui, snapshot: &Snapshot, out: &mut Vec<Command>) {
    egui::CollapsingHeader::new("Materials")
        .default_open(false)
        .show(ui, |ui| {
            for material in &snapshot.materials {
                ui.label(format!("{} ({} bodies)", material.name, material.bodies));
                let (mut e, mut mu) = (material.restitution, material.friction);
                let changed = ui
                    .add(egui::Slider::new(&mut e, 0.0..=1.0).text("restitution"))
                    .changed()
                    | ui.add(egui::Slider::new(&mut mu, 0.0..=2.0).text("friction"))
                        .changed();
                if changed {
                    out.push(Command::SetMaterial {
                        name: material.name.clone(),
                        restitution: e,
                        friction: mu,
                    });
                }
            }
        });
}

/// The motors, servos and springs of the scene's joints, changed live; absent from scenes
/// without any.
fn joints_section(ui: &mut egui::Ui, snapshot: &Snapshot, out: &mut Vec<Command>) {
    if snapshot.driven_joints.is_empty() {
        return;
    }
    egui::CollapsingHeader::new("Joint drives")
        .default_open(true)
        .show(ui, |ui| {
            for driven in &snapshot.driven_joints {
                ui.label(&driven.label);
                let mut drives = driven.drives;
                if drive_controls(ui, &mut drives) {
                    out.push(Command::SetJointDrives {
                        joint: driven.joint,
                        drives,
                    });
                }
            }
        });
}

/// A joint's motor, servo and spring values as drag values; whether one changed.
fn drive_controls(ui: &mut egui::Ui, drives: &mut JointDrives) -> bool {
    let mut changed = false;
    let mut value = |ui: &mut egui::Ui, v: &mut f64, range: (f64, f64), text: &str| {
        let drag = egui::DragValue::new(v).speed(0.1).range(range.0..=range.1);
        changed |= ui.add(drag.prefix(text)).changed();
    };
    ui.horizontal(|ui| {
        if let Some(motor) = &mut drives.motor {
            value(ui, &mut motor.speed, (-100.0, 100.0), "motor speed ");
            value(ui, &mut motor.max_force, (0.0, 1e5), "max ");
        }
        if let Some(servo) = &mut drives.servo {
            value(ui, &mut servo.hertz, (0.0, 60.0), "servo Hz ");
            value(ui, &mut servo.max_force, (0.0, 1e5), "max ");
        }
        if let Some(spring) = &mut drives.spring {
            value(ui, &mut spring.hertz, (0.0, 60.0), "spring Hz ");
            value(ui, &mut spring.damping_ratio, (0.0, 10.0), "damping ");
        }
    });
    changed
}

/// Bodies whose state went non-finite: the world isolated them (they no longer move, touch
/// anything or get drawn); the user should know which and when.
fn faults(ui: &mut egui::Ui, snapshot: &Snapshot) {
    if snapshot.fault_count == 0 {
        return;
    }
    let colour = egui::Color32::LIGHT_RED;
    ui.colored_label(
        colour,
        format!(
            "isolated (not finite, or beyond contact range): {} bodies",
            snapshot.fault_count
        ),
    );
    for fault in &snapshot.faults {
        ui.colored_label(
            colour,
            format!(
                "  {} (body {}) at step {}, t = {:.3} s: {}",
                fault.name,
                fault.body.index(),
                fault.step,
                fault.time,
                fault.reason
            ),
        );
    }
}

/// How many bodies fell far below the scene and were taken out (see `sim::world_bounds`);
/// beside the heading, where it is always in view and moves no button.
fn left_world(ui: &mut egui::Ui, snapshot: &Snapshot) {
    match snapshot.left_world {
        0 => {}
        1 => {
            ui.label("1 body left the world");
        }
        n => {
            ui.label(format!("{n} bodies left the world"));
        }
    }
}

const STAGES_LABEL: &str = "stages (µs)";
const STAGES_LEGEND: &str =
    "b broad phase, n narrow phase, i islands and sleep, s contact solve, g integration";

fn stage_times(s: &StageTimes) -> String {
    let us = |seconds: f64| seconds * 1e6;
    format!(
        "b {:.0} n {:.0} i {:.0} s {:.0} g {:.0}",
        us(s.broad_phase),
        us(s.narrow_phase),
        us(s.islands),
        us(s.solve),
        us(s.integrate)
    )
}

fn counters(ui: &mut egui::Ui, snapshot: &Snapshot, stats: FrameStats) {
    let c = &snapshot.counters;
    let pairs = [
        [
            ("bodies", c.bodies.to_string()),
            ("sim time", format!("{:.2} s", c.sim_time)),
        ],
        [
            ("sim rate", format!("{:.0}/s", c.step_rate)),
            ("step", format!("{:.3} ms", c.step_wall_time * 1e3)),
        ],
        [
            ("awake", c.awake.to_string()),
            ("contacts", c.contacts.to_string()),
        ],
        [
            ("pairs", c.pairs.to_string()),
            ("render", format!("{:.0} fps", stats.frames_per_second)),
        ],
    ];
    let singles = [
        (
            "energy",
            format!("{:.2} J", c.kinetic_energy + c.potential_energy),
        ),
        ("|p|", format!("{:.3} N·s", c.linear_momentum)),
        ("|L|", format!("{:.3} N·m·s", c.angular_momentum)),
        ("max overlap", format!("{:.2} mm", c.max_penetration * 1e3)),
        (STAGES_LABEL, stage_times(&c.stages)),
    ];
    // Short counters two to a row keep the plots in view on a 720-pixel window.
    egui::Grid::new("short counters")
        .num_columns(4)
        .show(ui, |ui| {
            for pair in &pairs {
                for (name, value) in pair {
                    ui.label(*name);
                    ui.monospace(value);
                }
                ui.end_row();
            }
        });
    egui::Grid::new("long counters")
        .num_columns(2)
        .show(ui, |ui| {
            for (name, value) in &singles {
                let label = ui.label(*name);
                if *name == STAGES_LABEL {
                    label.on_hover_text(STAGES_LEGEND);
                }
                ui.monospace(value);
                ui.end_row();
            }
        });
}

fn pipeline_name(pipeline: Pipeline) -> &'static str {
    match pipeline {
        Pipeline::Soft => "soft (substepped solver)",
        Pipeline::Classic => "classic (the report's)",
    }
}

/// The broad phases the panel offers; the grid's cells are 1 m, about a typical body.
const BROAD_PHASE_CHOICES: [BroadPhaseKind; 3] = [
    BroadPhaseKind::SweepAndPrune,
    BroadPhaseKind::UniformGrid { cell_size: 1.0 },
    BroadPhaseKind::BruteForce,
];

fn broad_phase_name(kind: BroadPhaseKind) -> &'static str {
    match kind {
        BroadPhaseKind::SweepAndPrune => "sweep and prune",
        BroadPhaseKind::UniformGrid { .. } => "uniform grid (1 m cells)",
        BroadPhaseKind::BruteForce => "brute force (n²)",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn screenshots_are_named_by_their_step_in_the_working_directory() {
        assert_eq!(
            screenshot_file(303),
            std::path::Path::new("rigid-screenshot-303.png")
        );
        assert_ne!(screenshot_file(1), screenshot_file(2));
    }

    /// A panel in its egui context, showing the falling box.
    struct Harness {
        ctx: egui::Context,
        snapshot: Snapshot,
        open: Option<bool>,
    }

    impl Harness {
        fn new() -> Harness {
            let sim = crate::sim::simulation::Simulation::new("falling_box").unwrap();
            Harness {
                ctx: egui::Context::default(),
                snapshot: sim.snapshot(web_time::Instant::now()),
                open: None,
            }
        }

        /// One frame of the panel (or its button) in a window of `size` points, with
        /// `events`; the panel's right edge, points.
        fn frame(&mut self, size: egui::Vec2, events: Vec<egui::Event>) -> f32 {
            let raw = egui::RawInput {
                screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, size)),
                events,
                ..Default::default()
            };
            let (mut panel, mut right) = (Panel::default(), f32::NAN);
            let stats = FrameStats {
                frames_per_second: 60.0,
            };
            let (open, snapshot) = (&mut self.open, &self.snapshot);
            let _ = self.ctx.run_ui(raw, |ui| {
                (_, right) = show_or_open_button(ui, &mut panel, open, snapshot, stats);
            });
            right
        }
    }

    /// On a phone (390 × 844 points) the panel starts closed and leaves the whole width to
    /// the scene; a tap on its button opens it. On 1280 × 720 it starts open.
    #[test]
    fn the_panel_starts_closed_on_a_phone_and_a_tap_opens_it() {
        let phone = egui::vec2(390.0, 844.0);
        let mut harness = Harness::new();
        assert_eq!(harness.frame(phone, vec![]), 0.0);
        assert_eq!(harness.open, Some(false));
        let at = egui::pos2(30.0, 18.0);
        let button = |pressed| egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        };
        // The button is laid out on the first frame, and can be hit from the next.
        harness.frame(phone, vec![egui::Event::PointerMoved(at)]);
        harness.frame(phone, vec![button(true)]);
        harness.frame(phone, vec![button(false)]);
        assert_eq!(harness.open, Some(true), "the tap opened the panel");
        assert_eq!(harness.frame(phone, vec![]), PANEL_WIDTH);
        let desktop = egui::vec2(1280.0, 720.0);
        assert_eq!(Harness::new().frame(desktop, vec![]), PANEL_WIDTH);
    }
}
