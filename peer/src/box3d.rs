//! Box3D's own benchmark program (`benchmark/main.c` of erincatto/box3d), run on the scenes
//! it shares with ours (`large_pyramid`, `many_pyramids`, `convex_pile`, `joint_grid`), when
//! the environment variable `BOX3D_DIR` names a Box3D checkout built with cmake:
//!
//! ```text
//! cmake -S . -B build -DBOX3D_BENCHMARKS=ON -DBOX3D_SAMPLES=OFF -DCMAKE_BUILD_TYPE=Release
//! cmake --build build --target benchmark -j2
//! ```
//!
//! It is run as `benchmark -t=1 -b=<name> -r=1`: one thread (`-t` is the most threads it
//! tries, from 1 up), one scene, one run per call, so that the calls can take turns with our
//! engines' runs. Each run builds the world, takes one untimed step ("initial step can be
//! expensive and skew benchmark"), then times the remaining steps at dt = 1/60 with 4
//! substeps, and prints `run 0 : <ms> (ms)`, the wall time of those steps together. Its step
//! count is the scene's own (200, 100, 500, 100), fixed in the program. It also writes
//! `<name>.csv` into its working directory, so it runs in a scratch directory.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Where Box3D's benchmark program is, or why it is not run.
pub enum Box3d {
    /// `BOX3D_DIR` is not set.
    NotSet,
    /// `BOX3D_DIR` is set but no built program was found there.
    Missing(String),
    Ready(PathBuf),
}

/// How to make the comparison with Box3D run.
pub const HOW_TO_ENABLE: &str = "set BOX3D_DIR to a Box3D checkout (github.com/erincatto/box3d) \
    built with `cmake -S . -B build -DBOX3D_BENCHMARKS=ON -DBOX3D_SAMPLES=OFF \
    -DCMAKE_BUILD_TYPE=Release && cmake --build build --target benchmark -j2`";

/// Where cmake puts the program, for the generators we know of.
const CANDIDATES: &[&str] = &[
    "build/bin/benchmark",
    "build/bin/Release/benchmark",
    "build/benchmark/benchmark",
];

impl Box3d {
    pub fn locate() -> Self {
        let Some(dir) = std::env::var_os("BOX3D_DIR") else {
            return Box3d::NotSet;
        };
        let dir = PathBuf::from(dir);
        match CANDIDATES.iter().map(|c| dir.join(c)).find(|p| p.is_file()) {
            Some(exe) => Box3d::Ready(exe),
            None => Box3d::Missing(format!(
                "BOX3D_DIR={} has no built benchmark program (looked for {})",
                dir.display(),
                CANDIDATES.join(", ")
            )),
        }
    }
}

/// One run of one of Box3D's benchmarks.
#[derive(Clone, Debug)]
pub struct Box3dRun {
    /// The scene's steps, as it printed them (the first is not timed).
    pub steps: usize,
    /// Wall time of the timed steps over their number (steps − 1), ms.
    pub ms_per_step: f64,
    /// Its counters line: "body … / shape … / contact … / joint … / stack …".
    pub counters: String,
}

/// Runs benchmark `name` once on one thread and reads its output.
pub fn run(exe: &Path, name: &str) -> Result<Box3dRun, String> {
    let stdout = run_program(exe, name, &[], &scratch_dir()?)?;
    parse(&stdout, name)
}

/// Box3D's own profile of one step (its `b3Profile`, as `-s` writes it), ms.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepProfile {
    pub step: f64,
    /// Its broad phase: the pairs' update.
    pub pairs: f64,
    /// Its narrow phase.
    pub collide: f64,
    /// Its solver stage, the integration of the bodies included.
    pub constraints: f64,
}

