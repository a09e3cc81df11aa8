//! Our engine (`rigid`) built from a shared scene description, at its default settings:
//! the `soft` pipeline with 8 substeps, the midpoint integrator and sleeping on. Only the
//! substeps may be set otherwise (for the sweep of work against error), and sleeping turned
//! off where the scene says so.

use glam::{DMat3, DVec3};
use rigid::physics::{BodyDesc, BodyId, EnvironmentForce, JointDesc, Material, Shape, World};

use crate::Engine;
use crate::scenes::{self, SceneDesc, ShapeDesc};

pub struct Ours {
    world: World,
    /// Our id of each body of the description, in its order.
    ids: Vec<BodyId>,
}

/// Our shape of each body of the scene, in its order. Each of the scene's hulls is built
/// once, by our hull code (`ConvexHull::from_points`), and shared by the bodies using it.
pub fn shapes_of(scene: &SceneDesc) -> Vec<Shape> {
    let hulls: Vec<Shape> = scene
        .hulls
        .iter()
        .map(|points| Shape::hull(points).expect("scene hulls span a volume"))
        .collect();
    scene
        .bodies
        .iter()
        .map(|b| shape_of(b.shape, &hulls))
        .collect()
}

/// Our shape for a shared shape description; `hulls` are the scene's hulls, built.
fn shape_of(shape: ShapeDesc, hulls: &[Shape]) -> Shape {
    match shape {
        ShapeDesc::Sphere { radius } => Shape::sphere(radius),
        ShapeDesc::Cuboid { half_extents } => Shape::cuboid(half_extents),
        ShapeDesc::Capsule {
            half_height,
            radius,
        } => Shape::capsule(half_height, radius),
        ShapeDesc::Cylinder {
            half_height,
            radius,
        } => Shape::cylinder(half_height, radius),
        ShapeDesc::Hull { hull } => hulls[hull].clone(),
    }
}

impl Ours {
    pub fn world(&self) -> &World {
        &self.world
    }

    pub fn world_mut(&mut self) -> &mut World {
        &mut self.world
    }
}

impl Engine for Ours {
    const NAME: &'static str = "ours";

    fn build(scene: &SceneDesc, substeps: Option<u32>) -> Self {
        let mut world = World::default();
        if let Some(substeps) = substeps {
            world.settings.solver.substeps = substeps;
        }
        world.settings.sleep.enabled = scene.sleeping;
        world.forces.push(EnvironmentForce::Gravity {
            acceleration: DVec3::new(0.0, -scenes::GRAVITY, 0.0),
        });
        let ids = scene
            .bodies
            .iter()
            .zip(shapes_of(scene))
            .map(|(b, shape)| {
                let desc = if b.fixed {
                    BodyDesc::fixed(shape)
                } else {
                    BodyDesc::dynamic(shape)
                };
                let material = Material {
                    density: b.material.density,
                    restitution: b.material.restitution,
                    friction: b.material.friction,
                };
                let desc = desc
                    .at(b.position)
                    .rotated(b.rotation)
                    .with_velocity(b.velocity)
                    .with_material(material);
                world.add_body(desc).expect("scene bodies are valid")
            })
            .collect::<Vec<_>>();
        for joint in &scene.joints {
            let desc = JointDesc::ball(ids[joint.a], ids[joint.b], joint.anchor);
            world.add_joint(desc).expect("scene joints are valid");
        }
        Ours { world, ids }
    }

    fn step(&mut self) {
        self.world.step(scenes::DT);
    }

    fn position(&self, i: usize) -> DVec3 {
        self.world.body(self.ids[i]).position
    }

    fn orientation(&self, i: usize) -> DMat3 {
        self.world.body(self.ids[i]).orientation
    }

    fn velocity(&self, i: usize) -> DVec3 {
        self.world.body(self.ids[i]).velocity()
    }

    fn kinetic_energy(&self, i: usize) -> f64 {
        self.world.body(self.ids[i]).kinetic_energy()
    }

    fn mass(&self, i: usize) -> f64 {
        self.world.body(self.ids[i]).mass()
    }

    fn is_sleeping(&self, i: usize) -> bool {
        self.world.body(self.ids[i]).sleeping
    }
}
