//! What idle bodies cost: step time of 10 awake spheres bouncing on a floor, alone and beside
//! 1000 sleeping or 1000 static boxes that nothing touches.

use glam::DVec3;

use crate::bench::median_time;
use crate::physics::{BodyDesc, EnvironmentForce, Shape, World};

pub const IDLE_BODIES: usize = 1000;
const STEPS: usize = 120;
const REPEATS: usize = 5;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Idle {
    None,
    Sleeping,
    Static,
}

/// Median wall time of one step, s.
pub fn step_time(idle: Idle) -> f64 {
    let (_, seconds) = median_time(REPEATS, || {
        let mut world = scene(idle);
        for _ in 0..STEPS {
            world.step(1.0 / 60.0);
        }
        world.awake_count()
    });
    seconds / STEPS as f64
}

fn scene(idle: Idle) -> World {
    let mut world = World::default();
    world.forces.push(EnvironmentForce::earth_gravity());
    let floor = BodyDesc::fixed(Shape::cuboid(DVec3::new(60.0, 0.5, 60.0))).at(DVec3::Y * -0.5);
    world.add_body(floor).expect("valid floor");
    for i in 0..10 {
        let ball = BodyDesc::dynamic(Shape::sphere(0.2)).at(DVec3::new(i as f64, 2.0, -5.0));
        world.add_body(ball).expect("valid ball");
    }
    if idle == Idle::None {
        return world;
    }
    // A 40 × 25 grid of boxes resting on the floor, 1.5 m apart, away from the balls.
    for i in 0..IDLE_BODIES {
        let at = DVec3::new((i % 40) as f64 * 1.5 - 30.0, 0.25, (i / 40) as f64 * 1.5);
        let shape = Shape::cuboid(DVec3::splat(0.25));
        let desc = match idle {
            Idle::Static => BodyDesc::fixed(shape),
            _ => BodyDesc::dynamic(shape),
        };
        let id = world.add_body(desc.at(at)).expect("valid box");
        if idle == Idle::Sleeping {
            world.body_mut(id).sleep();
        }
    }
    world
}
