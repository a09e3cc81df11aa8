//! rapier3d (the `rapier3d-f64` crate: f64 throughout, like ours) built from the same scene
//! description, at its default `IntegrationParameters` apart from dt (and, for the sweep of
//! work against error, the number of solver iterations). Where the scene has sleeping off,
//! every body is built with `can_sleep(false)`. Hulls are rapier's own convex hull of the
//! scene's points (`SharedShape::convex_hull`), built once per cloud and shared. Joints are
//! impulse joints (`ImpulseJointSet`, solved with the contacts), not multibody joints.
//!
//! rapier's math is glam 0.33 (through `glamx`) and ours is glam 0.34: vectors cross over
//! component by component.

use glam::{DMat3, DQuat, DVec3};
use rapier3d_f64::math::{Pose, Rotation, Vector};
use rapier3d_f64::prelude::{
    CoefficientCombineRule, ColliderBuilder, IntegrationParameters, PhysicsWorld, RigidBodyBuilder,
    RigidBodyHandle, SharedShape, SphericalJointBuilder,
};

use crate::Engine;
use crate::scenes::{self, SceneDesc, ShapeDesc};

/// rapier combines a pair's coefficients with the rule of the two colliders (the larger
/// rule wins), by default the average. Ours takes the smaller restitution and the geometric
/// mean of the frictions; every rapier collider here is given those rules so both engines
/// see the same contact coefficients in mixed scenes.
pub const RESTITUTION_RULE: CoefficientCombineRule = CoefficientCombineRule::Min;
pub const FRICTION_RULE: CoefficientCombineRule = CoefficientCombineRule::GeometricMean;

/// The integration parameters used: rapier's defaults with the shared dt, and `iterations`
/// solver iterations (its substeps) when given.
pub fn parameters(iterations: Option<u32>) -> IntegrationParameters {
    let defaults = IntegrationParameters::default();
    IntegrationParameters {
        dt: scenes::DT,
        num_solver_iterations: iterations.map_or(defaults.num_solver_iterations, |n| n as usize),
        ..defaults
    }
}

pub struct Theirs {
    world: PhysicsWorld,
    /// rapier's handle of each body of the description, in its order.
    handles: Vec<RigidBodyHandle>,
}

fn to_rapier(v: DVec3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

fn from_rapier(v: Vector) -> DVec3 {
    DVec3::new(v.x, v.y, v.z)
}

fn rotation_to_rapier(q: DQuat) -> Rotation {
    Rotation::from_xyzw(q.x, q.y, q.z, q.w)
}

impl Engine for Theirs {
    const NAME: &'static str = "rapier";

    fn build(scene: &SceneDesc, iterations: Option<u32>) -> Self {
        let mut world = PhysicsWorld {
            gravity: Vector::new(0.0, -scenes::GRAVITY, 0.0),
            integration_parameters: parameters(iterations),
            ..PhysicsWorld::default()
        };
        let hulls: Vec<SharedShape> = scene
            .hulls
            .iter()
            .map(|points| {
                let points: Vec<Vector> = points.iter().map(|&p| to_rapier(p)).collect();
                SharedShape::convex_hull(&points).expect("scene hulls span a volume")
            })
            .collect();
        let handles = scene
            .bodies
            .iter()
            .map(|b| {
                let body = if b.fixed {
                    RigidBodyBuilder::fixed()
                } else {
                    RigidBodyBuilder::dynamic().can_sleep(scene.sleeping)
                };
                let pose = Pose::from_parts(to_rapier(b.position), rotation_to_rapier(b.rotation));
                let body = body.pose(pose).linvel(to_rapier(b.velocity));
                let collider = match b.shape {
                    ShapeDesc::Sphere { radius } => ColliderBuilder::ball(radius),
                    ShapeDesc::Cuboid { half_extents: h } => ColliderBuilder::cuboid(h.x, h.y, h.z),
                    ShapeDesc::Capsule {
                        half_height,
                        radius,
                    } => ColliderBuilder::capsule_y(half_height, radius),
                    ShapeDesc::Cylinder {
                        half_height,
                        radius,
                    } => ColliderBuilder::cylinder(half_height, radius),
                    ShapeDesc::Hull { hull } => ColliderBuilder::new(hulls[hull].clone()),
                };
                // The body's mass and inertia come from the collider's density, as ours do.
                let collider = collider
                    .density(b.material.density)
                    .friction(b.material.friction)
                    .restitution(b.material.restitution)
                    .friction_combine_rule(FRICTION_RULE)
                    .restitution_combine_rule(RESTITUTION_RULE);
                world.insert(body, collider).0
            })
            .collect::<Vec<_>>();
        for joint in &scene.joints {
            // An impulse joint at rapier's defaults, but for contacts between the two bodies,
            // which rapier keeps and ours (and Box3D) turn off.
            let builder = SphericalJointBuilder::new()
                .local_anchor1(to_rapier(joint.local_anchor(&scene.bodies, joint.a)))
                .local_anchor2(to_rapier(joint.local_anchor(&scene.bodies, joint.b)))
                .contacts_enabled(false);
            world.insert_impulse_joint(handles[joint.a], handles[joint.b], builder);
        }
        Theirs { world, handles }
    }

    fn step(&mut self) {
        self.world.step();
    }

    fn position(&self, i: usize) -> DVec3 {
        // The centre of mass, as ours reports (the same point as the body origin for these
        // symmetric shapes and the scenes' hulls, centred on theirs).
        from_rapier(self.world.bodies[self.handles[i]].center_of_mass())
    }

    fn orientation(&self, i: usize) -> DMat3 {
        let q = self.world.bodies[self.handles[i]].rotation();
        DMat3::from_quat(DQuat::from_xyzw(q.x, q.y, q.z, q.w))
    }

    fn velocity(&self, i: usize) -> DVec3 {
        from_rapier(self.world.bodies[self.handles[i]].linvel())
    }

    fn kinetic_energy(&self, i: usize) -> f64 {
        self.world.bodies[self.handles[i]].kinetic_energy()
    }

    fn mass(&self, i: usize) -> f64 {
        self.world.bodies[self.handles[i]].mass()
    }

    fn is_sleeping(&self, i: usize) -> bool {
        self.world.bodies[self.handles[i]].is_sleeping()
    }
}
