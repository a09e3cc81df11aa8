//! A step reuses the memory of the steps before it: once a scene's lists (pairs, manifolds,
//! contacts, solver slots, colours, prepared joints) have grown to the most it needs,
//! stepping allocates nothing, on one thread or several. Allocations are counted by this binary's global
//! allocator, on every thread, so the narrow phase's worker threads count too. The binary
//! holds one test, so that no other test allocates while it counts.
//!
//! The steps run inside a rayon pool, as its tasks. Called from a thread outside the pool
//! (the viewer's simulation thread), every step hands its first task to the pool through
//! rayon's injector queue, which allocates a block of 63 slots as it fills one: one
//! allocation in rayon per 63 threaded steps, which this test does not count.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use glam::DVec3;
use rayon::ThreadPoolBuilder;
use rigid::physics::{BodyDesc, EnvironmentForce, JointDesc, Shape, World};
use rigid::scene;

/// The system allocator, counting the allocations and reallocations made while `COUNTING`.
struct CountingAllocator;

static COUNTING: AtomicBool = AtomicBool::new(false);
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

fn count() {
    if COUNTING.load(Ordering::Relaxed) {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
    }
}

// SAFETY: every call is passed on to the system allocator unchanged.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

/// Allocations made while `steps` steps of `dt` run.
fn allocations_over(world: &mut World, dt: f64, steps: usize) -> usize {
    ALLOCATIONS.store(0, Ordering::Relaxed);
    COUNTING.store(true, Ordering::Relaxed);
    for _ in 0..steps {
        world.step(dt);
    }
    COUNTING.store(false, Ordering::Relaxed);
    ALLOCATIONS.load(Ordering::Relaxed)
}

/// A built-in scene after `warm_up` s, with sleeping on or off.
fn warmed_up(name: &str, sleeping: bool, warm_up: f64) -> (World, f64) {
    let scene = scene::load(name).unwrap();
    let mut world = scene.build_world().unwrap();
    world.settings.sleep.enabled = sleeping;
    let dt = scene.settings.dt;
    for _ in 0..(warm_up / dt).round() as usize {
        world.step(dt);
    }
    (world, dt)
}

/// A chain of 10 balls on ball joints from a fixed point, set swinging, beside a kinematic
/// platform carrying a box, after 1 s.
fn joints_and_a_platform() -> (World, f64) {
    let mut world = World::default();
    world.forces.push(EnvironmentForce::earth_gravity());
    world.settings.sleep.enabled = false;
    let mut previous = world
        .add_body(BodyDesc::fixed(Shape::sphere(0.05)))
        .unwrap();
    for k in 1..=10 {
        let at = DVec3::new(0.3 * k as f64, 0.0, 0.0);
        let link = world.add_body(BodyDesc::dynamic(Shape::sphere(0.1)).at(at));
        let link = link.unwrap();
        let anchor = at - DVec3::X * 0.15;
        world
            .add_joint(JointDesc::ball(previous, link, anchor))
            .unwrap();
        previous = link;
    }
    let platform = BodyDesc::kinematic(Shape::cuboid(DVec3::new(2.0, 0.1, 2.0)))
        .at(DVec3::new(0.0, -5.0, 0.0))
        .with_velocity(DVec3::X * 0.5);
    world.add_body(platform).unwrap();
    let crate_ = BodyDesc::dynamic(Shape::cuboid(DVec3::splat(0.2))).at(DVec3::new(0.0, -4.7, 0.0));
    world.add_body(crate_).unwrap();
    let dt = 1.0 / 60.0;
    for _ in 0..60 {
        world.step(dt);
    }
    (world, dt)
}

/// 30 unit boxes created at one point on a fixed floor, after 3 steps: they are still
/// deeper in each other than `deep_overlap`, so the steps push them out (`soft::push_out`).
fn a_crowd_at_one_point() -> (World, f64) {
    let mut world = World::default();
    world.forces.push(EnvironmentForce::earth_gravity());
    let floor = BodyDesc::fixed(Shape::cuboid(DVec3::new(20.0, 0.5, 20.0))).at(DVec3::Y * -0.5);
    world.add_body(floor).unwrap();
    let crate_ = BodyDesc::dynamic(Shape::cuboid(DVec3::splat(0.5))).at(DVec3::Y * 0.5);
    for _ in 0..30 {
        world.add_body(crate_.clone()).unwrap();
    }
    let dt = 1.0 / 60.0;
    for _ in 0..3 {
        world.step(dt);
    }
    (world, dt)
}

#[test]
fn steps_after_the_lists_have_grown_allocate_nothing() {
    // The pyramid's 210 boxes kept awake: every stage runs on a full resting load, the
    // manifolds carried from step to step. The bounce scene's elastic ball keeps hitting
    // the floor (a period of 1.28 s) after the other four have come to rest and fallen
    // asleep: a manifold is made and dropped at every bounce. Each runs first until its
    // load is at its peak, then for longer than a bounce.
    let cases = [("pyramid", false, 2.0, 2.0), ("bounce", true, 8.0, 3.0)];
    let mut failures = Vec::new();
    for threads in [1, 2] {
        let pool = ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        for (name, sleeping, warm_up, measured) in cases {
            let (allocations, steps, awake) = pool.install(|| {
                let (mut world, dt) = warmed_up(name, sleeping, warm_up);
                let steps = (measured / dt).round() as usize;
                let awake = world.awake_count();
                (allocations_over(&mut world, dt, steps), steps, awake)
            });
            let case =
                format!("{name}, {threads} threads: {allocations} allocations in {steps} steps");
            println!("{case}, {awake} awake");
            assert!(awake > 0, "{name}: nothing awake to measure");
            if allocations != 0 {
                failures.push(case);
            }
        }
        let allocations = pool.install(|| {
            let (mut world, dt) = joints_and_a_platform();
            allocations_over(&mut world, dt, 60)
        });
        let case = format!("joints and a platform, {threads} threads: {allocations} allocations");
        println!("{case}");
        if allocations != 0 {
            failures.push(case);
        }
        let (allocations, deepest) = pool.install(|| {
            let (mut world, dt) = a_crowd_at_one_point();
            (allocations_over(&mut world, dt, 5), world.max_penetration())
        });
        let case = format!("a crowd at one point, {threads} threads: {allocations} allocations");
        println!("{case}, deepest overlap {deepest} m");
        let deep_overlap = World::default().settings.solver.deep_overlap;
        assert!(deepest > deep_overlap, "no deep overlap left to push out");
        if allocations != 0 {
            failures.push(case);
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}
