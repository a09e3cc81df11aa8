//! Benchmark command: prints Markdown tables (run time against error, idle-body cost,
//! scaling, stage profile, stability stress) and writes the plots as SVG.
//!
//! `cargo run --release -p rigid-bench > bench.md`
//! `cargo run --release -p rigid-bench -- scaling profile`

use std::path::{Path, PathBuf};

use clap::{Parser, ValueEnum};
use rigid::physics::{Integrator, Pipeline};
use rigid_bench::contact_cases::{self, Point};
use rigid_bench::idle_bodies::{self, IDLE_BODIES, Idle};
use rigid_bench::scaling::{self, BRUTE_FORCE_LIMIT, COUNTS, KINDS};
use rigid_bench::svg_plot::{Series, log_log};
use rigid_bench::{Measurement, integrators, markdown_table, pareto_front, stage_profile, stress};

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
        integrator_tables(&args.plots)?;
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

/// An integrator case: (integrator, dt) → its error and cost.
type IntegratorCase = fn(Integrator, f64) -> Measurement;

fn integrator_tables(plots: &Path) -> Result<(), String> {
    println!("## Integrators: work against precision\n");
    let cases: [(&str, &str, &str, IntegratorCase); 2] = [
        (
            "C1 free fall, position error after 1 s (m)",
            "c1_free_fall",
            "|y − y_exact| (m)",
            integrators::free_fall,
        ),
        (
            "C3 torque-free spin about the intermediate axis, 20 s",
            "c3_spin",
            "max |ΔE|/E",
            integrators::intermediate_axis_spin,
        ),
    ];
    for (title, file, error_label, case) in cases {
        println!("### {title}\n");
        integrator_case(plots, title, file, error_label, case)?;
    }
    Ok(())
}

/// One integrator case: its table, its Pareto front and its plot.
fn integrator_case(
    plots: &Path,
    title: &str,
    file: &str,
    error_label: &str,
    case: IntegratorCase,
) -> Result<(), String> {
    let rows = integrators::sweep(case);
    println!("{}", markdown_table(&rows, error_label));
    let front = pareto_front(&rows, |m| (m.micros_per_sim_second, m.error));
    let text: Vec<String> = front
        .iter()
        .map(|m| format!("{} at 1/{:.0} ({:.1e})", m.config, 1.0 / m.dt, m.error))
        .collect();
    println!("Pareto front (cheapest first): {}\n", text.join(" → "));
    let lines = Integrator::ALL
        .iter()
        .map(|integrator| {
            let points = rows.iter().filter(|m| m.config == integrator.name());
            let points = points.map(|m| (m.micros_per_sim_second, m.error));
            (integrator.name().to_string(), points.collect())
        })
        .collect();
    let front = front.iter().map(|m| (m.micros_per_sim_second, m.error));
    let svg = work_precision_plot(title, error_label, lines, front.collect());
    let alt = format!("{file}: error against cost");
    write_plot(plots, &format!("{file}.svg"), &alt, &svg)
}

fn contact_tables(plots: &Path) -> Result<(), String> {
    println!("## Contact pipelines: work against precision\n");
    let mut fronts = Vec::new();
    for case in &contact_cases::CASES {
        println!("### {}\n", case.title);
        let sweep = contact_cases::sweep(case);
        print_contact_table(case, &sweep.points);
        print_limits(&sweep);
        let front = pareto_front(&sweep.points, |p| (p.micros_per_second, p.error));
        let text: Vec<String> = front.iter().map(|p| describe(p)).collect();
        println!("Pareto front (cheapest first): {}\n", text.join(" → "));
        fronts.push((case.title, text.join(" → ")));
        let lines = contact_lines(&sweep.points);
        let front = front.iter().map(|p| (p.micros_per_second, p.error));
        let svg = work_precision_plot(case.title, "relative error", lines, front.collect());
        let alt = format!("{}: error against cost", case.file);
        write_plot(plots, &format!("{}.svg", case.file), &alt, &svg)?;
    }
    println!("### Pareto fronts of every contact case\n");
    println!("| case | front, cheapest first |\n|---|---|");
    for (title, front) in fronts {
        println!("| {title} | {front} |");
    }
    println!();
    Ok(())
}

/// How long the longest run took, and which dts were left out for being too slow.
fn print_limits(sweep: &contact_cases::Sweep) {
    let longest = sweep
        .points
        .iter()
        .map(|p| p.run_seconds)
        .fold(0.0, f64::max);
    println!(
        "Longest single run: {longest:.2} s (a line stops before a dt whose run would take \
         over {} s).\n",
        contact_cases::MAX_RUN_SECONDS
    );
    for (pipeline, substeps, dts) in &sweep.skipped {
        let dts: Vec<String> = dts.iter().map(|dt| format!("1/{:.0}", 1.0 / dt)).collect();
        println!(
            "Left out: {} ×{substeps} at {} (one run would take over {} s).\n",
            pipeline_name(*pipeline),
            dts.join(", "),
            contact_cases::MAX_RUN_SECONDS
        );
    }
}

