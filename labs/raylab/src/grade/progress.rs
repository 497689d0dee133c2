//! What `raylab grade` shows while it runs. On a terminal, a progress bar with what it is
//! doing now; on a log (its standard error not a terminal, where the bar draws nothing), plain
//! lines on standard output instead: one when a submission starts, one per lab built, one per
//! exercise with its status and seconds. The lines of the run's end (each submission's points,
//! the summary) are printed either way.

use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};

/// The progress of a grading run.
pub struct Progress {
    /// The bar, hidden when its output is not a terminal.
    bar: ProgressBar,
    /// Whether the lines of a log are printed (the bar is hidden).
    log: bool,
}

impl Progress {
    /// The progress of grading `submissions` submissions, on the terminal's bar if there is
    /// one, else as lines of a log.
    pub fn new(submissions: usize) -> Self {
        let bar = ProgressBar::new(submissions as u64).with_style(
            ProgressStyle::with_template("grading {bar:30} {pos}/{len} [{elapsed}] {msg}")
                .expect("the progress template is valid"),
        );
        let log = bar.is_hidden();
        Self::with_bar(bar, log)
    }

    /// The progress shown on `bar`, or as lines of a log when `log`.
    fn with_bar(bar: ProgressBar, log: bool) -> Self {
        if !log {
            bar.enable_steady_tick(Duration::from_millis(500));
        }
        Self { bar, log }
    }

    /// What the grader is doing now: the bar's message, and a line of the log when `logged`
    /// (a step that takes time and is said once, not one a line says after it ends).
    pub fn doing(&self, what: String, logged: bool) {
        if self.log && logged {
            println!("{what}");
        }
        self.bar.set_message(what);
    }

    /// A line of the log only: what a step that has ended did (the bar says what comes next).
    pub fn logged(&self, line: impl FnOnce() -> String) {
        if self.log {
            println!("{}", line());
        }
    }

    /// A line printed whether or not the output is a terminal (above the bar on one).
    pub fn line(&self, line: &str) {
        self.bar.suspend(|| println!("{line}"));
    }

    /// A line on standard error whether or not it is a terminal.
    pub fn warn(&self, line: &str) {
        self.bar.suspend(|| eprintln!("{line}"));
    }

    /// One more submission graded.
    pub fn submission_done(&self) {
        self.bar.inc(1);
    }

    /// The run has ended: the bar is cleared.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// Seconds for a line of the log: one decimal.
pub fn seconds(seconds: f64) -> String {
    format!("{seconds:.1} s")
}
