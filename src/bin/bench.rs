//! Benchmark command: prints Markdown tables (run time against error, idle-body cost,
//! scaling, stage profile, stability stress) and writes the plots as SVG.
//!
//! `cargo run --release --no-default-features --bin bench > bench.md`
//! `cargo run --release --no-default-features --bin bench -- scaling profile`

use std::path::PathBuf;

use clap::{Parser, ValueEnum};
use rigid::bench::contact_cases::{self, Point};
use rigid::bench::idle_bodies::{self, IDLE_BODIES, Idle};
use rigid::bench::scaling::{self, BRUTE_FORCE_LIMIT, COUNTS, KINDS};
use rigid::bench::svg_plot::{Series, log_log};
use rigid::bench::{integrators, markdown_table, stage_profile, stress};
use rigid::physics::Pipeline;

#[derive(Parser)]
#[command(about = "Benchmarks of the engine: tables on stdout, plots as SVG")]
struct Args {
    /// Sections to run (all when none is named).
    sections: Vec<Section>,
    /// Where the SVG plots go.
    #[arg(long, default_value = "assets/benchmarks")]
    plots: PathBuf,
}

#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
enum Section {
    Integrators,
    Contacts,
    Idle,
    Scaling,
    Profile,
    Stress,
}

fn main() -> Result<(), String> {
    let args = Args::parse();
    let wants = |s: Section| args.sections.is_empty() || args.sections.contains(&s);
    if wants(Section::Integrators) {
        integrator_tables();
    }
    if wants(Section::Contacts) {
        contact_tables(&args.plots)?;
    }
    if wants(Section::Idle) {
        idle_table();
    }
    if wants(Section::Scaling) {
        scaling_table(&args.plots)?;
    }
    if wants(Section::Profile) {
        profile_table();
    }
    if wants(Section::Stress) {
        stress_table();
    }
    Ok(())
}

fn integrator_tables() {
    println!("## Integrators: work against precision\n");
    println!("### C1 free fall, position error after 1 s (m)\n");
    let c1 = integrators::sweep(integrators::free_fall);
    println!("{}", markdown_table(&c1, "|y − y_exact| (m)"));
    println!("### C3 torque-free spin about the intermediate axis, 20 s\n");
    let c3 = integrators::sweep(integrators::intermediate_axis_spin);
    println!("{}", markdown_table(&c3, "max |ΔE|/E"));
}

/// A contact reference case: (pipeline, substeps, dt) → (error, µs per simulated second).
type ContactCase = fn(Pipeline, u32, f64) -> (f64, f64);

fn contact_tables(plots: &std::path::Path) -> Result<(), String> {
    println!("## Contact pipelines: work against precision\n");
    let cases: [(&str, &str, ContactCase); 2] = [
        (
            "C2 bounce, worst relative apex error of bounces 1–3",
            "c2_bounce",
            contact_cases::bounce,
        ),
        (
            "C4 slide, relative error of the stopping distance",
            "c4_slide",
            contact_cases::slide,
        ),
    ];
    for (title, file, case) in cases {
        let points = contact_cases::sweep(case);
        println!("### {title}\n");
        println!(
            "| pipeline | substeps | dt | error | µs per simulated s |\n|---|---|---|---|---|"
        );
        for p in &points {
            println!(
                "| {} | {} | 1/{:.0} | {:.2e} | {:.0} |",
                pipeline_name(p.pipeline),
                p.substeps,
                1.0 / p.dt,
                p.error,
                p.micros_per_second
            );
        }
        let front = contact_cases::pareto_front(&points);
        let front_text: Vec<String> = front.iter().map(|p| describe(p)).collect();
        println!(
            "\nPareto front (cheapest first): {}\n",
            front_text.join(" → ")
        );
        let series = [Pipeline::Soft, Pipeline::Classic]
            .into_iter()
            .flat_map(|pipeline| {
                contact_cases::SUBSTEPS
                    .into_iter()
                    .map(move |substeps| (pipeline, substeps))
            })
            .map(|(pipeline, substeps)| Series {
                name: format!("{} ×{substeps}", pipeline_name(pipeline)),
                points: points
                    .iter()
                    .filter(|p| p.pipeline == pipeline && p.substeps == substeps)
                    .map(|p| (p.micros_per_second, p.error.max(1e-6)))
                    .collect(),
            })
            .collect::<Vec<_>>();
        let svg = log_log(title, "µs per simulated second", "relative error", &series);
        write_plot(plots, &format!("{file}.svg"), &svg)?;
    }
    Ok(())
}

