//! Benchmark command: prints Markdown tables of run time against error.
//!
//! `cargo run --release --bin bench > bench.md`

use rigid::bench::idle_bodies::{self, IDLE_BODIES, Idle};
use rigid::bench::{integrators, markdown_table};

fn main() {
    println!("## Integrators: work against precision\n");
    println!("### C1 free fall, position error after 1 s (m)\n");
    println!(
        "{}",
        markdown_table(
            &integrators::sweep(integrators::free_fall),
            "|y − y_exact| (m)"
        )
    );
    println!("### C3 torque-free spin about the intermediate axis, 20 s\n");
    println!(
        "{}",
        markdown_table(
            &integrators::sweep(integrators::intermediate_axis_spin),
            "max |ΔE|/E"
        )
    );
    println!("## What idle bodies cost\n");
    println!("10 awake spheres bouncing on a floor, with {IDLE_BODIES} boxes nothing touches.\n");
    println!("| idle bodies | step time (median) | ratio to none |\n|---|---|---|");
    let alone = idle_bodies::step_time(Idle::None);
    for (name, idle) in [
        ("none", Idle::None),
        ("sleeping", Idle::Sleeping),
        ("static", Idle::Static),
    ] {
        let time = idle_bodies::step_time(idle);
        println!("| {name} | {:.1} µs | {:.2} |", time * 1e6, time / alone);
    }
}
