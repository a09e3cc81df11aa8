//! The worlds the viewer can show, by name. This is the one place that creates worlds for the
//! viewer: when scene files arrive, `build` becomes a lookup into them.

use std::f64::consts::FRAC_PI_2;

use glam::{DQuat, DVec3, Vec3};

use crate::physics::{BodyDesc, BodyError, EnvironmentForce, Shape, World};

pub const DEFAULT_SCENE: &str = "falling_box";

pub const SCENE_NAMES: &[&str] = &["falling_box", "pachinko", "shapes", "spin"];

/// Where the camera starts: it looks from `eye` at `target`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraHint {
    pub eye: Vec3,
    pub target: Vec3,
}

/// A world ready to run, with the camera that frames it.
#[derive(Clone, Debug)]
pub struct SceneSetup {
    pub world: World,
    pub camera: CameraHint,
}

/// Builds the named scene, or says which names exist.
pub fn build(name: &str) -> Result<SceneSetup, String> {
    let built = match name {
        "falling_box" => falling_box(),
        "pachinko" => pachinko(),
        "shapes" => shapes(),
        "spin" => spin(),
        _ => {
            return Err(format!(
                "unknown scene '{name}'; known: {}",
                SCENE_NAMES.join(", ")
            ));
        }
    };
    built.map_err(|e| format!("scene '{name}': {e}"))
}

fn earth_world() -> World {
    let mut world = World::default();
    world.forces.push(EnvironmentForce::earth_gravity());
    world
}

fn camera(eye: [f32; 3], target: [f32; 3]) -> CameraHint {
    CameraHint {
        eye: Vec3::from(eye),
        target: Vec3::from(target),
    }
}

/// The report's figure 10: a box dropped, tilted and off-centre, onto a fixed cube that
/// stands on a fixed platform.
fn falling_box() -> Result<SceneSetup, BodyError> {
    let mut world = earth_world();
    let platform = Shape::cuboid(DVec3::new(4.0, 0.25, 4.0));
    world.add_body(
        BodyDesc::fixed(platform)
            .named("platform")
            .at(DVec3::new(0.0, -0.25, 0.0)),
    )?;
    let cube = Shape::cuboid(DVec3::splat(0.5));
    world.add_body(
        BodyDesc::fixed(cube.clone())
            .named("pedestal")
            .at(DVec3::new(0.0, 0.5, 0.0)),
    )?;
    let tilt = DQuat::from_euler(glam::EulerRot::XYZ, 0.5, 0.3, 0.6);
    world.add_body(
        BodyDesc::dynamic(cube)
            .named("box")
            .at(DVec3::new(0.35, 4.0, 0.2))
            .rotated(tilt),
    )?;
    Ok(SceneSetup {
        world,
        camera: camera([6.0, 4.5, 8.5], [0.0, 1.2, 0.0]),
    })
}

const PACHINKO_WIDTH: f64 = 3.0;
const PACHINKO_DEPTH: f64 = 0.3;

/// A vertical board: staggered rows of fixed pins, side walls, bins at the bottom, and a
/// handful of balls above the pins.
fn pachinko() -> Result<SceneSetup, BodyError> {
    let mut world = earth_world();
    let half_w = PACHINKO_WIDTH;
    let d = PACHINKO_DEPTH;
    let slab = |half: DVec3, at: DVec3, name: &str| {
        BodyDesc::fixed(Shape::cuboid(half)).named(name).at(at)
    };
    world.add_body(slab(
        DVec3::new(half_w + 0.1, 5.0, 0.05),
        DVec3::new(0.0, 5.0, -d - 0.05),
        "back",
    ))?;
    world.add_body(slab(
        DVec3::new(half_w + 0.1, 0.1, d),
        DVec3::new(0.0, -0.1, 0.0),
        "floor",
    ))?;
    for side in [-1.0, 1.0] {
        world.add_body(slab(
            DVec3::new(0.1, 5.0, d),
            DVec3::new(side * half_w, 5.0, 0.0),
            "wall",
        ))?;
    }
    add_pins(&mut world)?;
    add_bins(&mut world)?;
    add_balls(&mut world)?;
    Ok(SceneSetup {
        world,
        camera: camera([4.0, 7.5, 16.5], [0.0, 4.8, 0.0]),
    })
}

