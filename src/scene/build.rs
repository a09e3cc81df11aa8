//! Scene → engine: body descriptions and the `World`.

use glam::DVec3;

use crate::physics::{
    AddBodyError, BodyDesc, BodyError, BodyId, EnvironmentForce, MAX_BODIES, Material, Motion,
    RigidBody, World, WorldSettings,
};
use crate::scene::error::{FieldError, SceneError, body_label};
use crate::scene::expand;
use crate::scene::file::{BodySpec, ForceSpec, KinematicSpec, Scene};
use crate::scene::joints::joint_field;
use crate::scene::material_ref::MaterialRef;
use crate::scene::script::{self, ScriptedMotion};
use crate::scene::shapes::{build_rotation, build_shape};
use crate::scene::validate::{self, check_material, positive, vector};

impl Scene {
    /// A world holding every body of the scene, its forces and its integrator. The time step is
    /// not part of a world: pass `self.settings.dt` to `World::step`.
    /// Kinematic bodies start at their scripts' poses at t = 0 and with their velocities;
    /// `scripted_motions` gives what must drive them at each step.
    pub fn build_world(&self) -> Result<World, SceneError> {
        let descs = self.body_descs()?;
        let joints = self.joint_descs(&descs)?;
        let mut world = World::new(WorldSettings {
            integrator: self.settings.integrator,
            ..WorldSettings::default()
        });
        world.forces = self.forces.iter().map(to_force).collect();
        for desc in descs {
            world
                .add_body(desc)
                .map_err(|error| self.add_error(error))?;
        }
        for joint in joints {
            // `joint_descs` made the world's own checks; this names the joint should they
            // ever differ.
            world
                .add_joint(joint.desc)
                .map_err(|e| joint_field(e).in_joint(&self.origin, &joint.label))?;
        }
        Ok(world)
    }

    /// `body_descs` checked the count against the same limit, so this is never expected.
    fn add_error(&self, error: AddBodyError) -> SceneError {
        match error {
            AddBodyError::Invalid(error) => body_error(&self.origin, error),
            AddBodyError::TooManyBodies => SceneError::TooManyBodies {
                file: self.origin.clone(),
                count: self.body_count(),
                limit: MAX_BODIES,
            },
        }
    }

    /// Every body the scene makes, generators expanded, each checked. This is the whole
    /// validation of the bodies: `parse` runs it too.
    pub fn body_descs(&self) -> Result<Vec<BodyDesc>, SceneError> {
        Ok(self.bodies_and_scripts()?.0)
    }

    /// The scripts of the scene's kinematic bodies, for the world `build_world` makes: call
    /// `scene::drive` with them before each step.
    pub fn scripted_motions(&self) -> Result<Vec<ScriptedMotion>, SceneError> {
        Ok(self.bodies_and_scripts()?.1)
    }

    fn bodies_and_scripts(&self) -> Result<(Vec<BodyDesc>, Vec<ScriptedMotion>), SceneError> {
        validate::check_scene(self)?;
        let mut descs = Vec::new();
        let mut scripts = Vec::new();
        for (index, spec) in self.bodies.iter().enumerate() {
            let label = body_label(&spec.name, index);
            let template = self
                .template(spec)
                .map_err(|e| e.in_body(&self.origin, &label))?;
            check_engine_body(&template).map_err(|e| e.in_body(&self.origin, &label))?;
            let first = descs.len();
            descs.extend(instances(spec, &template).map_err(|e| e.in_body(&self.origin, &label))?);
            if let Some(motion) = spec.kinematic {
                scripts.extend(start_scripts(motion, first, &mut descs[first..]));
            }
        }
        Ok((descs, scripts))
    }

    /// The index (in `build_world` order) of the body the camera follows, if any
    /// (`Camera::follow`).
    pub fn followed_body(&self) -> Result<Option<usize>, SceneError> {
        self.body_to_follow(&self.body_descs()?)
    }

    /// For each body the scene makes (in `build_world` order), whether it is hidden.
    pub fn hidden_bodies(&self) -> Vec<bool> {
        self.per_body(|body| body.hidden)
    }

    /// For each body the scene makes (in `build_world` order), the name of its material: a key
    /// of `materials`, or `own: BODY` for a material written inline in the body.
    pub fn material_names(&self) -> Vec<String> {
        self.per_body(|body| match &body.material {
            MaterialRef::Named(name) => name.clone(),
            MaterialRef::Inline(_) => format!("own: {}", body.name),
        })
    }

    /// `value` of each body as written, repeated for every body its generator makes.
    fn per_body<T: Clone>(&self, value: impl Fn(&BodySpec) -> T) -> Vec<T> {
        self.bodies
            .iter()
            .flat_map(|body| {
                let count = expand::count(body.repeat.as_ref()) as usize;
                std::iter::repeat_n(value(body), count)
            })
            .collect()
    }

    /// The number of bodies the scene makes, generators expanded.
    pub fn body_count(&self) -> u64 {
        self.bodies
            .iter()
            .map(|body| expand::count(body.repeat.as_ref()))
            .fold(0, u64::saturating_add)
    }

