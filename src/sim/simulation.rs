//! A world together with the run settings the viewer controls, advanced one fixed step at a
//! time. No threads here: the thread in `thread.rs` drives it, tests and headless renders call
//! it directly.

use std::collections::VecDeque;
use std::path::Path;
use std::sync::Arc;
use web_time::{Duration, Instant};

use glam::{DVec3, Vec3};

use crate::physics::collision::broad_phase::UniformGrid;
use crate::physics::{
    Aabb, BodyId, BroadPhaseKind, EnvironmentForce, Fault, JointDrives, JointId, JointKind,
    Material, Motion, RemoveError, RigidBody, World,
};
use crate::scene::{self, ScriptedMotion};
use crate::sim::command::{Command, DT_RANGE, SpawnKind};
use crate::sim::recording::{FileCommands, RecordedCommand, Recording, RecordingError};
use crate::sim::saved_world::SavedWorld;
use crate::sim::scenes::{self, CameraHint};
use crate::sim::snapshot::{
    BodyPose, BodyState, Counters, DrivenJoint, HistorySample, JointSketch, LineSegment,
    MAX_FAULTS_SHOWN, MaterialSummary, ShapeTable, SimSettings, Snapshot,
};

use crate::sim::{spawn, world_bounds};

/// The material name of bodies spawned from the panel.
const SPAWNED_MATERIAL: &str = "spawned";

/// Simulated seconds a spawned body is flagged as new (the viewer highlights it), long
/// enough to spot where it appeared.
const SPAWN_HIGHLIGHT_SECONDS: f64 = 3.0;

/// Simulated seconds between two plotted samples, and how many are kept (20 s of history).
const HISTORY_INTERVAL: f64 = 1.0 / 30.0;
const HISTORY_LEN: usize = 600;

/// Wall time over which the step rate and step cost are averaged: short enough to show
/// within a fraction of a second of starting.
const RATE_WINDOW: Duration = Duration::from_millis(250);

/// Bounds on the user-set time scale: beyond them the fixed-dt loop cannot keep up.
const TIME_SCALE_RANGE: (f64, f64) = (0.0, 10.0);

/// A world with the viewer's run settings, the log of commands applied to it, and what its
/// snapshots need (shapes, previous poses, history). Stepped by calling `step`.
pub struct Simulation {
    /// The scene the simulation started with: where a replay starts.
    first_scene: String,
    /// Fixed steps taken since the simulation started, across resets and scene changes.
    ticks: u64,
    /// Every command applied so far, with its tick, for `recording`.
    log: Vec<RecordedCommand>,
    /// Commands still to apply when replaying a recording, in tick order.
    script: VecDeque<RecordedCommand>,
    scene: String,
    camera: CameraHint,
    world: World,
    settings: SimSettings,
    world_generation: u64,
    shapes: ShapeTable,
    shape_ids: Vec<u32>,
    /// By body index, the bodies' names, shared with the snapshots.
    names: Arc<Vec<String>>,
    previous: Vec<BodyPose>,
    /// Bodies the scene hides; spawned bodies are always drawn.
    hidden: Vec<bool>,
    /// Per body index: its material's name in the scene (`SPAWNED_MATERIAL` for spawns).
    materials: Vec<String>,
    /// The scene's scripted kinematic bodies, driven before each step.
    motions: Vec<ScriptedMotion>,
    history: VecDeque<HistorySample>,
    rate: RateMeter,
    /// The last command that could not be applied, shown by the UI.
    message: Option<String>,
    /// Bounding boxes of the bodies for placing spawns, kept while nothing moves so that a
    /// burst of spawns between two steps costs O(n) each, not a box computation per body.
    spawn_boxes: Option<Vec<Aabb>>,
    /// Per body index: the world time it was spawned at (None for the scene's bodies).
    spawned_at: Vec<Option<f64>>,
    /// Dynamic bodies whose centre sinks below this height are taken out of the world (see
    /// `world_bounds::floor_of`), m.
    floor: f64,
    /// Bodies taken out for falling below `floor` since the scene was loaded.
    left_world: usize,
    /// Set when a step or command panicked: the world is kept for inspection but no longer
    /// stepped until a reset or another scene replaces it.
    failure: Option<String>,
}

impl Simulation {
    /// Builds a built-in scene by name, or a scene file by path; errors name the file, body
    /// and field. Runs at dt = 1/120 s (not the scene's `settings.dt`),
    /// time scale 1, unpaused.
    pub fn new(scene: &str) -> Result<Simulation, String> {
        let setup = scenes::build(scene)?;
        let settings = SimSettings {
            dt: 1.0 / 120.0,
            time_scale: 1.0,
            paused: false,
            gravity: DVec3::ZERO,
            integrator: setup.world.settings.integrator,
            pipeline: setup.world.settings.pipeline,
            broad_phase: setup.world.settings.broad_phase,
            substeps: setup.world.settings.solver.substeps,
            sleeping: setup.world.settings.sleep.enabled,
            restitution: Material::default().restitution,
            friction: Material::default().friction,
        };
        let mut sim = Simulation {
            first_scene: scene.to_string(),
            ticks: 0,
            log: Vec::new(),
            script: VecDeque::new(),
            scene: String::new(),
            camera: setup.camera,
            world: World::default(),
            settings,
            world_generation: 0,
            shapes: ShapeTable::default(),
            shape_ids: Vec::new(),
            names: Arc::new(Vec::new()),
            previous: Vec::new(),
            hidden: Vec::new(),
            materials: Vec::new(),
            motions: Vec::new(),
            history: VecDeque::new(),
            rate: RateMeter::default(),
            message: None,
            spawn_boxes: None,
            spawned_at: Vec::new(),
            floor: 0.0,
            left_world: 0,
            failure: None,
        };
        sim.install(scene, setup);
        Ok(sim)
    }