fn pipeline_name(pipeline: Pipeline) -> &'static str {
    match pipeline {
        Pipeline::Soft => "soft",
        Pipeline::Classic => "classic",
    }
}

fn describe(p: &Point) -> String {
    format!(
        "{} ×{} at 1/{:.0} ({:.1e})",
        pipeline_name(p.pipeline),
        p.substeps,
        1.0 / p.dt,
        p.error
    )
}

fn write_plot(dir: &std::path::Path, name: &str, svg: &str) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let path = dir.join(name);
    std::fs::write(&path, svg).map_err(|e| format!("{}: {e}", path.display()))?;
    println!("Plot: `{}`\n", path.display());
    Ok(())
}

fn idle_table() {
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
    println!();
}

fn scaling_table(plots: &std::path::Path) -> Result<(), String> {
    println!("## Scaling: step time against body count (rain into a bin)\n");
    println!("Median of steps 30–90 at 1/60 s, all bodies awake and colliding.\n");
    println!("| bodies | sweep and prune | uniform grid | brute force |\n|---|---|---|---|");
    let mut series: Vec<Series> = KINDS
        .iter()
        .map(|(name, _)| Series {
            name: name.to_string(),
            points: Vec::new(),
        })
        .collect();
    for count in COUNTS {
        let mut row = format!("| {count} |");
        for (k, (_, kind)) in KINDS.iter().enumerate() {
            let skip = matches!(kind, rigid::physics::BroadPhaseKind::BruteForce)
                && count > BRUTE_FORCE_LIMIT;
            if skip {
                row += " – |";
                continue;
            }
            let time = scaling::step_time(count, *kind);
            series[k].points.push((count as f64, time * 1e3));
            row += &format!(" {:.2} ms |", time * 1e3);
        }
        println!("{row}");
    }
    println!();
    let svg = log_log(
        "Step time against body count (rain)",
        "bodies",
        "ms per step",
        &series,
    );
    write_plot(plots, "scaling.svg", &svg)
}

fn profile_table() {
    println!("## Stage profile: where a step's time goes\n");
    println!("Mean µs per step over the first 2 s of each scene at its own dt.\n");
    println!(
        "| scene | steps | broad phase | narrow phase | islands | solve | checks | total |\n\
         |---|---|---|---|---|---|---|---|"
    );
    for name in stage_profile::SCENES {
        let (t, steps) = stage_profile::profile(name);
        let us = |s: f64| format!("{:.0}", s * 1e6);
        println!(
            "| {name} | {steps} | {} | {} | {} | {} | {} | {} |",
            us(t.broad_phase),
            us(t.narrow_phase),
            us(t.islands),
            us(t.solve),
            us(t.checks),
            us(t.total())
        );
    }
    println!();
}

fn stress_table() {
    println!("## Stability stress\n");
    println!("| case | measured | criterion | result |\n|---|---|---|---|");
    let outcomes = [
        stress::tumbling(1_000_000),
        stress::stack(10),
        stress::stack(20),
        stress::stack(40),
        stress::heavy_on_light(100.0),
        stress::heavy_on_light(1000.0),
        stress::projectile(300.0),
        stress::projectile(1000.0),
        stress::long_pachinko(300.0),
    ];
    for o in outcomes {
        let verdict = if o.passed { "pass" } else { "**fail**" };
        // Norms are written |x|: escape the bars so they do not end table cells.
        let cell = |text: &str| text.replace('|', "\\|");
        println!(
            "| {} | {} | {} | {verdict} |",
            o.case,
            cell(&o.measured),
            cell(o.criterion)
        );
    }
    println!();
}
