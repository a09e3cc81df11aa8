//! The event loop: it owns the simulation handle, the window and the camera, turns mouse and
//! keyboard input into camera moves and simulation commands, and draws a frame per redraw.

use std::path::PathBuf;
use std::sync::Arc;
use web_time::Instant;

use glam::{DVec3, Vec2};
use image::RgbaImage;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, Touch, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

use crate::render::offscreen::save_png;
use crate::render::{FrameInput, OrbitCamera, Ray, Viewport};
use crate::sim::snapshot::BodyPose;
use crate::sim::{
    CameraHint, Command, Driver, FileCommands, Recording, Simulation, Snapshot, SpawnKind,
};
use crate::ui::aim;
use crate::ui::display::{Display, UiFrame};
use crate::ui::drag::Drag;
use crate::ui::inspector;
use crate::ui::panel::{self, FrameStats, Panel, PanelRequests, screenshot_file};
use crate::ui::picking::{self, Pick};
use crate::ui::touch::{Gesture, Touches};

/// How to start the viewer.
pub struct AppOptions {
    /// A built-in scene's name or the path of a scene file.
    pub scene: String,
    /// Close after this many seconds.
    pub exit_after: Option<f64>,
    /// Save the last frame here before closing.
    pub screenshot: Option<PathBuf>,
    /// Replay this recording (see `sim::recording`) instead of starting `scene` fresh.
    pub replay: Option<PathBuf>,
    /// Whether the replay may run the recording's commands that read or write files.
    pub replay_files: FileCommands,
}

/// Opens the viewer window and runs until it is closed (or `exit_after` passes).
#[cfg(not(target_arch = "wasm32"))]
pub fn run(options: AppOptions) -> Result<(), String> {
    let (event_loop, mut app) = prepare(options)?;
    // Redraw continuously: the simulation moves whether or not there is input.
    event_loop.set_control_flow(ControlFlow::Poll);
    event_loop
        .run_app(&mut app)
        .map_err(|e| format!("event loop: {e}"))?;
    app.result
}

/// Starts the viewer in the page (`web/index.html`) on the scene its address names, and
/// returns: the browser runs the event loop. Failures, panics included, are shown on the
/// page instead of leaving it blank.
#[cfg(target_arch = "wasm32")]
pub fn run_in_browser() {
    use winit::platform::web::EventLoopExtWebSys;
    std::panic::set_hook(Box::new(|info| {
        console_error_panic_hook::hook(info);
        crate::web::show_failure(&format!("The viewer stopped: {info}"));
    }));
    let options = AppOptions {
        scene: crate::web::requested_scene(),
        exit_after: None,
        screenshot: None,
        replay: None,
        replay_files: FileCommands::Refuse,
    };
    match prepare(options) {
        // Each redraw asks for the next one, so frames follow the page's refresh rate.
        Ok((event_loop, app)) => {
            event_loop.set_control_flow(ControlFlow::Wait);
            event_loop.spawn_app(app)
        }
        Err(e) => crate::web::show_failure(&e),
    }
}

/// The simulation and the event loop, before any window exists.
fn prepare(options: AppOptions) -> Result<(EventLoop<()>, App), String> {
    let simulation = match &options.replay {
        Some(path) => {
            let recording = Recording::load(path).map_err(|e| e.to_string())?;
            let file = path.display().to_string();
            Simulation::replaying(&recording, &file, options.replay_files)
                .map_err(|e| e.to_string())?
        }
        None => Simulation::new(&options.scene)?,
    };
    let sim = Driver::start(simulation)?;
    let event_loop = EventLoop::new().map_err(|e| format!("cannot open a window: {e}"))?;
    Ok((event_loop, App::new(options, sim)))
}

/// In the browser the device is created asynchronously: it lands here, and the next event
/// installs it.
#[cfg(target_arch = "wasm32")]
type PendingDisplay = std::rc::Rc<std::cell::RefCell<Option<Result<Display, String>>>>;

/// Mouse state between events: where the cursor is and what a held button does.
#[derive(Default)]
struct Mouse {
    /// Physical pixels from the window's top-left corner.
    position: Option<Vec2>,
    orbiting: bool,
    panning: bool,
}