    /// A simulation that will apply the recording's commands at their ticks as it steps.
    /// The recording is checked first (see `Recording::check`): one holding a command that
    /// reads or writes a file is refused unless `files` allows them. `file` names the
    /// recording in errors.
    pub fn replaying(
        recording: &Recording,
        file: &str,
        files: FileCommands,
    ) -> Result<Simulation, RecordingError> {
        recording.check(file, files)?;
        let mut sim =
            Simulation::new(&recording.scene).map_err(|message| RecordingError::Scene {
                file: file.to_string(),
                message,
            })?;
        sim.script = recording.commands.iter().cloned().collect();
        Ok(sim)
    }

    /// The world being stepped.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// Fixed steps taken since the simulation started.
    pub fn ticks(&self) -> u64 {
        self.ticks
    }

    /// The run so far: the first scene and every command applied, with its tick.
    pub fn recording(&self) -> Recording {
        Recording {
            scene: self.first_scene.clone(),
            ticks: self.ticks,
            commands: self.log.clone(),
        }
    }

    /// The run settings in force.
    pub fn settings(&self) -> &SimSettings {
        &self.settings
    }

    /// The world as `Command::SaveWorld` writes it: with its scene, dt, hidden bodies and
    /// material names, everything a run resumed from it needs.
    pub fn saved_world(&self) -> SavedWorld {
        SavedWorld {
            scene: self.scene.clone(),
            dt: self.settings.dt,
            hidden: self.hidden.clone(),
            materials: self.materials.clone(),
            world: self.world.to_snapshot(),
        }
    }

    /// Applies one command; returns false for `Quit`. Commands that change the run are
    /// logged for `recording`; saving and quitting are not. A command with a value the
    /// simulation cannot run with (see `Command::check`) is refused with a message.
    pub fn apply(&mut self, command: Command) -> bool {
        if let Err(message) = command.check() {
            self.message = Some(format!("{} refused: {message}", command.name()));
            return true;
        }
        let changes_run = !matches!(
            command,
            Command::Quit | Command::SaveWorld(_) | Command::SaveRecording(_)
        );
        if changes_run {
            self.log.push(RecordedCommand {
                tick: self.ticks,
                command: command.clone(),
            });
        }
        match command {
            Command::SetPaused(paused) => self.settings.paused = paused,
            Command::StepOnce => self.advance(),
            Command::Reset => self.load(&self.scene.clone()),
            Command::LoadScene(name) => self.load(&name),
            Command::SetGravity(g) => self.set_gravity(g),
            Command::SetRestitution(e) => {
                self.set_material(e.clamp(0.0, 1.0), self.settings.friction)
            }
            Command::SetFriction(mu) => self.set_material(self.settings.restitution, mu.max(0.0)),
            Command::SetMaterial {
                name,
                restitution,
                friction,
            } => self.set_named_material(&name, restitution, friction),
            Command::SetDt(dt) => self.settings.dt = dt,
            Command::SetTimeScale(s) => {
                self.settings.time_scale = s.clamp(TIME_SCALE_RANGE.0, TIME_SCALE_RANGE.1)
            }
            Command::SetIntegrator(integrator) => {
                self.settings.integrator = integrator;
                self.world.settings.integrator = integrator;
            }
            Command::SetPipeline(pipeline) => {
                self.settings.pipeline = pipeline;
                self.apply_world_settings();
            }
            Command::SetBroadPhase(kind) => {
                self.settings.broad_phase = kind;
                self.apply_world_settings();
            }
            Command::SetSubsteps(substeps) => {
                self.settings.substeps = substeps.clamp(1, 64);
                self.apply_world_settings();
            }
            Command::SetSleeping(enabled) => {
                self.settings.sleeping = enabled;
                self.apply_world_settings();
            }
            Command::Spawn {
                kind,
                position,
                velocity,
            } => self.spawn(kind, position, velocity),
            Command::ApplyImpulse {
                body,
                impulse,
                point,
            } => self.apply_impulse(body, impulse, point),
            Command::RemoveBody { body } => {
                let removed = match self.world.id_at(body) {
                    Some(id) => self.world.remove_body(id),
                    None => Err(RemoveError::NoSuchBody(body.min(u32::MAX as usize) as u32)),
                };
                self.message = removed.err().map(|e| e.to_string());
            }
            Command::SetJointDrives { joint, drives } => {
                let set = self.world.set_joint_drives(JointId(joint), drives);
                self.message = set.err().map(|e| format!("joint {joint}: {e}"));
            }
            Command::SaveWorld(path) => self.save_world(&path),
            Command::LoadWorld(path) => self.load_world(&path),
            Command::SaveRecording(path) => {
                self.message = self.recording().save(&path).err();
            }
            Command::Quit => return false,
        }
        true
    }

    /// Stops stepping after a panic; the message stays on screen until the world is replaced.
    pub fn fail(&mut self, cause: &str) {
        let text = format!("simulation stopped: {cause}; Reset or pick a scene to go on");
        self.failure = Some(text.clone());
        self.message = Some(text);
        self.settings.paused = true;
    }

    /// Why the simulation stopped, if a step or command panicked.
    pub fn failure(&self) -> Option<&str> {
        self.failure.as_deref()
    }

    /// One fixed step of `settings.dt`, after the replayed commands that are due.
    pub fn step(&mut self) {
        while self.script.front().is_some_and(|c| c.tick <= self.ticks) {
            let due = self.script.pop_front().expect("checked above");
            self.apply(due.command);
        }
        self.advance();
    }

