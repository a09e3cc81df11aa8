//! Scene joints → the engine's `JointDesc`s: bodies resolved by name, chains expanded, and
//! each joint checked as `World::add_joint` checks it, so that `parse` finds every error.

use std::collections::HashMap;

use glam::DVec3;

use crate::physics::{BodyDesc, BodyId, JointDesc, JointError, Motion, Servo};
use crate::scene::error::{FieldError, SceneError, body_label};
use crate::scene::expand;
use crate::scene::file::{ChainJoint, JointKindSpec, JointSpec, Scene};
use crate::scene::validate::{finite, vector};

/// A joint ready for `World::add_joint`, with the label its errors carry.
pub(crate) struct SceneJoint {
    pub label: String,
    pub desc: JointDesc,
}

impl Scene {
    /// The index of the body the camera follows (`Camera::follow`) among `bodies` (the
    /// scene's `body_descs`), if it follows one.
    pub(crate) fn body_to_follow(&self, bodies: &[BodyDesc]) -> Result<Option<usize>, SceneError> {
        let Some(name) = &self.camera.follow else {
            return Ok(None);
        };
        let names = BodyNames::of(bodies);
        let body = names.resolve("camera.follow", name);
        body.map(|id| Some(id.0 as usize))
            .map_err(|e| e.in_scene(&self.origin))
    }

    /// Every joint of the scene, chains expanded, between the bodies `bodies` (the scene's
    /// `body_descs`, whose slot k a fresh world numbers `BodyId(k)`).
    pub(crate) fn joint_descs(&self, bodies: &[BodyDesc]) -> Result<Vec<SceneJoint>, SceneError> {
        let names = BodyNames::of(bodies);
        let mut joints = Vec::new();
        for (index, spec) in self.joints.iter().enumerate() {
            let label = body_label(&spec.name, index);
            let descs = self
                .descs_of(spec, &names)
                .map_err(|e| e.in_joint(&self.origin, &label))?;
            let chain = matches!(spec.kind, JointKindSpec::Chain { .. });
            for (k, desc) in descs.into_iter().enumerate() {
                let label = if chain {
                    format!("{label}[{k}]")
                } else {
                    label.clone()
                };
                check(&desc, bodies).map_err(|e| e.in_joint(&self.origin, &label))?;
                joints.push(SceneJoint { label, desc });
            }
        }
        Ok(joints)
    }

    /// The joints one line makes, options applied, before the engine's checks.
    fn descs_of(&self, spec: &JointSpec, names: &BodyNames) -> Result<Vec<JointDesc>, FieldError> {
        check_options(spec)?;
        let descs = match &spec.kind {
            JointKindSpec::Chain { links, joint, pin } => {
                if !spec.body_a.is_empty() || !spec.body_b.is_empty() {
                    return Err(FieldError::new(
                        "body_a",
                        "a chain names its bodies in kind.links and kind.pin, not body_a or body_b",
                    ));
                }
                self.chain(links, *joint, pin.as_deref(), names)?
            }
            kind => {
                let a = names.resolve("body_a", &spec.body_a)?;
                let b = names.resolve("body_b", &spec.body_b)?;
                vec![single(kind, a, b)?]
            }
        };
        Ok(descs.into_iter().map(|d| with_options(d, spec)).collect())
    }

    /// The links' joints of a `Chain`, the pin's first.
    fn chain(
        &self,
        links: &str,
        joint: ChainJoint,
        pin: Option<&str>,
        names: &BodyNames,
    ) -> Result<Vec<JointDesc>, FieldError> {
        let ids = self.chain_links(links, names)?;
        let at = |id: BodyId| names.positions[id.index()];
        let mut descs = Vec::with_capacity(ids.len());
        if let Some(pin) = pin {
            let pin = names.resolve("kind.pin", pin)?;
            // The pin stands in for a link before the first, one link's spacing above it.
            let before = 2.0 * at(ids[0]) - at(ids[1]);
            descs.push(link(joint, pin, ids[0], before, at(ids[0])));
        }
        for pair in ids.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            descs.push(link(joint, a, b, at(a), at(b)));
        }
        Ok(descs)
    }

    /// The copies `links_0`, `links_1`, … of the body line named `links`, in order.
    fn chain_links(&self, links: &str, names: &BodyNames) -> Result<Vec<BodyId>, FieldError> {
        let line = self
            .bodies
            .iter()
            .find(|body| body.name == links && body.repeat.is_some())
            .ok_or_else(|| {
                FieldError::new(
                    "kind.links",
                    format!("no body line named '{links}' has a repeat to make the links"),
                )
            })?;
        let count = expand::count(line.repeat.as_ref());
        if count < 2 {
            return Err(FieldError::new(
                "kind.links",
                format!("'{links}' makes {count} copy, a chain needs at least 2"),
            ));
        }
        (0..count)
            .map(|k| names.resolve("kind.links", &format!("{links}_{k}")))
            .collect()
    }
}