struct App {
    options: AppOptions,
    sim: Driver,
    display: Option<Display>,
    window_created: bool,
    #[cfg(target_arch = "wasm32")]
    pending_display: PendingDisplay,
    egui_ctx: egui::Context,
    egui_state: Option<egui_winit::State>,
    panel: Panel,
    /// Whether the panel is shown (`panel::show_or_open_button`).
    panel_open: Option<bool>,
    camera: OrbitCamera,
    camera_generation: Option<u64>,
    /// How far the followed body had moved at the last frame (`CameraHint::follow_shift`).
    follow_shift: glam::Vec3,
    viewport: Viewport,
    mouse: Mouse,
    touches: Touches,
    drag: Option<Drag>,
    clock: FrameClock,
    started: Instant,
    /// The window was closed: draw one last frame (for the screenshot), then exit.
    closing: bool,
    result: Result<(), String>,
}

impl App {
    fn new(options: AppOptions, sim: Driver) -> App {
        let camera = OrbitCamera::from_hint(&CameraHint {
            eye: glam::Vec3::new(0.0, 3.0, 8.0),
            target: glam::Vec3::ZERO,
            follow: None,
        });
        App {
            options,
            sim,
            display: None,
            window_created: false,
            #[cfg(target_arch = "wasm32")]
            pending_display: PendingDisplay::default(),
            egui_ctx: egui::Context::default(),
            egui_state: None,
            panel: Panel::default(),
            panel_open: None,
            camera,
            camera_generation: None,
            follow_shift: glam::Vec3::ZERO,
            viewport: Viewport::full((1, 1)),
            mouse: Mouse::default(),
            touches: Touches::default(),
            drag: None,
            clock: FrameClock::default(),
            started: Instant::now(),
            closing: false,
            result: Ok(()),
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, message: String) {
        #[cfg(target_arch = "wasm32")]
        crate::web::show_failure(&message);
        self.result = Err(message);
        event_loop.exit();
    }

    fn exit_due(&self) -> bool {
        self.closing
            || self
                .options
                .exit_after
                .is_some_and(|s| self.started.elapsed().as_secs_f64() >= s)
    }

    /// The ray under the cursor, if the cursor is over the 3D view.
    fn cursor_ray(&self) -> Option<Ray> {
        let p = self.mouse.position?;
        let v = self.viewport;
        let local = p - Vec2::new(v.x, v.y);
        let inside = local.x >= 0.0 && local.y >= 0.0 && local.x < v.width && local.y < v.height;
        inside.then(|| self.camera.ray(local, Vec2::new(v.width, v.height)))
    }

    /// The cursor's ray when the cursor is over the 3D view and not over the panel.
    fn scene_ray(&self) -> Option<Ray> {
        if self.egui_ctx.is_pointer_over_egui() {
            return None;
        }
        self.cursor_ray()
    }

    /// The ray the panel's spawns aim along (see `aim::VIEW_AIM`).
    fn view_aim_ray(&self) -> Ray {
        let size = Vec2::new(self.viewport.width, self.viewport.height);
        self.camera.ray(size * aim::VIEW_AIM, size)
    }

    fn pick_under_cursor(&self, snapshot: &Snapshot, poses: &[BodyPose]) -> Option<Pick> {
        picking::pick(&self.scene_ray()?, snapshot, poses)
    }

    /// Spawns a body of `kind` where the user looks: aimed along `ray`, or above the view's
    /// centre without one (a panel button, or a cursor outside the view). See `ui::aim`.
    fn spawn(&self, kind: SpawnKind, ray: Option<Ray>) {
        let Some(snapshot) = self.sim.latest() else {
            return;
        };
        let poses = current_poses(&snapshot);
        let ray = ray.unwrap_or_else(|| self.view_aim_ray());
        let position = aim::spawn_position(kind, &ray, &self.camera, &snapshot, &poses);
        self.sim.send(Command::Spawn {
            kind,
            position,
            velocity: DVec3::ZERO,
        });
    }

    fn on_mouse_button(&mut self, button: MouseButton, state: ElementState) {
        let pressed = state == ElementState::Pressed;
        if !pressed {
            self.drag = None;
            self.mouse.orbiting = false;
            self.mouse.panning = false;
            return;
        }
        if self.egui_ctx.is_pointer_over_egui() {
            return;
        }
        match button {
            MouseButton::Left => {
                // On a dynamic body the left button pushes it; elsewhere it orbits.
                self.drag = self.sim.latest().and_then(|snapshot| {
                    let poses = current_poses(&snapshot);
                    let hit = self.pick_under_cursor(&snapshot, &poses)?;
                    snapshot.bodies[hit.body]
                        .is_dynamic
                        .then(|| Drag::start(&hit, &poses[hit.body]))
                });
                self.mouse.orbiting = self.drag.is_none();
            }
            MouseButton::Right | MouseButton::Middle => self.mouse.panning = true,
            _ => {}
        }
    }

    fn on_cursor_moved(&mut self, position: Vec2) {
        if let Some(previous) = self.mouse.position {
            let delta = position - previous;
            if self.mouse.orbiting {
                self.camera.orbit(delta);
            }
            if self.mouse.panning {
                self.camera.pan(delta, self.viewport.height);
            }
        }
        self.mouse.position = Some(position);
    }

    /// A touch, as the mouse gestures it stands for (`touch`).
    fn on_touch(&mut self, touch: Touch, over_panel: bool) {
        let position = Vec2::new(touch.location.x as f32, touch.location.y as f32);
        for gesture in self
            .touches
            .on_touch(touch.id, touch.phase, position, over_panel)
        {
            match gesture {
                Gesture::Point(at) => self.on_cursor_moved(at),
                Gesture::Press => self.on_mouse_button(MouseButton::Left, ElementState::Pressed),
                Gesture::Release => self.on_mouse_button(MouseButton::Left, ElementState::Released),
                Gesture::Zoom(steps) => self.camera.zoom(steps),
                Gesture::Pan(delta) => self.camera.pan(delta, self.viewport.height),
            }
        }
    }

    fn on_key(&mut self, key: &Key) {
        if self.egui_ctx.egui_wants_keyboard_input() {
            return;
        }
        let paused = self.sim.latest().is_some_and(|s| s.settings.paused);
        match key {
            Key::Named(NamedKey::Space) => self.sim.send(Command::SetPaused(!paused)),
            Key::Character(c) if c.as_str() == "r" => self.sim.send(Command::Reset),
            Key::Named(NamedKey::Delete | NamedKey::Backspace) => self.remove_under_cursor(),
            Key::Character(c) if c.as_str() == "n" => {
                self.sim.send(Command::SetPaused(true));
                self.sim.send(Command::StepOnce);
            }
            Key::Character(c) => {
                if let Some(kind) = spawn_key(c.as_str()) {
                    self.spawn(kind, self.scene_ray());
                }
            }
            _ => {}
        }
    }

    /// Removes the body under the cursor, static or dynamic (a support pulled away).
    fn remove_under_cursor(&mut self) {
        let Some(snapshot) = self.sim.latest() else {
            return;
        };
        let poses = current_poses(&snapshot);
        if let Some(hit) = self.pick_under_cursor(&snapshot, &poses) {
            self.sim.send(Command::RemoveBody { body: hit.body });
        }
    }

    /// Moves the camera by as much as the followed body moved since the last frame, while
    /// the panel lets it: the user's orbit, pan and zoom stay as they set them.
    fn follow(&mut self, snapshot: &Snapshot, poses: &[BodyPose]) {
        let shift = snapshot.camera.follow_shift(poses);
        if self.panel.follow_camera {
            self.camera.target += shift - self.follow_shift;
        }
        self.follow_shift = shift;
    }

    /// Runs the panel, applies the drag spring and draws one frame.
    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        self.sim.pump();
        let Some(snapshot) = self.sim.latest() else {
            return;
        };
        if self.camera_generation != Some(snapshot.world_generation) {
            self.camera = OrbitCamera::from_hint(&snapshot.camera);
            self.camera_generation = Some(snapshot.world_generation);
            self.follow_shift = glam::Vec3::ZERO;
            self.drag = None;
        }
        let now = Instant::now();
        let frame_dt = self.clock.tick(now);
        let poses = snapshot.poses_at(snapshot.blend_factor(now));
        self.follow(&snapshot, &poses);

        let picked = self.pick_under_cursor(&snapshot, &poses).map(|p| p.body);
        let inspected = self.drag.map(|d| d.body).or(picked);
        let (ui_frame, requests) = self.run_panel(&snapshot, inspected);
        let screenshot_asked = requests.screenshot;
        for kind in requests.spawns {
            self.spawn(kind, None);
        }
        let mut commands = requests.commands;
        // Only bodies the mouse can push are highlighted under the cursor.
        let hovered = picked.filter(|&i| snapshot.bodies[i].is_dynamic);
        let mut extra_lines = Vec::new();
        if let (Some(drag), Some(ray)) = (self.drag, self.cursor_ray())
            && let Some(body) = snapshot.bodies.get(drag.body)
        {
            let pose = &poses[drag.body];
            commands.extend(drag.push(&ray, body, pose, frame_dt));
            extra_lines.push(drag.line(&ray, pose));
        }
        for command in commands {
            self.sim.send(command);
        }

        let frame = FrameInput {
            snapshot: &snapshot,
            poses: &poses,
            camera: &self.camera,
            overlays: self.panel.overlays,
            selected: self.drag.map(|d| d.body).or(hovered),
            extra_lines: &extra_lines,
            viewport: self.viewport,
        };
        let exiting = self.exit_due();
        let exit_capture = exiting && self.options.screenshot.is_some();
        let Some(display) = self.display.as_mut() else {
            return;
        };
        let image = match display.draw(&frame, ui_frame, exit_capture || screenshot_asked) {
            Ok(image) => image,
            // The button's failure is the panel's to tell; the run goes on.
            Err(e) if !exit_capture => {
                self.panel.set_screenshot_note(e);
                None
            }
            Err(e) => return self.fail(event_loop, e),
        };
        if let Some(image) = image
            && let Err(e) = self.save_captured(&image, screenshot_asked, exiting, &snapshot)
        {
            return self.fail(event_loop, e);
        }
        #[cfg(target_arch = "wasm32")]
        crate::web::publish_status(&snapshot);
        if exiting {
            event_loop.exit();
        }
    }

