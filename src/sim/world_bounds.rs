//! Bodies that fell out of the scene. A body that drops past everything would otherwise fall
//! forever: awake, out of view, its kinetic energy growing in the plots. The simulation takes
//! out every dynamic body whose centre of mass sinks below the scene's floor (see
//! `floor_of`) and counts it; being a rule of the simulation, a replay does the same.

use crate::physics::{Aabb, BodyId, Motion, World};

/// The least depth below the scene's lowest fixed point at which a falling body is taken
/// out, m: far below anything the camera frames, so a body is long gone from view first.
pub const MIN_FALL_MARGIN: f64 = 20.0;

/// The height below which a dynamic body has left the world: the bottom of the scene's
/// fixed geometry (static and kinematic bodies, or every body when it has none) minus the
/// larger of `MIN_FALL_MARGIN` and the geometry's largest side. Taken when the scene loads.
pub fn floor_of(world: &World) -> f64 {
    let fixed = bounds_of(world, |motion| {
        matches!(motion, Motion::Static | Motion::Kinematic)
    });
    let scene = if fixed.min.y.is_finite() {
        fixed
    } else {
        bounds_of(world, |_| true)
    };
    if !scene.min.y.is_finite() {
        return -MIN_FALL_MARGIN;
    }
    let size = (scene.max - scene.min).max_element();
    scene.min.y - MIN_FALL_MARGIN.max(size)
}

/// The dynamic bodies whose centre of mass lies below `floor`.
pub fn fallen(world: &World, floor: f64) -> Vec<BodyId> {
    world
        .body_ids()
        .filter(|id| {
            let body = &world.bodies()[id.index()];
            body.is_dynamic() && body.position.y < floor
        })
        .collect()
}

/// The union of the boxes of the bodies whose motion `chosen` accepts; `Aabb::EMPTY` if none.
fn bounds_of(world: &World, chosen: impl Fn(Motion) -> bool) -> Aabb {
    world
        .bodies()
        .iter()
        .filter(|body| chosen(body.motion))
        .map(Aabb::of_body)
        .filter(|aabb| aabb.min.is_finite() && aabb.max.is_finite())
        .fold(Aabb::EMPTY, |all, aabb| all.union(&aabb))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::{BodyDesc, Shape};
    use glam::DVec3;

    #[test]
    fn the_floor_lies_a_margin_below_the_fixed_geometry() {
        let mut world = World::default();
        // A 5 m platform with its bottom at y = -1: the margin is the minimum, 20 m.
        let platform = BodyDesc::fixed(Shape::cuboid(DVec3::new(2.5, 0.5, 2.5)));
        world
            .add_body(platform.at(DVec3::new(0.0, -0.5, 0.0)))
            .unwrap();
        let ball = BodyDesc::dynamic(Shape::sphere(0.5)).at(DVec3::new(0.0, -50.0, 0.0));
        world.add_body(ball).unwrap();
        assert_eq!(floor_of(&world), -21.0);
        // A 60 m wide ground: the margin grows to the scene's size.
        let ground = BodyDesc::fixed(Shape::cuboid(DVec3::new(30.0, 0.5, 1.0)));
        world
            .add_body(ground.at(DVec3::new(0.0, -0.5, 0.0)))
            .unwrap();
        assert_eq!(floor_of(&world), -61.0);
    }

    #[test]
    fn without_fixed_bodies_the_floor_follows_every_body() {
        let mut world = World::default();
        assert_eq!(floor_of(&world), -MIN_FALL_MARGIN);
        let ball = BodyDesc::dynamic(Shape::sphere(1.0)).at(DVec3::new(0.0, 10.0, 0.0));
        world.add_body(ball).unwrap();
        assert_eq!(floor_of(&world), 9.0 - MIN_FALL_MARGIN);
    }
}