/// The one joint of a line that is not a chain; vectors checked so that a bad one is named
/// by its component.
fn single(kind: &JointKindSpec, a: BodyId, b: BodyId) -> Result<JointDesc, FieldError> {
    Ok(match *kind {
        JointKindSpec::Ball { anchor } => {
            vector("kind.anchor", anchor)?;
            JointDesc::ball(a, b, anchor)
        }
        JointKindSpec::Hinge { anchor, axis } => {
            vector("kind.anchor", anchor)?;
            vector("kind.axis", axis)?;
            JointDesc::hinge(a, b, anchor, axis)
        }
        JointKindSpec::Slider { anchor, axis } => {
            vector("kind.anchor", anchor)?;
            vector("kind.axis", axis)?;
            JointDesc::slider(a, b, anchor, axis)
        }
        JointKindSpec::ConeTwist { anchor, axis, cone } => {
            vector("kind.anchor", anchor)?;
            vector("kind.axis", axis)?;
            finite("kind.cone", cone)?;
            JointDesc::cone_twist(a, b, anchor, axis, cone.to_radians())
        }
        JointKindSpec::Fixed { anchor } => {
            vector("kind.anchor", anchor)?;
            JointDesc::fixed(a, b, anchor)
        }
        JointKindSpec::Distance { anchor_a, anchor_b } => {
            vector("kind.anchor_a", anchor_a)?;
            vector("kind.anchor_b", anchor_b)?;
            JointDesc::distance(a, b, anchor_a, anchor_b)
        }
        JointKindSpec::Chain { .. } => unreachable!("chains are expanded by Scene::chain"),
    })
}

/// One joint of a chain between links whose origins are at `p` and `q`: a ball joint halfway
/// between them, or a rod from one origin to the other.
fn link(joint: ChainJoint, a: BodyId, b: BodyId, p: DVec3, q: DVec3) -> JointDesc {
    match joint {
        ChainJoint::Ball => JointDesc::ball(a, b, p.midpoint(q)),
        ChainJoint::Distance => JointDesc::distance(a, b, p, q),
    }
}

/// Limits in the file's units and in order, before angle limits become radians (so that the
/// message shows what was written).
fn check_options(spec: &JointSpec) -> Result<(), FieldError> {
    if let Some((lo, hi)) = spec.limits {
        finite("limits.0", lo)?;
        finite("limits.1", hi)?;
        if lo > hi {
            return Err(FieldError::new(
                "limits",
                format!("must be in order (lo ≤ hi), got ({lo}, {hi})"),
            ));
        }
    }
    Ok(())
}

fn with_options(desc: JointDesc, spec: &JointSpec) -> JointDesc {
    // Angles in scene files are degrees: a hinge's and a cone-twist's limits, a hinge's
    // servo target.
    let in_degrees = matches!(
        spec.kind,
        JointKindSpec::Hinge { .. } | JointKindSpec::ConeTwist { .. }
    );
    JointDesc {
        limits: spec.limits.map(|(lo, hi)| match in_degrees {
            true => (lo.to_radians(), hi.to_radians()),
            false => (lo, hi),
        }),
        motor: spec.motor,
        servo: spec.servo.map(|s| Servo {
            target: if in_degrees {
                s.target.to_radians()
            } else {
                s.target
            },
            ..s
        }),
        spring: spec.spring,
        breaking: spec.breaking,
        collide_connected: spec.colliding,
        ..desc
    }
}

/// What `World::add_joint` would refuse, told without a world: the description's own checks,
/// and whether either body is dynamic.
fn check(desc: &JointDesc, bodies: &[BodyDesc]) -> Result<(), FieldError> {
    desc.validate().map_err(joint_field)?;
    let dynamic = |id: BodyId| bodies[id.index()].motion == Motion::Dynamic;
    if !dynamic(desc.body_a) && !dynamic(desc.body_b) {
        return Err(joint_field(JointError::NoDynamicBody));
    }
    Ok(())
}

/// The engine's error on the field of the scene's joint line it is about.
pub(crate) fn joint_field(error: JointError) -> FieldError {
    let field = match &error {
        JointError::NotFinite(field)
        | JointError::Negative { field, .. }
        | JointError::NotPositive { field, .. } => field,
        JointError::Unsupported(field) => field,
        JointError::ZeroAxis => "kind.axis",
        JointError::ZeroLength => "kind.anchor_b",
        JointError::LimitsOutOfOrder { .. } => "limits",
        JointError::MotorAndServo => "servo",
        JointError::ConeOutOfRange(_) => "kind.cone",
        JointError::SameBody(_) | JointError::NoDynamicBody => "body_b",
        JointError::NoSuchBody(_) | JointError::BodyGone(_) | JointError::NoSuchJoint(_) => {
            "body_a"
        }
    };
    FieldError::new(field.to_string(), error.to_string())
}

/// The bodies by name, for joints to find them; a name may be shared (then unusable).
struct BodyNames<'a> {
    slots: HashMap<&'a str, Vec<usize>>,
    positions: Vec<DVec3>,
}

impl<'a> BodyNames<'a> {
    fn of(bodies: &'a [BodyDesc]) -> Self {
        let mut slots: HashMap<&str, Vec<usize>> = HashMap::new();
        for (index, body) in bodies.iter().enumerate() {
            slots.entry(body.name.as_str()).or_default().push(index);
        }
        BodyNames {
            slots,
            positions: bodies.iter().map(|body| body.position).collect(),
        }
    }

    /// The one body named `name`, or an error on `field` saying why not.
    fn resolve(&self, field: &str, name: &str) -> Result<BodyId, FieldError> {
        if name.is_empty() {
            return Err(FieldError::new(field, "missing: give a body's name"));
        }
        match self.slots.get(name).map(Vec::as_slice) {
            Some([index]) => Ok(BodyId(*index as u32)),
            Some(many) => Err(FieldError::new(
                field,
                format!(
                    "{} bodies are named '{name}': the name is ambiguous",
                    many.len()
                ),
            )),
            None => Err(FieldError::new(field, self.unknown(name))),
        }
    }

    fn unknown(&self, name: &str) -> String {
        let copy = format!("{name}_0");
        if self.slots.contains_key(copy.as_str()) {
            format!(
                "no body is named '{name}' (its generated copies are '{name}_0', '{name}_1', …)"
            )
        } else {
            format!("no body is named '{name}'")
        }
    }
}