    fn advance(&mut self) {
        if self.failure.is_some() {
            return;
        }
        self.spawn_boxes = None;
        self.ticks += 1;
        self.previous = self.world.bodies().iter().map(pose_of).collect();
        let started = Instant::now();
        scene::drive(&self.motions, &mut self.world, self.settings.dt);
        self.world.step(self.settings.dt);
        self.rate.record(started.elapsed());
        self.remove_fallen();
        self.sample_history();
    }

    /// Takes out the bodies that fell below the scene's floor, so none falls forever.
    fn remove_fallen(&mut self) {
        for id in world_bounds::fallen(&self.world, self.floor) {
            if self.world.remove_body(id).is_ok() {
                self.left_world += 1;
            }
        }
    }

    /// Copies the state out for the renderer and UI. `step_interval` is the wall time one
    /// step stands for at the current time scale.
    pub fn snapshot(&self, published_at: Instant) -> Snapshot {
        let contacts = contact_counts(&self.world);
        let bodies = self
            .world
            .bodies()
            .iter()
            .enumerate()
            .map(|(i, body)| {
                let hidden = self.hidden.get(i).copied().unwrap_or(false);
                // An isolated body's state is not finite: there is nothing to draw (the panel
                // lists it among the faults).
                let gone = matches!(body.motion, Motion::Removed | Motion::Isolated);
                let visible = !hidden && !gone;
                let mut state = body_state(body, self.previous[i], self.shape_ids[i], visible);
                state.just_spawned = self.just_spawned(i);
                (state.touching, state.contact_points) = contacts[i];
                state
            })
            .collect();
        let step_interval = if self.settings.time_scale > 0.0 {
            self.settings.dt / self.settings.time_scale
        } else {
            0.0
        };
        Snapshot {
            scene: self.scene.clone(),
            world_generation: self.world_generation,
            camera: self.camera,
            bodies,
            names: Arc::clone(&self.names),
            shapes: self.shapes.clone(),
            broad_phase_boxes: broad_phase_boxes(&self.world),
            broad_phase_cells: broad_phase_cells(&self.world),
            lines: contact_lines(&self.world),
            joints: joint_sketches(&self.world),
            counters: self.counters(),
            materials: self.material_summaries(),
            driven_joints: driven_joints(&self.world),
            history: self.history.iter().copied().collect(),
            settings: self.settings,
            message: self.message.clone(),
            faults: newest_faults(self.world.faults()),
            fault_count: self.world.faults().len(),
            left_world: self.left_world,
            published_at,
            step_interval,
        }
    }

    /// Whether body `index` was spawned less than `SPAWN_HIGHLIGHT_SECONDS` ago.
    fn just_spawned(&self, index: usize) -> bool {
        let now = self.world.time();
        self.spawned_at
            .get(index)
            .copied()
            .flatten()
            .is_some_and(|t| now - t < SPAWN_HIGHLIGHT_SECONDS)
    }

    /// Run settings that live in the world's own settings.
    fn apply_world_settings(&mut self) {
        let world = &mut self.world.settings;
        world.integrator = self.settings.integrator;
        world.pipeline = self.settings.pipeline;
        world.broad_phase = self.settings.broad_phase;
        world.solver.substeps = self.settings.substeps;
        world.classic.substeps = self.settings.substeps;
        world.sleep.enabled = self.settings.sleeping;
    }

    fn counters(&self) -> Counters {
        let totals = self.world.totals();
        Counters {
            sim_time: self.world.time(),
            steps: self.world.step_count(),
            step_rate: self.rate.steps_per_second,
            step_wall_time: self.rate.mean_step,
            bodies: self.world.bodies().len(),
            awake: self.world.awake_count(),
            pairs: self.world.pair_count(),
            contacts: self.world.contacts().iter().map(|m| m.contacts.len()).sum(),
            max_penetration: self.world.max_penetration(),
            stages: self.world.stage_times(),
            kinetic_energy: totals.kinetic_energy,
            potential_energy: totals.potential_energy,
            linear_momentum: totals.linear_momentum.length(),
            angular_momentum: totals.angular_momentum.length(),
        }
    }

    /// Replaces the world by a scene. Run settings (dt, time scale, pause, integrator) carry
    /// over; world settings (gravity, materials) come from the scene.
    fn load(&mut self, name: &str) {
        match scenes::build(name) {
            Ok(setup) => self.install(name, setup),
            Err(e) => self.message = Some(e),
        }
    }

    fn save_world(&mut self, path: &Path) {
        self.message = self.saved_world().save(path).err();
    }

    /// Replaces the world by a saved one; the camera comes from its scene when that loads.
    fn load_world(&mut self, path: &Path) {
        let loaded = SavedWorld::load(path).and_then(|saved| {
            let file = path.display().to_string();
            let world = World::from_snapshot(saved.world, &file).map_err(|e| e.to_string())?;
            // The scene also gives the scripts of its kinematic bodies, which a world does
            // not hold; they go on from the saved world's time.
            let (camera, motions) = scenes::build(&saved.scene)
                .map_or((self.camera, Vec::new()), |setup| {
                    (setup.camera, setup.motions)
                });
            let dt = saved.dt.clamp(DT_RANGE.0, DT_RANGE.1);
            Ok((
                saved.scene,
                dt,
                scenes::SceneSetup {
                    world,
                    camera,
                    hidden: saved.hidden,
                    materials: saved.materials,
                    motions,
                },
            ))
        });
        match loaded {
            Ok((scene, dt, setup)) => {
                // The saved world runs on with its own settings, not the viewer's.
                let saved = setup.world.settings;
                self.settings.dt = dt;
                self.settings.integrator = saved.integrator;
                self.settings.pipeline = saved.pipeline;
                self.settings.broad_phase = saved.broad_phase;
                self.settings.substeps = saved.solver.substeps;
                self.settings.sleeping = saved.sleep.enabled;
                self.install(&scene, setup);
            }
            Err(e) => self.message = Some(e),
        }
    }

