//! Scene → engine: body descriptions and the `World`.

use crate::physics::{
    AddBodyError, BodyDesc, BodyError, EnvironmentForce, MAX_BODIES, Material, Motion, RigidBody,
    World, WorldSettings,
};
use crate::scene::error::{FieldError, SceneError, body_label};
use crate::scene::expand;
use crate::scene::file::{BodySpec, ForceSpec, Scene};
use crate::scene::material_ref::MaterialRef;
use crate::scene::shapes::{build_rotation, build_shape};
use crate::scene::validate::{self, check_material, positive, vector};

impl Scene {
    /// A world holding every body of the scene, its forces and its integrator. The time step is
    /// not part of a world: pass `self.settings.dt` to `World::step`.
    pub fn build_world(&self) -> Result<World, SceneError> {
        let descs = self.body_descs()?;
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
        validate::check_scene(self)?;
        let mut descs = Vec::new();
        for (index, spec) in self.bodies.iter().enumerate() {
            let label = body_label(&spec.name, index);
            let template = self
                .template(spec)
                .map_err(|e| e.in_body(&self.origin, &label))?;
            check_engine_body(&template).map_err(|e| e.in_body(&self.origin, &label))?;
            descs.extend(instances(spec, &template).map_err(|e| e.in_body(&self.origin, &label))?);
        }
        Ok(descs)
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
        Ok(BodyDesc {
            name: spec.name.clone(),
            shape,
            material,
            motion: if spec.is_static {
                Motion::Static
            } else {
                Motion::Dynamic
            },
            mass: spec.mass,
            position: spec.position,
            rotation,
            velocity: spec.velocity,
            angular_velocity: spec.angular_velocity,
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
