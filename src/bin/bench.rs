//! Benchmark command: prints Markdown tables of run time against error.
//!
//! `cargo run --release --bin bench > bench.md`

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
}