    fn install(&mut self, name: &str, setup: scenes::SceneSetup) {
        self.scene = name.to_string();
        self.camera = setup.camera;
        self.world = setup.world;
        // The panel shows where each step's time goes.
        self.world.set_stage_timing(true);
        self.spawn_boxes = None;
        self.spawned_at.clear();
        self.floor = world_bounds::floor_of(&self.world);
        self.left_world = 0;
        self.hidden = setup.hidden;
        self.materials = setup.materials;
        self.motions = setup.motions;
        self.apply_world_settings();
        self.settings.gravity = gravity_of(&self.world);
        if let Some(body) = self.world.bodies().iter().find(|b| b.is_dynamic()) {
            self.settings.restitution = body.material.restitution;
            self.settings.friction = body.material.friction;
        }
        self.world_generation += 1;
        self.shapes = ShapeTable {
            generation: self.shapes.generation + 1,
            shapes: Arc::new(Vec::new()),
        };
        self.shape_ids.clear();
        self.names = Arc::new(Vec::new());
        self.previous.clear();
        for i in 0..self.world.bodies().len() {
            self.track_body(i);
        }
        self.history.clear();
        self.message = None;
        // Recovering from a failure: run again, as before the panic paused the clock.
        if self.failure.take().is_some() {
            self.settings.paused = false;
        }
    }

    /// Registers body `index` in the shape table and gives it a previous pose.
    fn track_body(&mut self, index: usize) {
        let body = &self.world.bodies()[index];
        let id = match self.shapes.shapes.iter().position(|s| *s == body.shape) {
            Some(id) => id,
            None => {
                Arc::make_mut(&mut self.shapes.shapes).push(body.shape.clone());
                self.shapes.generation += 1;
                self.shapes.shapes.len() - 1
            }
        };
        let pose = pose_of(body);
        let names = Arc::make_mut(&mut self.names);
        names.resize(self.world.bodies().len(), String::new());
        names[index].clone_from(&body.name);
        if index < self.shape_ids.len() {
            // A spawn in a removed body's slot: a spawn is always drawn, and of its material.
            self.shape_ids[index] = id as u32;
            self.previous[index] = pose;
            self.materials[index] = SPAWNED_MATERIAL.to_string();
            if let Some(hidden) = self.hidden.get_mut(index) {
                *hidden = false;
            }
            return;
        }
        self.shape_ids.push(id as u32);
        self.previous.push(pose);
        // Scene bodies arrive named by `install`; bodies added later are spawns.
        if self.materials.len() <= index {
            self.materials
                .resize(index + 1, SPAWNED_MATERIAL.to_string());
        }
    }

    fn set_gravity(&mut self, acceleration: DVec3) {
        self.world
            .forces
            .retain(|f| !matches!(f, EnvironmentForce::Gravity { .. }));
        self.world
            .forces
            .push(EnvironmentForce::Gravity { acceleration });
        self.settings.gravity = acceleration;
    }

    fn set_material(&mut self, restitution: f64, friction: f64) {
        self.settings.restitution = restitution;
        self.settings.friction = friction;
        write_material(&mut self.world, |_| true, restitution, friction);
    }

    /// Edits the bodies of one material; values that are not finite are ignored.
    fn set_named_material(&mut self, name: &str, restitution: f64, friction: f64) {
        if !(restitution.is_finite() && friction.is_finite()) {
            return;
        }
        let materials = &self.materials;
        let chosen = |index: usize| materials.get(index).is_some_and(|m| m == name);
        let (restitution, friction) = (restitution.clamp(0.0, 1.0), friction.max(0.0));
        write_material(&mut self.world, chosen, restitution, friction);
    }

    /// The materials by name with their bodies' current values (those of the first body).
    fn material_summaries(&self) -> Vec<MaterialSummary> {
        let mut summaries: Vec<MaterialSummary> = Vec::new();
        for (name, body) in self.materials.iter().zip(self.world.bodies()) {
            match summaries.iter_mut().find(|s| s.name == *name) {
                Some(summary) => summary.bodies += 1,
                None => summaries.push(MaterialSummary {
                    name: name.clone(),
                    restitution: body.material.restitution,
                    friction: body.material.friction,
                    bodies: 1,
                }),
            }
        }
        summaries
    }

    fn spawn(&mut self, kind: SpawnKind, position: DVec3, velocity: DVec3) {
        let material = Material {
            restitution: self.settings.restitution,
            friction: self.settings.friction,
            ..Material::default()
        };
        let desc = spawn::body(kind, self.world.bodies().len() as u64, material);
        let boxes = self
            .spawn_boxes
            .get_or_insert_with(|| spawn::body_boxes(&self.world));
        let spot = spawn::free_spot(boxes, &desc, position);
        let placed = spawn::box_at(&desc, spot);
        match self.world.add_body(desc.at(spot).with_velocity(velocity)) {
            Ok(id) => {
                boxes.push(placed);
                self.track_body(id.index());
                let index = id.index();
                if self.spawned_at.len() <= index {
                    self.spawned_at.resize(index + 1, None);
                }
                self.spawned_at[index] = Some(self.world.time());
            }
            Err(e) => self.message = Some(format!("spawn refused: {e}")),
        }
    }

    fn apply_impulse(&mut self, index: usize, impulse: DVec3, point: DVec3) {
        if index >= self.world.bodies().len() || !impulse.is_finite() || !point.is_finite() {
            return;
        }
        let Some(id) = self.world.id_at(index) else {
            return;
        };
        let body = self.world.body_mut(id);
        if body.is_dynamic() {
            body.apply_impulse_at(impulse, point);
        }
    }

