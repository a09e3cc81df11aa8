//! Work against precision of the contact pipelines on two reference cases with analytic
//! answers, over dt and substeps (soft) or slices (classic):
//! - C2 bounce: a 0.1 m ball dropped 1 m onto the ground with ε = 0.8; the error is the
//!   largest relative error of the first three apex heights against h ε^(2k).
//! - C4 slide: a box sliding at 5 m/s with μ = 0.5; the error is the relative error of the
//!   stopping distance against v²/(2 μ g).

use glam::DVec3;

use crate::bench::median_time;
use crate::physics::forces::STANDARD_GRAVITY;
use crate::physics::{
    BodyDesc, BodyId, EnvironmentForce, Material, Pipeline, Shape, World, WorldSettings,
};

pub const DTS: [f64; 4] = [1.0 / 30.0, 1.0 / 60.0, 1.0 / 120.0, 1.0 / 240.0];
pub const SUBSTEPS: [u32; 4] = [1, 2, 4, 8];
const REPEATS: usize = 3;

/// One configuration's error and cost.
pub struct Point {
    pub pipeline: Pipeline,
    pub substeps: u32,
    pub dt: f64,
    pub error: f64,
    /// Median wall time per simulated second, µs.
    pub micros_per_second: f64,
}

fn material(restitution: f64, friction: f64) -> Material {
    Material {
        density: 1000.0,
        restitution,
        friction,
    }
}

fn world(pipeline: Pipeline, substeps: u32, restitution: f64, friction: f64) -> World {
    let mut world = World::new(WorldSettings {
        pipeline,
        ..WorldSettings::default()
    });
    world.settings.solver.substeps = substeps;
    world.settings.classic.substeps = substeps;
    world.settings.sleep.enabled = false;
    world.forces.push(EnvironmentForce::earth_gravity());
    let ground = BodyDesc::fixed(Shape::cuboid(DVec3::new(50.0, 0.5, 50.0)))
        .at(DVec3::Y * -0.5)
        .with_material(material(restitution, friction));
    world.add_body(ground).expect("valid ground");
    world
}

/// C2: the largest relative error of the first three apexes (1 if fewer than three).
pub fn bounce(pipeline: Pipeline, substeps: u32, dt: f64) -> (f64, f64) {
    const SECONDS: f64 = 4.0;
    let (radius, drop, e) = (0.1, 1.0, 0.8);
    let (error, seconds) = median_time(REPEATS, || {
        let mut world = world(pipeline, substeps, 1.0, 0.0);
        let ball = BodyDesc::dynamic(Shape::sphere(radius))
            .at(DVec3::Y * (radius + drop))
            .with_material(material(e, 0.0));
        let ball = world.add_body(ball).expect("valid ball");
        let mut apexes = Vec::new();
        let mut previous_vy = 0.0;
        for _ in 0..(SECONDS / dt).round() as usize {
            world.step(dt);
            let vy = world.body(ball).velocity().y;
            if previous_vy > 0.0 && vy <= 0.0 {
                apexes.push(world.body(ball).position.y - radius);
            }
            previous_vy = vy;
        }
        if apexes.len() < 3 {
            return 1.0;
        }
        (0..3)
            .map(|k| {
                let expected = drop * e.powi(2 * (k as i32 + 1));
                (apexes[k] - expected).abs() / expected
            })
            .fold(0.0, f64::max)
    });
    (error, seconds * 1e6 / SECONDS)
}

/// C4: relative error of the stopping distance.
pub fn slide(pipeline: Pipeline, substeps: u32, dt: f64) -> (f64, f64) {
    const SECONDS: f64 = 3.0;
    let (mu, v0) = (0.5, 5.0);
    let (error, seconds) = median_time(REPEATS, || {
        let mut world = world(pipeline, substeps, 0.0, mu);
        let half = DVec3::splat(0.25);
        let block = BodyDesc::dynamic(Shape::cuboid(half))
            .at(DVec3::Y * half.y)
            .with_velocity(DVec3::X * v0)
            .with_material(material(0.0, mu));
        let block: BodyId = world.add_body(block).expect("valid block");
        for _ in 0..(SECONDS / dt).round() as usize {
            world.step(dt);
        }
        let expected = v0 * v0 / (2.0 * mu * STANDARD_GRAVITY);
        (world.body(block).position.x - expected).abs() / expected
    });
    (error, seconds * 1e6 / SECONDS)
}

/// Every pipeline, substep count and dt for one case.
pub fn sweep(case: fn(Pipeline, u32, f64) -> (f64, f64)) -> Vec<Point> {
    let mut points = Vec::new();
    for pipeline in [Pipeline::Soft, Pipeline::Classic] {
        for substeps in SUBSTEPS {
            for dt in DTS {
                let (error, micros_per_second) = case(pipeline, substeps, dt);
                points.push(Point {
                    pipeline,
                    substeps,
                    dt,
                    error,
                    micros_per_second,
                });
            }
        }
    }
    points
}

/// The configurations no other beats on both error and cost.
pub fn pareto_front(points: &[Point]) -> Vec<&Point> {
    let mut front: Vec<&Point> = points
        .iter()
        .filter(|p| {
            !points.iter().any(|q| {
                q.error <= p.error
                    && q.micros_per_second <= p.micros_per_second
                    && (q.error < p.error || q.micros_per_second < p.micros_per_second)
            })
        })
        .collect();
    front.sort_by(|a, b| a.micros_per_second.total_cmp(&b.micros_per_second));
    front
}
