//! A long run's progress on stderr, in the style of the field's command-line tools: a bar on
//! a terminal, a plain line every `PROGRESS_INTERVAL` otherwise (a log, a pipe). The headless
//! runner and `rigid record` report with it.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

/// How often a run whose stderr is not a terminal reports its progress, in wall time.
pub const PROGRESS_INTERVAL: Duration = Duration::from_secs(10);

/// A long run's progress on stderr: a bar on a terminal, else a plain line every
/// `PROGRESS_INTERVAL`, so that a run of 10¹² steps says where it is and how long is left.
pub struct Progress {
    bar: Option<ProgressBar>,
    /// What is counted ("steps", "ticks") and how many there are in all.
    unit: &'static str,
    total: u64,
    started: Instant,
    /// Wall time since `started` at which the next plain line is due.
    next_line: Duration,
}

impl Progress {
    /// Progress of `total` things counted as `unit` ("steps", "frames"), from now.
    pub fn new(unit: &'static str, total: u64) -> Self {
        let bar = std::io::stderr().is_terminal().then(|| {
            let template =
                "{elapsed_precise} [{wide_bar}] {human_pos}/{human_len} {msg} ({eta} left)";
            let style = ProgressStyle::with_template(template)
                .unwrap_or_else(|_| ProgressStyle::default_bar());
            ProgressBar::new(total).with_style(style).with_message(unit)
        });
        Progress {
            bar,
            unit,
            total,
            started: Instant::now(),
            next_line: PROGRESS_INTERVAL,
        }
    }

    /// `done` of the total are done.
    pub fn update(&mut self, done: u64) {
        match &self.bar {
            Some(bar) => bar.set_position(done),
            None => {
                if let Some(line) = self.line_due(done, self.started.elapsed()) {
                    eprintln!("{line}");
                }
            }
        }
    }

    /// The plain line to print with `done` done after `elapsed`, if one is due; none
    /// before the first interval has passed, and at most one per interval.
    fn line_due(&mut self, done: u64, elapsed: Duration) -> Option<String> {
        if elapsed < self.next_line {
            return None;
        }
        while self.next_line <= elapsed {
            self.next_line += PROGRESS_INTERVAL;
        }
        let fraction = done as f64 / self.total.max(1) as f64;
        let seconds = elapsed.as_secs_f64();
        let left = if done > 0 {
            format!(", about {:.0} s left", seconds / fraction - seconds)
        } else {
            String::new()
        };
        Some(format!(
            "{} {done} of {} ({:.1} %) after {seconds:.0} s{left}",
            self.unit,
            self.total,
            100.0 * fraction
        ))
    }

    /// A line on stderr, above the bar when there is one.
    pub fn println(&self, line: &str) {
        match &self.bar {
            Some(bar) => bar.println(line),
            None => eprintln!("{line}"),
        }
    }

    /// Takes the bar off the terminal.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Off a terminal, a line is printed once per interval of wall time (the times are given,
    /// not measured), with the count, the share done and the time left.
    #[test]
    fn plain_progress_lines_come_once_per_interval() {
        let mut progress = Progress {
            bar: None,
            unit: "steps",
            total: 1_000_000_000_000,
            started: Instant::now(),
            next_line: PROGRESS_INTERVAL,
        };
        let at = |seconds: u64| Duration::from_secs(seconds);
        assert_eq!(progress.line_due(1_000, at(9)), None);
        assert_eq!(
            progress.line_due(10_000_000_000, at(10)).as_deref(),
            Some("steps 10000000000 of 1000000000000 (1.0 %) after 10 s, about 990 s left")
        );
        assert_eq!(progress.line_due(10_000_000_001, at(19)), None);
        // A step that took several intervals gives one line, and the next is due an
        // interval later.
        assert!(progress.line_due(20_000_000_000, at(45)).is_some());
        assert_eq!(progress.line_due(20_000_000_001, at(49)), None);
        assert!(progress.line_due(25_000_000_000, at(50)).is_some());
    }
}