    fn sample_history(&mut self) {
        let time = self.world.time();
        if let Some(last) = self.history.back()
            && time - last.time < HISTORY_INTERVAL
        {
            return;
        }
        let c = self.counters();
        self.history.push_back(HistorySample {
            time,
            kinetic_energy: c.kinetic_energy,
            potential_energy: c.potential_energy,
            linear_momentum: c.linear_momentum,
            angular_momentum: c.angular_momentum,
            max_penetration: c.max_penetration,
        });
        if self.history.len() > HISTORY_LEN {
            self.history.pop_front();
        }
    }
}

/// The first gravity field of the world, or zero.
fn gravity_of(world: &World) -> DVec3 {
    world
        .forces
        .iter()
        .find_map(|f| match f {
            EnvironmentForce::Gravity { acceleration } => Some(*acceleration),
            _ => None,
        })
        .unwrap_or(DVec3::ZERO)
}

fn pose_of(body: &RigidBody) -> BodyPose {
    BodyPose {
        position: body.shape_origin().as_vec3(),
        rotation: body.rotation().as_quat(),
    }
}

/// Gives the bodies `chosen` picks (by index) this restitution and friction.
fn write_material(
    world: &mut World,
    chosen: impl Fn(usize) -> bool,
    restitution: f64,
    friction: f64,
) {
    for id in world.body_ids() {
        if chosen(id.index()) {
            let material = &mut world.body_mut(id).material;
            material.restitution = restitution;
            material.friction = friction;
        }
    }
}

fn newest_faults(faults: &[Fault]) -> Vec<Fault> {
    faults[faults.len().saturating_sub(MAX_FAULTS_SHOWN)..].to_vec()
}

/// By body index: the bodies each touched in the last step's manifolds, and the contact
/// points of those manifolds.
fn contact_counts(world: &World) -> Vec<(u32, u32)> {
    let mut counts = vec![(0, 0); world.bodies().len()];
    for manifold in world.contacts() {
        let points = manifold.contacts.len() as u32;
        for body in [manifold.body_a, manifold.body_b] {
            if let Some(count) = counts.get_mut(body.index()) {
                count.0 += 1;
                count.1 += points;
            }
        }
    }
    counts
}

fn body_state(body: &RigidBody, previous: BodyPose, shape_id: u32, visible: bool) -> BodyState {
    let min = DVec3::new(
        body.world_support(-DVec3::X).x,
        body.world_support(-DVec3::Y).y,
        body.world_support(-DVec3::Z).z,
    );
    let max = DVec3::new(
        body.world_support(DVec3::X).x,
        body.world_support(DVec3::Y).y,
        body.world_support(DVec3::Z).z,
    );
    BodyState {
        pose: pose_of(body),
        previous,
        shape_id,
        aabb: (min.as_vec3(), max.as_vec3()),
        bounding_radius: body.shape.bounding_radius() as f32,
        center_of_mass: body.position.as_vec3(),
        mass: if body.is_dynamic() {
            body.mass() as f32
        } else {
            0.0
        },
        is_dynamic: body.is_dynamic(),
        is_kinematic: body.is_kinematic(),
        sleeping: body.sleeping,
        visible,
        just_spawned: false,
        velocity: body.velocity().as_vec3(),
        angular_velocity: body.angular_velocity().as_vec3(),
        touching: 0,
        contact_points: 0,
    }
}

/// Step rate and mean step cost over windows of `RATE_WINDOW` wall-clock time.
#[derive(Default)]
struct RateMeter {
    window_start: Option<Instant>,
    steps: u32,
    busy: Duration,
    steps_per_second: f64,
    mean_step: f64,
}

impl RateMeter {
    fn record(&mut self, step_time: Duration) {
        let now = Instant::now();
        let start = *self.window_start.get_or_insert(now);
        self.steps += 1;
        self.busy += step_time;
        let window = now - start;
        if window >= RATE_WINDOW {
            self.steps_per_second = self.steps as f64 / window.as_secs_f64();
            self.mean_step = self.busy.as_secs_f64() / self.steps as f64;
            *self = RateMeter {
                window_start: Some(now),
                steps_per_second: self.steps_per_second,
                mean_step: self.mean_step,
                ..RateMeter::default()
            };
        }
    }
}

/// The broad-phase boxes of the awake bodies.
fn broad_phase_boxes(world: &World) -> Vec<(Vec3, Vec3)> {
    world
        .broad_phase_proxies()
        .iter()
        .filter(|proxy| proxy.active)
        .map(|proxy| (proxy.aabb.min.as_vec3(), proxy.aabb.max.as_vec3()))
        .collect()
}

fn broad_phase_cells(world: &World) -> Vec<(Vec3, Vec3)> {
    let BroadPhaseKind::UniformGrid { cell_size } = world.settings.broad_phase else {
        return Vec::new();
    };
    let active = world.broad_phase_proxies().iter().filter(|p| p.active);
    UniformGrid::new(cell_size)
        .occupied_cells(active.map(|p| &p.aabb))
        .into_iter()
        .map(|cell| (cell.min.as_vec3(), cell.max.as_vec3()))
        .collect()
}

/// The joints with a motor, servo or spring, for the panel to change live.
fn driven_joints(world: &World) -> Vec<DrivenJoint> {
    let bodies = world.bodies();
    let driven = (world.joints()).filter(|(_, joint)| joint.drives() != JointDrives::default());
    driven
        .map(|(id, joint)| {
            let name = |id: BodyId| bodies[id.index()].name.as_str();
            let kind = format!("{:?}", joint.kind).to_lowercase();
            let (a, b) = (name(joint.body_a), name(joint.body_b));
            DrivenJoint {
                joint: id.0,
                label: format!("{kind} {a} – {b}"),
                drives: joint.drives(),
            }
        })
        .collect()
}