fn add_pins(world: &mut World) -> Result<(), BodyError> {
    // Cylinders are built along y; a quarter turn about x points them out of the board.
    let across = DQuat::from_rotation_x(FRAC_PI_2);
    let pin = Shape::cylinder(PACHINKO_DEPTH, 0.1);
    let spacing = 0.6;
    for row in 0..9 {
        let y = 2.2 + row as f64 * 0.6;
        let offset = if row % 2 == 0 { 0.0 } else { spacing / 2.0 };
        let mut x = -PACHINKO_WIDTH + 0.3 + offset;
        while x < PACHINKO_WIDTH - 0.2 {
            let at = DVec3::new(x, y, 0.0);
            world.add_body(
                BodyDesc::fixed(pin.clone())
                    .named("pin")
                    .at(at)
                    .rotated(across),
            )?;
            x += spacing;
        }
    }
    Ok(())
}

fn add_bins(world: &mut World) -> Result<(), BodyError> {
    let divider = Shape::cuboid(DVec3::new(0.04, 0.6, PACHINKO_DEPTH));
    for i in 1..8 {
        let x = -PACHINKO_WIDTH + i as f64 * (2.0 * PACHINKO_WIDTH / 8.0);
        let at = DVec3::new(x, 0.6, 0.0);
        world.add_body(BodyDesc::fixed(divider.clone()).named("bin").at(at))?;
    }
    Ok(())
}

fn add_balls(world: &mut World) -> Result<(), BodyError> {
    for i in 0..12 {
        let x = -1.5 + (i % 6) as f64 * 0.55 + 0.07 * (i / 6) as f64;
        let y = 8.4 + (i / 6) as f64 * 0.5;
        let ball = BodyDesc::dynamic(Shape::sphere(0.16)).named("ball");
        world.add_body(ball.at(DVec3::new(x, y, 0.0)))?;
    }
    Ok(())
}

/// One body of each primitive kind, spinning as they fall onto a floor.
fn shapes() -> Result<SceneSetup, BodyError> {
    let mut world = earth_world();
    let floor = Shape::cuboid(DVec3::new(5.0, 0.25, 5.0));
    world.add_body(
        BodyDesc::fixed(floor)
            .named("floor")
            .at(DVec3::new(0.0, -0.25, 0.0)),
    )?;
    let bodies = [
        Shape::sphere(0.5),
        Shape::cuboid(DVec3::new(0.6, 0.3, 0.4)),
        Shape::capsule(0.4, 0.3),
        Shape::cylinder(0.4, 0.4),
    ];
    for (i, shape) in bodies.into_iter().enumerate() {
        let x = -2.4 + i as f64 * 1.6;
        let desc = BodyDesc::dynamic(shape)
            .at(DVec3::new(x, 2.5 + 0.4 * i as f64, 0.0))
            .rotated(DQuat::from_rotation_z(0.4 * i as f64))
            .with_angular_velocity(DVec3::new(0.3, 1.0, 0.5));
        world.add_body(desc)?;
    }
    Ok(SceneSetup {
        world,
        camera: camera([0.0, 5.5, 10.0], [0.0, 0.8, 0.0]),
    })
}

/// Weightless spin about the intermediate axis: the tennis-racket (Dzhanibekov) flip.
fn spin() -> Result<SceneSetup, BodyError> {
    let mut world = World::default();
    let handle = Shape::cuboid(DVec3::new(0.9, 0.35, 0.12));
    world.add_body(
        BodyDesc::dynamic(handle)
            .named("racket")
            .at(DVec3::new(0.0, 1.5, 0.0))
            .with_angular_velocity(DVec3::new(0.01, 4.0, 0.01)),
    )?;
    Ok(SceneSetup {
        world,
        camera: camera([1.5, 3.0, 6.5], [0.0, 1.5, 0.0]),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_named_scene_builds_with_finite_bodies() {
        for name in SCENE_NAMES {
            let setup = build(name).unwrap();
            assert!(!setup.world.bodies().is_empty(), "{name}");
            assert!(setup.world.bodies().iter().all(|b| b.is_finite()), "{name}");
        }
    }

    #[test]
    fn unknown_scene_lists_the_known_ones() {
        let err = build("nope").unwrap_err();
        assert!(err.contains("falling_box"), "{err}");
    }
}