    /// Saves a captured frame where it was asked for: the Screenshot button's file (the panel
    /// tells what became of it) and, when exiting, the `--screenshot` file, whose failure is
    /// the run's.
    fn save_captured(
        &mut self,
        image: &RgbaImage,
        button: bool,
        exiting: bool,
        snapshot: &Snapshot,
    ) -> Result<(), String> {
        if button {
            let path = screenshot_file(snapshot.counters.steps);
            let note = match save_png(image, &path) {
                Ok(()) => format!("saved {}", path.display()),
                Err(e) => e,
            };
            self.panel.set_screenshot_note(note);
        }
        match self.options.screenshot.as_ref().filter(|_| exiting) {
            Some(path) => save_png(image, path),
            None => Ok(()),
        }
    }

    /// Builds the panel for this frame; also sets the 3D viewport to the space it leaves.
    /// Runs the panel, and the inspector beside the cursor for body `inspected`.
    fn run_panel(
        &mut self,
        snapshot: &Snapshot,
        inspected: Option<usize>,
    ) -> (UiFrame, PanelRequests) {
        let (Some(display), Some(state)) = (self.display.as_ref(), self.egui_state.as_mut()) else {
            return (empty_ui_frame(), PanelRequests::default());
        };
        let raw = state.take_egui_input(&display.window);
        let stats = FrameStats {
            frames_per_second: self.clock.rate,
        };
        let mut requests = PanelRequests::default();
        let mut panel_right = 0.0;
        let (panel, open) = (&mut self.panel, &mut self.panel_open);
        let tip =
            (inspected.and_then(|i| inspector::inspection(snapshot, i))).zip(self.mouse.position);
        let output = self.egui_ctx.run_ui(raw, |ui| {
            (requests, panel_right) = panel::show_or_open_button(ui, panel, open, snapshot, stats);
            if let Some((text, cursor)) = &tip {
                let points = ui.ctx().pixels_per_point();
                inspector::show(ui.ctx(), egui::pos2(cursor.x, cursor.y) / points, text);
            }
        });
        state.handle_platform_output(&display.window, output.platform_output);
        let (width, height) = display.size();
        let x = (panel_right * output.pixels_per_point)
            .min(width as f32 - 1.0)
            .max(0.0);
        self.viewport = Viewport {
            x,
            y: 0.0,
            width: (width as f32 - x).max(1.0),
            height: (height as f32).max(1.0),
        };
        let paint_jobs = self
            .egui_ctx
            .tessellate(output.shapes, output.pixels_per_point);
        let frame = UiFrame {
            paint_jobs,
            textures: output.textures_delta,
            pixels_per_point: output.pixels_per_point,
        };
        (frame, requests)
    }