/// Each joint where the viewer draws it (see `JointSketch`).
fn joint_sketches(world: &World) -> Vec<JointSketch> {
    let bodies = world.bodies();
    world
        .joints()
        .map(|(_, joint)| {
            let [a, b] = [joint.body_a.index(), joint.body_b.index()];
            // From the centre of mass to the drawn origin, in body axes: + local_center.
            let from_origin =
                |index: usize, anchor: DVec3| (anchor + bodies[index].local_center).as_vec3();
            let turns = !matches!(
                joint.kind,
                JointKind::Ball | JointKind::Fixed | JointKind::Distance
            );
            JointSketch {
                bodies: [a, b],
                anchors: [
                    from_origin(a, joint.local_anchor_a),
                    from_origin(b, joint.local_anchor_b),
                ],
                axis: turns.then(|| joint.local_axis_a.as_vec3()),
                moving: [bodies[a].motion.moves(), bodies[b].motion.moves()],
            }
        })
        .collect()
}

/// Length of a drawn contact normal, m.
const NORMAL_LENGTH: f32 = 0.12;
/// Only contacts this close are drawn, m: speculative ones further apart are not touching.
const DRAWN_SEPARATION: f64 = 1e-3;
/// Half size of the cross drawn at a contact point, m.
const POINT_SIZE: f32 = 0.03;
const CONTACT_COLOR: [f32; 3] = [1.0, 0.85, 0.1];
const NORMAL_COLOR: [f32; 3] = [1.0, 0.35, 0.1];