fn print_contact_table(case: &contact_cases::Case, points: &[Point]) {
    let (check_head, check_rule) = match case.check {
        Some((title, _)) => (format!(" {title} |"), "---|"),
        None => (String::new(), ""),
    };
    println!(
        "| pipeline | substeps | dt | error | µs per simulated s |{check_head}\n\
         |---|---|---|---|---|{check_rule}"
    );
    for p in points {
        let check = p
            .check
            .as_ref()
            .map(|c| format!(" {c} |"))
            .unwrap_or_default();
        println!(
            "| {} | {} | 1/{:.0} | {:.2e} | {:.0} |{check}",
            pipeline_name(p.config.pipeline),
            p.config.substeps,
            1.0 / p.config.dt,
            p.error,
            p.micros_per_second
        );
    }
    println!();
}

/// One line per pipeline and substep count, across dt: (µs per simulated s, error).
fn contact_lines(points: &[Point]) -> Vec<(String, Vec<(f64, f64)>)> {
    let families = contact_cases::PIPELINES.into_iter().flat_map(|pipeline| {
        let substeps = contact_cases::SUBSTEPS.into_iter();
        substeps.map(move |substeps| (pipeline, substeps))
    });
    families
        .map(|(pipeline, substeps)| {
            let on_line =
                |p: &&Point| p.config.pipeline == pipeline && p.config.substeps == substeps;
            let points = points.iter().filter(on_line);
            let name = format!("{} ×{substeps}", pipeline_name(pipeline));
            (
                name,
                points.map(|p| (p.micros_per_second, p.error)).collect(),
            )
        })
        .collect()
}

/// Error against cost on log axes: one line per configuration family, the Pareto front
/// over them. Log axes cannot show an error of 0: it is drawn a decade below the smallest
/// non-zero error (at 1e-6 if every error is 0), and the plot says so.
fn work_precision_plot(
    title: &str,
    error_label: &str,
    lines: Vec<(String, Vec<(f64, f64)>)>,
    front: Vec<(f64, f64)>,
) -> String {
    let errors = lines
        .iter()
        .flat_map(|(_, points)| points.iter().map(|p| p.1));
    let smallest = errors.clone().filter(|&e| e > 0.0).fold(f64::MAX, f64::min);
    let floor = match smallest {
        f64::MAX => 1e-6,
        e => 10f64.powf(e.log10().floor() - 1.0),
    };
    let zeros = errors.clone().any(|e| e <= 0.0);
    let lift = |points: Vec<(f64, f64)>| points.into_iter().map(|(x, y)| (x, y.max(floor)));
    let mut series: Vec<Series> = lines
        .into_iter()
        .map(|(name, points)| Series::line(name, lift(points).collect()))
        .collect();
    series.push(Series::front(lift(front).collect()));
    let y_label = match zeros {
        true => format!("{error_label} (0 drawn at {floor:.0e})"),
        false => error_label.to_string(),
    };
    log_log(title, "µs per simulated second", &y_label, &series)
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
        pipeline_name(p.config.pipeline),
        p.config.substeps,
        1.0 / p.config.dt,
        p.error
    )
}

/// Writes the plot and prints the Markdown that shows it, `alt` as its text.
fn write_plot(dir: &Path, name: &str, alt: &str, svg: &str) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let path = dir.join(name);
    std::fs::write(&path, svg).map_err(|e| format!("{}: {e}", path.display()))?;
    println!("![{alt}]({})\n", path.display());
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

fn scaling_table(plots: &Path) -> Result<(), String> {
    println!("## Scaling: step time against body count (rain into a bin)\n");
    println!("Median of steps 30–90 at 1/60 s, all bodies awake and colliding.\n");
    println!("| bodies | sweep and prune | uniform grid | brute force |\n|---|---|---|---|");
    let mut series: Vec<Series> = KINDS
        .iter()
        .map(|(name, _)| Series::line(*name, Vec::new()))
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
    write_plot(plots, "scaling.svg", "step time against body count", &svg)
}

fn profile_table() {
    println!("## Stage profile: where a step's time goes\n");
    println!(
        "Mean µs per step over the first 2 s of each scene at its own dt, with its own \
         pipeline. Islands: islands, sleeping and waking. Solve: contact impulses. Integrate: \
         forces and integration of the awake bodies over all substeps.\n"
    );
    println!(
        "| scene | steps | broad phase | narrow phase | islands | solve | integrate | checks | total |\n\
         |---|---|---|---|---|---|---|---|---|"
    );
    for name in rigid::scene::builtin_scene_names() {
        let (t, steps) = stage_profile::profile(name);
        let us = |s: f64| format!("{:.0}", s * 1e6);
        println!(
            "| {name} | {steps} | {} | {} | {} | {} | {} | {} | {} |",
            us(t.broad_phase),
            us(t.narrow_phase),
            us(t.islands),
            us(t.solve),
            us(t.integrate),
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
        stress::heavy_on_light(100.0, 8),
        stress::heavy_on_light(1000.0, 8),
        stress::heavy_on_light(1000.0, 32),
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