    /// Takes the window's device, or fails the viewer with the reason there is none.
    fn install_display(&mut self, event_loop: &ActiveEventLoop, display: Result<Display, String>) {
        let display = match display {
            Ok(display) => display,
            Err(e) => return self.fail(event_loop, e),
        };
        let adapter = display.describe();
        eprintln!("rigid: rendering on {adapter}");
        #[cfg(target_arch = "wasm32")]
        crate::web::publish_adapter(&adapter);
        let window = &display.window;
        self.egui_state = Some(egui_winit::State::new(
            self.egui_ctx.clone(),
            egui::ViewportId::ROOT,
            window,
            Some(window.scale_factor() as f32),
            None,
            Some(display.max_texture_side()),
        ));
        self.display = Some(display);
        self.started = Instant::now();
    }

    #[cfg(target_arch = "wasm32")]
    fn install_pending_display(&mut self, event_loop: &ActiveEventLoop) {
        let pending = self.pending_display.borrow_mut().take();
        if let Some(display) = pending {
            self.install_display(event_loop, display);
        }
    }
}

/// A 1280×720 window on the desktop; in the browser, the page's canvas, sized by its CSS.
fn window_attributes() -> winit::window::WindowAttributes {
    let attributes = Window::default_attributes().with_title("rigid");
    #[cfg(not(target_arch = "wasm32"))]
    return attributes.with_inner_size(winit::dpi::LogicalSize::new(1280.0, 720.0));
    #[cfg(target_arch = "wasm32")]
    {
        use winit::platform::web::WindowAttributesExtWebSys;
        attributes
            .with_canvas(crate::web::canvas())
            .with_prevent_default(true)
            .with_focusable(true)
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        // Resumed comes again (a page shown again, an app brought back): one window is
        // enough, also while the browser is still creating its device.
        if self.window_created {
            return;
        }
        self.window_created = true;
        let window = match event_loop.create_window(window_attributes()) {
            Ok(window) => Arc::new(window),
            Err(e) => return self.fail(event_loop, format!("cannot create the window: {e}")),
        };
        #[cfg(not(target_arch = "wasm32"))]
        self.install_display(event_loop, pollster::block_on(Display::new(window)));
        #[cfg(target_arch = "wasm32")]
        {
            let pending = self.pending_display.clone();
            wasm_bindgen_futures::spawn_local(async move {
                let display = Display::new(window.clone()).await;
                *pending.borrow_mut() = Some(display);
                window.request_redraw();
            });
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        #[cfg(target_arch = "wasm32")]
        self.install_pending_display(event_loop);
        let (Some(display), Some(state)) = (self.display.as_mut(), self.egui_state.as_mut()) else {
            return;
        };
        let consumed = state.on_window_event(&display.window, &event).consumed;
        match event {
            WindowEvent::CloseRequested if self.options.screenshot.is_some() => {
                self.closing = true;
                display.window.request_redraw();
            }
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(_) | WindowEvent::ScaleFactorChanged { .. } => display.resize(),
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            WindowEvent::CursorMoved { position, .. } => {
                self.on_cursor_moved(Vec2::new(position.x as f32, position.y as f32))
            }
            WindowEvent::CursorLeft { .. } => self.mouse.position = None,
            WindowEvent::MouseInput { state, button, .. } if !consumed || !state.is_pressed() => {
                self.on_mouse_button(button, state)
            }
            WindowEvent::MouseWheel { delta, .. } if !self.egui_ctx.is_pointer_over_egui() => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                self.camera.zoom(steps);
            }
            WindowEvent::Touch(touch) => self.on_touch(touch, consumed),
            WindowEvent::KeyboardInput { event, .. } if !consumed && event.state.is_pressed() => {
                self.on_key(&event.logical_key)
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        #[cfg(target_arch = "wasm32")]
        self.install_pending_display(event_loop);
        match &self.display {
            Some(display) => display.window.request_redraw(),
            // No window to draw in (never created): the exit timer still applies.
            None if self.exit_due() => event_loop.exit(),
            None => {}
        }
    }
}

/// Keys 1 to 5 spawn the panel's kinds, in the panel's order, at the cursor.
fn spawn_key(key: &str) -> Option<SpawnKind> {
    let digit: usize = key.parse().ok()?;
    SpawnKind::ALL.get(digit.checked_sub(1)?).copied()
}

fn current_poses(snapshot: &Snapshot) -> Vec<BodyPose> {
    snapshot.poses_at(snapshot.blend_factor(Instant::now()))
}

fn empty_ui_frame() -> UiFrame {
    UiFrame {
        paint_jobs: Vec::new(),
        textures: egui::TexturesDelta::default(),
        pixels_per_point: 1.0,
    }
}

/// Frame timing: the last frame's duration and frames per second over quarter-second windows.
#[derive(Default)]
struct FrameClock {
    last: Option<Instant>,
    window_start: Option<Instant>,
    frames: u32,
    rate: f64,
}

impl FrameClock {
    /// Marks a frame at `now`; returns the seconds since the previous one.
    fn tick(&mut self, now: Instant) -> f32 {
        let dt = self.last.map_or(0.0, |last| (now - last).as_secs_f32());
        self.last = Some(now);
        let start = *self.window_start.get_or_insert(now);
        self.frames += 1;
        let window = (now - start).as_secs_f64();
        if window >= 0.25 {
            self.rate = self.frames as f64 / window;
            self.frames = 0;
            self.window_start = Some(now);
        }
        dt
    }
}