/// A small cross at each touching contact point and its normal (from A towards B).
fn contact_lines(world: &World) -> Vec<LineSegment> {
    let mut lines = Vec::new();
    let contacts = world.contacts().iter().flat_map(|m| &m.contacts);
    for contact in contacts.filter(|c| c.separation <= DRAWN_SEPARATION) {
        let point = contact.position.as_vec3();
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            lines.push(LineSegment {
                from: point - axis * POINT_SIZE,
                to: point + axis * POINT_SIZE,
                color: CONTACT_COLOR,
            });
        }
        lines.push(LineSegment {
            from: point,
            to: point + contact.normal.as_vec3() * NORMAL_LENGTH,
            color: NORMAL_COLOR,
        });
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::BodyId;
    use crate::physics::Shape;

    #[test]
    fn absurd_pushes_never_spread_to_other_bodies() {
        let mut sim = Simulation::new("stack").unwrap();
        let top = sim.world().bodies().len() - 1;
        let point = sim.world().bodies()[top].position;
        for impulse in [1e300, f64::MAX, f64::INFINITY, f64::NAN] {
            sim.apply(Command::ApplyImpulse {
                body: top,
                impulse: DVec3::new(impulse, impulse, 0.0),
                point,
            });
            for _ in 0..5 {
                sim.step();
            }
        }
        let world = sim.world();
        // The pushed body flew off or was isolated; every other body is finite and in place.
        for (i, body) in world.bodies().iter().enumerate().filter(|(i, _)| *i != top) {
            assert!(body.is_finite(), "body {i}");
            assert!(
                body.position.y.abs() < 20.0,
                "body {i} at {}",
                body.position
            );
        }
        let pushed = &world.bodies()[top];
        assert!(pushed.is_finite() || world.faults().iter().any(|f| f.body.index() == top));
    }

    #[test]
    fn a_body_gone_non_finite_is_reported_and_not_drawn() {
        let mut sim = Simulation::new("stack").unwrap();
        let top = sim.world().bodies().len() - 1;
        // The commands refuse non-finite pushes; a force set on the world goes through.
        sim.world
            .body_mut(BodyId(top as u32))
            .apply_force(DVec3::new(f64::NAN, 0.0, 0.0));
        sim.step();
        let shown = sim.snapshot(Instant::now());
        assert_eq!(shown.fault_count, 1);
        assert_eq!(shown.faults.len(), 1);
        assert_eq!(shown.faults[0].body.index(), top);
        assert_eq!(shown.faults[0].step, 0, "isolated in the step it went bad");
        assert!(!shown.bodies[top].visible);
        let others_visible = shown.bodies[..top].iter().filter(|b| b.visible).count();
        let others_visible_before = Simulation::new("stack")
            .unwrap()
            .snapshot(Instant::now())
            .bodies[..top]
            .iter()
            .filter(|b| b.visible)
            .count();
        assert_eq!(others_visible, others_visible_before);
    }

    #[test]
    fn the_snapshot_carries_only_the_newest_faults() {
        let mut sim = Simulation::new("pachinko").unwrap();
        let balls: Vec<usize> = (0..sim.world().bodies().len())
            .filter(|&i| sim.world().bodies()[i].is_dynamic())
            .take(MAX_FAULTS_SHOWN + 3)
            .collect();
        for &ball in &balls {
            sim.world
                .body_mut(BodyId(ball as u32))
                .apply_force(DVec3::splat(f64::INFINITY));
        }
        sim.step();
        let shown = sim.snapshot(Instant::now());
        assert_eq!(shown.fault_count, balls.len());
        let listed: Vec<usize> = shown.faults.iter().map(|f| f.body.index()).collect();
        assert_eq!(listed, balls[3..].to_vec());
    }

    #[test]
    fn a_material_is_edited_on_its_own_bodies_only() {
        let mut sim = Simulation::new("falling_box").unwrap();
        let before = sim.snapshot(Instant::now()).materials;
        let names: Vec<(&str, usize)> =
            before.iter().map(|m| (m.name.as_str(), m.bodies)).collect();
        assert_eq!(names, [("concrete", 2), ("wood", 1)]);
        sim.apply(Command::SetMaterial {
            name: "concrete".into(),
            restitution: 0.9,
            friction: 1.2,
        });
        let bodies = sim.world().bodies();
        let concrete = [&bodies[0], &bodies[1]];
        assert!(concrete.iter().all(|b| b.material.restitution == 0.9));
        assert!(concrete.iter().all(|b| b.material.friction == 1.2));
        assert_eq!(bodies[2].material, sim_scene_material("falling_box", 2));
        // Out-of-range values are clamped, non-finite ones ignored.
        sim.apply(Command::SetMaterial {
            name: "wood".into(),
            restitution: 3.0,
            friction: -1.0,
        });
        sim.apply(Command::SetMaterial {
            name: "wood".into(),
            restitution: f64::NAN,
            friction: 0.1,
        });
        let wood = &sim.world().bodies()[2].material;
        assert_eq!((wood.restitution, wood.friction), (1.0, 0.0));
        let shown = sim.snapshot(Instant::now()).materials;
        assert_eq!((shown[0].restitution, shown[0].friction), (0.9, 1.2));
        // Spawned bodies make a material of their own.
        sim.apply(Command::Spawn {
            kind: SpawnKind::Sphere,
            position: DVec3::new(0.0, 6.0, 0.0),
            velocity: DVec3::ZERO,
        });
        let shown = sim.snapshot(Instant::now()).materials;
        assert_eq!((shown[2].name.as_str(), shown[2].bodies), ("spawned", 1));
    }

    /// The car's four wheel motors are listed for the panel; a new speed takes over (the
    /// car then rolls at ω r with the wheels' 0.3 m radius), and a refused one leaves the
    /// motor as it was and says why.
    #[test]
    fn the_panel_changes_the_car_motors_live() {
        let mut sim = Simulation::new("car").unwrap();
        let driven = sim.snapshot(Instant::now()).driven_joints;
        let labels: Vec<&str> = driven.iter().map(|d| d.label.as_str()).collect();
        assert_eq!(labels[0], "hinge chassis – wheel_0");
        assert_eq!(labels.len(), 4);
        for driven in &driven {
            let mut drives = driven.drives;
            drives.motor.as_mut().unwrap().speed = -5.0;
            let joint = driven.joint;
            sim.apply(Command::SetJointDrives { joint, drives });
        }
        while sim.world().time() < 2.0 {
            sim.step();
        }
        let chassis = sim.world().bodies().iter().find(|b| b.name == "chassis");
        let speed = chassis.unwrap().velocity().x;
        assert!(
            (speed - 1.5).abs() < 0.015,
            "{speed} m/s against 5 rad/s × 0.3 m"
        );
        let mut drives = driven[0].drives;
        drives.motor.as_mut().unwrap().speed = f64::NAN;
        sim.apply(Command::SetJointDrives { joint: 0, drives });
        let shown = sim.snapshot(Instant::now());
        assert_eq!(shown.driven_joints[0].drives.motor.unwrap().speed, -5.0);
        let message = shown.message.unwrap();
        assert_eq!(message, "joint 0: motor.speed must be finite");
    }

    fn sim_scene_material(scene: &str, body: usize) -> Material {
        Simulation::new(scene).unwrap().world().bodies()[body].material
    }

    #[test]
    fn spawned_hulls_are_valid_convex_hulls() {
        let mut sim = Simulation::new("falling_box").unwrap();
        for i in 0..5 {
            sim.apply(Command::Spawn {
                kind: SpawnKind::Hull,
                position: DVec3::new(i as f64, 3.0, 0.0),
                velocity: DVec3::ZERO,
            });
        }
        let hulls: Vec<_> = sim
            .world()
            .bodies()
            .iter()
            .filter_map(|b| match &b.shape {
                Shape::ConvexHull(hull) => Some(hull.clone()),
                _ => None,
            })
            .collect();
        assert_eq!(hulls.len(), 5);
        for hull in &hulls {
            assert!(hull.validate().is_ok());
            // 14 points on a sphere shell: most of them are hull vertices.
            assert!(hull.vertices.len() >= 8, "{}", hull.vertices.len());
        }
        assert_ne!(
            hulls[0].vertices, hulls[1].vertices,
            "each spawn gets its own points"
        );
    }

    fn spawn_ball(sim: &mut Simulation, position: DVec3) {
        sim.apply(Command::Spawn {
            kind: SpawnKind::Sphere,
            position,
            velocity: DVec3::ZERO,
        });
    }

    #[test]
    fn bodies_below_the_floor_leave_the_world_and_are_counted() {
        // falling_box: the platform's bottom is y = -0.5 and its side 3 m, so the floor lies
        // the 20 m margin below it, far below anything the camera shows.
        let mut sim = Simulation::new("falling_box").unwrap();
        assert_eq!(sim.floor, -20.5);
        let floor = sim.floor;
        spawn_ball(&mut sim, DVec3::new(10.0, floor - 1.0, 0.0));
        spawn_ball(&mut sim, DVec3::new(10.0, floor + 1.0, 0.0));
        let (deep, shallow) = (3, 4);
        sim.step();
        let bodies = sim.world().bodies();
        assert_eq!(bodies[deep].motion, Motion::Removed);
        assert!(bodies[shallow].is_dynamic());
        let snapshot = sim.snapshot(Instant::now());
        assert_eq!(snapshot.left_world, 1);
        assert!(!snapshot.bodies[deep].visible);
        // The falling box of the scene and the ball above the floor stay until they sink
        // past it; then the ball goes too.
        while sim.world().bodies()[shallow].is_dynamic() {
            assert!(sim.world().bodies()[2].is_dynamic());
            sim.step();
        }
        assert!(sim.world().bodies()[shallow].position.y < sim.floor + 0.1);
        assert_eq!(sim.snapshot(Instant::now()).left_world, 2);
        // A reset starts the count again.
        sim.apply(Command::Reset);
        assert_eq!(sim.snapshot(Instant::now()).left_world, 0);
    }

    #[test]
    fn a_spawned_body_is_flagged_new_for_a_few_seconds() {
        let mut sim = Simulation::new("falling_box").unwrap();
        spawn_ball(&mut sim, DVec3::new(0.0, 3.0, 2.0));
        let new = |sim: &Simulation| sim.snapshot(Instant::now()).bodies[3].just_spawned;
        assert!(new(&sim));
        assert!(!sim.snapshot(Instant::now()).bodies[2].just_spawned);
        // One step more than the highlight lasts: summed steps may fall just short of it.
        let steps = (SPAWN_HIGHLIGHT_SECONDS / sim.settings().dt).ceil() as usize + 1;
        for _ in 0..steps {
            sim.step();
        }
        assert!(!new(&sim));
    }

    #[test]
    fn step_once_advances_one_dt() {
        let mut sim = Simulation::new("falling_box").unwrap();
        sim.apply(Command::SetDt(0.01));
        sim.apply(Command::StepOnce);
        sim.apply(Command::StepOnce);
        assert_eq!(sim.world().step_count(), 2);
        assert!((sim.world().time() - 0.02).abs() < 1e-12);
    }

    #[test]
    fn reset_restores_the_scene_and_keeps_run_settings() {
        let mut sim = Simulation::new("falling_box").unwrap();
        let start = sim.snapshot(Instant::now()).bodies[2].pose;
        sim.apply(Command::SetDt(0.005));
        for _ in 0..50 {
            sim.step();
        }
        sim.apply(Command::Spawn {
            kind: SpawnKind::Sphere,
            position: DVec3::Y * 3.0,
            velocity: DVec3::ZERO,
        });
        let generation = sim.snapshot(Instant::now()).world_generation;
        sim.apply(Command::Reset);
        let snap = sim.snapshot(Instant::now());
        assert_eq!(snap.bodies.len(), 3);
        assert_eq!(snap.bodies[2].pose, start);
        assert_eq!(snap.counters.steps, 0);
        assert_eq!(snap.settings.dt, 0.005);
        assert!(snap.world_generation > generation);
    }

    #[test]
    fn spawn_registers_new_shapes_once() {
        let mut sim = Simulation::new("falling_box").unwrap();
        let before = sim.snapshot(Instant::now()).shapes;
        for _ in 0..2 {
            sim.apply(Command::Spawn {
                kind: SpawnKind::Capsule,
                position: DVec3::new(0.0, 5.0, 0.0),
                velocity: DVec3::X,
            });
        }
        let after = sim.snapshot(Instant::now());
        assert_eq!(after.shapes.shapes.len(), before.shapes.len() + 1);
        assert!(after.shapes.generation > before.generation);
        assert_eq!(after.bodies[3].shape_id, after.bodies[4].shape_id);
        assert_eq!(after.bodies[4].velocity, glam::Vec3::X);
    }

    /// Gravity past `MAX_GRAVITY` is refused with a message, as a scene refuses it, and the
    /// world keeps the gravity it had (1e12 m/s² made bodies tunnel, 1e308 overflowed).
    #[test]
    fn gravity_beyond_its_limit_is_refused() {
        let mut sim = Simulation::new("falling_box").unwrap();
        let before = gravity_of(sim.world());
        for g in [1e12, 1e308] {
            sim.apply(Command::SetGravity(DVec3::new(0.0, -g, 0.0)));
            let message = sim.message.clone().unwrap_or_default();
            assert!(
                message.starts_with("SetGravity refused: gravity"),
                "{message}"
            );
            assert_eq!(gravity_of(sim.world()), before);
        }
    }

    #[test]
    fn gravity_and_materials_reach_the_world() {
        let mut sim = Simulation::new("falling_box").unwrap();
        sim.apply(Command::SetGravity(DVec3::new(0.0, -1.62, 0.0)));
        sim.apply(Command::SetRestitution(0.9));
        sim.apply(Command::SetFriction(0.1));
        assert_eq!(gravity_of(sim.world()), DVec3::new(0.0, -1.62, 0.0));
        assert!(
            sim.world()
                .bodies()
                .iter()
                .all(|b| b.material.restitution == 0.9)
        );
        assert!(
            sim.world()
                .bodies()
                .iter()
                .all(|b| b.material.friction == 0.1)
        );
        sim.apply(Command::SetDt(0.01));
        sim.apply(Command::StepOnce);
        let v = sim.world().bodies()[2].velocity();
        assert!((v.y + 0.0162).abs() < 1e-9, "{v}");
    }

    #[test]
    fn impulse_moves_only_dynamic_bodies() {
        let mut sim = Simulation::new("falling_box").unwrap();
        let box_centre = sim.world().bodies()[2].position;
        sim.apply(Command::ApplyImpulse {
            body: 2,
            impulse: DVec3::X * 1000.0,
            point: box_centre,
        });
        sim.apply(Command::ApplyImpulse {
            body: 0,
            impulse: DVec3::X,
            point: DVec3::ZERO,
        });
        sim.apply(Command::ApplyImpulse {
            body: 99,
            impulse: DVec3::X,
            point: DVec3::ZERO,
        });
        let expected = 1000.0 / sim.world().bodies()[2].mass();
        assert!((sim.world().bodies()[2].velocity().x - expected).abs() < 1e-9);
        assert_eq!(sim.world().bodies()[0].velocity(), DVec3::ZERO);
    }

    #[test]
    fn unknown_scene_keeps_the_world_and_reports() {
        let mut sim = Simulation::new("falling_box").unwrap();
        sim.apply(Command::LoadScene("nope".into()));
        let snap = sim.snapshot(Instant::now());
        assert_eq!(snap.scene, "falling_box");
        assert!(snap.message.unwrap().contains("nope"));
    }
}