    /// One body as written, before its generator: every field checked and converted.
    fn template(&self, spec: &BodySpec) -> Result<BodyDesc, FieldError> {
        let shape = build_shape(&spec.shape).map_err(|e| e.within("shape"))?;
        vector("position", spec.position)?;
        let rotation = build_rotation(&spec.rotation).map_err(|e| e.within("rotation"))?;
        vector("velocity", spec.velocity)?;
        vector("angular_velocity", spec.angular_velocity)?;
        let material = self.material(&spec.material)?;
        if let Some(mass) = spec.mass {
            positive("mass", mass)?;
        }
        if let Some(repeat) = &spec.repeat {
            expand::check(repeat).map_err(|e| e.within("repeat"))?;
        }
        let (velocity, angular_velocity) = match spec.kinematic {
            Some(motion) => kinematic_velocities(spec, &motion)?,
            None => (spec.velocity, spec.angular_velocity),
        };
        Ok(BodyDesc {
            name: spec.name.clone(),
            shape,
            material,
            motion: motion_of(spec),
            mass: spec.mass,
            position: spec.position,
            rotation,
            velocity,
            angular_velocity,
        })
    }

    fn material(&self, material: &MaterialRef) -> Result<Material, FieldError> {
        match material {
            MaterialRef::Inline(material) => {
                check_material(material).map_err(|e| e.within("material"))?;
                Ok(*material)
            }
            MaterialRef::Named(name) => self.materials.get(name).copied().ok_or_else(|| {
                let known: Vec<&str> = self.materials.keys().map(String::as_str).collect();
                let defined = if known.is_empty() {
                    "the scene defines no materials".to_owned()
                } else {
                    format!("defined: {}", known.join(", "))
                };
                FieldError::new("material", format!("unknown material '{name}' ({defined})"))
            }),
        }
    }
}

fn motion_of(spec: &BodySpec) -> Motion {
    match (spec.is_static, spec.kinematic) {
        (true, _) => Motion::Static,
        (false, Some(_)) => Motion::Kinematic,
        (false, None) => Motion::Dynamic,
    }
}

/// A kinematic body's starting velocities: its script's, which `velocity` and
/// `angular_velocity` may not contradict (nor may `static`).
fn kinematic_velocities(
    spec: &BodySpec,
    motion: &KinematicSpec,
) -> Result<(DVec3, DVec3), FieldError> {
    script::check(motion).map_err(|e| e.within("kinematic"))?;
    if spec.is_static {
        return Err(FieldError::new(
            "kinematic",
            "a body is either static or kinematic, not both",
        ));
    }
    for (field, value) in [
        ("velocity", spec.velocity),
        ("angular_velocity", spec.angular_velocity),
    ] {
        if value != DVec3::ZERO {
            return Err(FieldError::new(
                field,
                "a kinematic body moves as its script says: give its velocity in kinematic",
            ));
        }
    }
    Ok(match *motion {
        KinematicSpec::Velocity { linear, angular } => (linear, angular),
        KinematicSpec::Sinusoid { .. } => (DVec3::ZERO, DVec3::ZERO),
    })
}

/// The scripts of a kinematic body line's copies, `descs`, which start at slot `first`; each
/// copy is put at its script's pose at t = 0.
fn start_scripts(
    motion: KinematicSpec,
    first: usize,
    descs: &mut [BodyDesc],
) -> Vec<ScriptedMotion> {
    let mut scripts = Vec::with_capacity(descs.len());
    for (k, desc) in descs.iter_mut().enumerate() {
        let script = ScriptedMotion {
            body: BodyId::new(first + k, 0),
            motion,
            rest_position: desc.position,
            rest_rotation: desc.rotation,
        };
        (desc.position, desc.rotation) = script.pose_at(0.0);
        scripts.push(script);
    }
    scripts
}

/// What only the engine can tell: its own checks, which include whether the mass, inertia
/// and momenta it derives stay finite (a tiny density or a huge speed can overflow them).
fn check_engine_body(desc: &BodyDesc) -> Result<(), FieldError> {
    RigidBody::from_desc(desc).map(|_| ()).map_err(field_of)
}

/// The template's copies, named `name_0`, `name_1`, … when a generator made them.
fn instances(spec: &BodySpec, template: &BodyDesc) -> Result<Vec<BodyDesc>, FieldError> {
    let repeated = spec.repeat.is_some();
    let offsets = expand::offsets(spec.repeat.as_ref());
    let mut descs = Vec::with_capacity(offsets.len());
    for (index, offset) in offsets.into_iter().enumerate() {
        let position = template.position + offset;
        if !position.is_finite() {
            return Err(FieldError::new(
                "repeat.spacing",
                format!("copy {index} lands at a non-finite position {position}"),
            ));
        }
        let name = if repeated {
            format!("{}_{index}", template.name)
        } else {
            template.name.clone()
        };
        descs.push(BodyDesc {
            name,
            position,
            ..template.clone()
        });
    }
    Ok(descs)
}

/// The engine's message, reduced to its field: the body is named by the caller.
fn field_of(error: BodyError) -> FieldError {
    FieldError::new(error.field(), error.reason())
}

/// Adding a body that `body_descs` accepted cannot fail; should the engine's rules ever
/// tighten, its error still names the body.
fn body_error(file: &str, error: BodyError) -> SceneError {
    let body = format!("'{}'", error.body());
    field_of(error).in_body(file, &body)
}

pub(crate) fn to_force(force: &ForceSpec) -> EnvironmentForce {
    match *force {
        ForceSpec::Gravity { acceleration } => EnvironmentForce::Gravity { acceleration },
        ForceSpec::LinearDrag { coefficient } => EnvironmentForce::LinearDrag { coefficient },
        ForceSpec::QuadraticDrag { coefficient } => EnvironmentForce::QuadraticDrag { coefficient },
        ForceSpec::Wind {
            velocity,
            coefficient,
        } => EnvironmentForce::Wind {
            velocity,
            coefficient,
        },
    }
}
