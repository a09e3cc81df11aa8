//! What idle bodies cost: step time of 10 awake spheres bouncing on a floor, alone and beside
//! 10 000 sleeping or 10 000 static boxes that nothing touches.

use glam::DVec3;

use crate::median_time;
use rigid::physics::{BodyDesc, EnvironmentForce, Material, Shape, World};

pub const IDLE_BODIES: usize = 10_000;
const STEPS: usize = 600;
const REPEATS: usize = 7;

/// Balls and floor bounce back fully: the balls are still bouncing when the timed steps end.
const LIVELY: Material = Material {
    density: 1000.0,
    restitution: 1.0,
    friction: 0.5,
};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Idle {
    None,
    Sleeping,
    Static,
}

/// Median wall time of one step, s, over fresh worlds that were built and took their first
/// step (which computes every body's box once) before the clock started.
pub fn step_time(idle: Idle) -> f64 {
    let worlds: Vec<World> = (0..REPEATS)
        .map(|_| {
            let mut world = scene(idle);
            world.step(1.0 / 60.0);
            world
        })
        .collect();
    let mut worlds = worlds.into_iter();
    let (awake, seconds) = median_time(REPEATS, || {
        let mut world = worlds.next().expect("one world per repeat");
        for _ in 0..STEPS {
            world.step(1.0 / 60.0);
        }
        world.awake_count()
    });
    assert_eq!(awake, 10, "the balls must still be bouncing");
    seconds / STEPS as f64
}

fn scene(idle: Idle) -> World {
    let mut world = World::default();
    world.forces.push(EnvironmentForce::earth_gravity());
    let floor = BodyDesc::fixed(Shape::cuboid(DVec3::new(70.0, 0.5, 130.0)))
        .at(DVec3::Y * -0.5)
        .with_material(LIVELY);
    world.add_body(floor).expect("valid floor");
    for i in 0..10 {
        let ball = BodyDesc::dynamic(Shape::sphere(0.2))
            .at(DVec3::new(i as f64, 2.0, -5.0))
            .with_material(LIVELY);
        world.add_body(ball).expect("valid ball");
    }
    if idle == Idle::None {
        return world;
    }
    // A 100 × 100 grid of boxes resting on the floor, 1.2 m apart, away from the balls.
    for i in 0..IDLE_BODIES {
        let at = DVec3::new(
            (i % 100) as f64 * 1.2 - 59.0,
            0.25,
            (i / 100) as f64 * 1.2 + 1.0,
        );
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