/// Runs benchmark `name` once on one thread with its profile per step on (`-s`), and reads
/// the profile it writes, a line per step, the untimed first step included.
pub fn profile(exe: &Path, name: &str) -> Result<Vec<StepProfile>, String> {
    let scratch = scratch_dir()?;
    let path = scratch.join(format!("{name}_t1.dat"));
    // An earlier run's file must not pass for this run's.
    match std::fs::remove_file(&path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            return Err(format!("{}: {e}", path.display()));
        }
        _ => {}
    }
    run_program(exe, name, &["-s"], &scratch)?;
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse_profile(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// The directory the program runs in: it writes its files into its working directory.
fn scratch_dir() -> Result<PathBuf, String> {
    let scratch = std::env::temp_dir().join("peer-bench-box3d");
    std::fs::create_dir_all(&scratch).map_err(|e| format!("{}: {e}", scratch.display()))?;
    Ok(scratch)
}

/// Runs the program on benchmark `name` with `extra` arguments in `scratch`; returns what
/// it printed.
fn run_program(exe: &Path, name: &str, extra: &[&str], scratch: &Path) -> Result<String, String> {
    let output = Command::new(exe)
        .args(["-t=1", &format!("-b={name}"), "-r=1"])
        .args(extra)
        .current_dir(scratch)
        .output()
        .map_err(|e| format!("could not run {}: {e}", exe.display()))?;
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    if !output.status.success() {
        return Err(format!(
            "{} -b={name} failed ({}): {}",
            exe.display(),
            output.status,
            stdout.trim()
        ));
    }
    Ok(stdout)
}

/// Reads the lines `-s` writes: step, pairs, collide, constraints, transforms, refit and
/// sleep islands, ms, separated by spaces.
pub fn parse_profile(text: &str) -> Result<Vec<StepProfile>, String> {
    let line_profile = |(k, line): (usize, &str)| {
        let values: Vec<f64> = (line.split_whitespace().map(str::parse))
            .collect::<Result<_, _>>()
            .map_err(|e| format!("line {}: {e}", k + 1))?;
        match values[..] {
            [step, pairs, collide, constraints, _, _, _] => Ok(StepProfile {
                step,
                pairs,
                collide,
                constraints,
            }),
            _ => Err(format!("line {}: {} values, not 7", k + 1, values.len())),
        }
    };
    let steps: Vec<StepProfile> = text
        .lines()
        .enumerate()
        .map(line_profile)
        .collect::<Result<_, _>>()?;
    if steps.len() < 2 {
        return Err(format!("{} steps profiled: none timed", steps.len()));
    }
    Ok(steps)
}

/// Reads `benchmark: <name>, steps = <n>`, `run 0 : <ms> (ms)` and the counters line.
pub fn parse(stdout: &str, name: &str) -> Result<Box3dRun, String> {
    let header = format!("benchmark: {name}, steps = ");
    let steps: usize = stdout
        .lines()
        .find_map(|line| line.strip_prefix(&header))
        .and_then(|n| n.trim().parse().ok())
        .ok_or_else(|| format!("no line `{header}<n>` in Box3D's output:\n{stdout}"))?;
    let ms: f64 = stdout
        .lines()
        .find_map(|line| {
            let rest = line.strip_prefix("run ")?;
            let (_, value) = rest.split_once(" : ")?;
            value.strip_suffix(" (ms)")?.trim().parse().ok()
        })
        .ok_or_else(|| format!("no line `run 0 : <ms> (ms)` in Box3D's output:\n{stdout}"))?;
    let counters = stdout
        .lines()
        .find(|line| line.starts_with("body "))
        .unwrap_or("")
        .to_owned();
    if steps < 2 {
        return Err(format!("Box3D ran {steps} steps: none timed"));
    }
    Ok(Box3dRun {
        steps,
        ms_per_step: ms / (steps - 1) as f64,
        counters,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What `benchmark -t=1 -b=large_pyramid -r=1` printed (Box3D 30c67b5).
    const OUTPUT: &str = "Starting benchmarks
======================================
benchmark: large_pyramid, steps = 200
thread count: 1
run 0 : 2683.18 (ms)
body 5051 / shape 5051 / contact 14950 / joint 0 / stack 6364816

======================================
All benchmarks complete!
";

    #[test]
    fn reads_the_programs_output() {
        let run = parse(OUTPUT, "large_pyramid").expect("parses");
        assert_eq!(run.steps, 200);
        assert!((run.ms_per_step - 2683.18 / 199.0).abs() < 1e-12);
        assert_eq!(
            run.counters,
            "body 5051 / shape 5051 / contact 14950 / joint 0 / stack 6364816"
        );
        assert!(parse(OUTPUT, "many_pyramids").is_err());
        assert!(parse("run 0 : 1e+06 (ms)\nbenchmark: x, steps = 11\n", "x").is_ok());
    }

    /// The first three lines `benchmark -t=1 -b=convex_pile -s -r=1` wrote (Box3D 30c67b5).
    const PROFILE: &str = "2.89047 1.1114 0.000538 1.20808 0.549295 0.00065 0.003755
1.44384 5.8e-05 0.000251 1.02556 0.410531 0.000585 0.0037
1.56739 2.1e-05 0.000207 1.19059 0.370514 0.000495 0.00375
";

    #[test]
    fn reads_the_programs_profile() {
        let steps = parse_profile(PROFILE).expect("parses");
        assert_eq!(steps.len(), 3);
        assert_eq!(
            steps[1],
            StepProfile {
                step: 1.44384,
                pairs: 5.8e-05,
                collide: 0.000251,
                constraints: 1.02556,
            }
        );
        assert!(
            parse_profile("0.6 0.01 0.04 0.4 0.02 0.08\n0.6 0.01 0.04 0.4 0.02 0.08\n").is_err()
        );
        assert!(
            parse_profile("0.6 0.01 x 0.4 0.02 0.08 0.0\n0.6 0.01 0.04 0.4 0.02 0.08 0.0\n")
                .is_err()
        );
        assert!(parse_profile(PROFILE.lines().next().unwrap()).is_err());
    }
}
