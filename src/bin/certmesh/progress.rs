//! The command line's progress display: one indicatif bar (or spinner) on stderr that
//! implements the library's [`Progress`] trait, so meshers, the comparison harness and
//! the CLI's own phases (fidelity sampling, writing) all draw on it.
//!
//! It is hidden with `--quiet` and whenever stderr is not a terminal (pipes, CI logs,
//! the tests), so it never mixes with reports or JSON. A spinner ticks on its own, so a
//! phase that reports no steps still shows that the run is alive and how long it took.
use certmesh::mesher::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::Duration;

/// How often a spinner redraws when the work reports nothing.
const TICK: Duration = Duration::from_millis(120);

/// An indicatif bar on stderr (hidden with `--quiet` or when stderr is not a terminal).
pub struct Bar {
    pb: ProgressBar,
    visible: bool,
}

impl Bar {
    pub fn new(quiet: bool) -> Self {
        let visible = !quiet && std::io::stderr().is_terminal();
        let pb = ProgressBar::with_draw_target(
            None,
            if visible {
                ProgressDrawTarget::stderr()
            } else {
                ProgressDrawTarget::hidden()
            },
        );
        Bar { pb, visible }
    }

    /// Begin a phase whose length is unknown (a ticking spinner with the elapsed time).
    pub fn phase(&self, name: &str) {
        self.start(name, 0);
    }
}

impl Progress for Bar {
    fn start(&self, phase: &str, total: u64) {
        let style = if total > 0 {
            ProgressStyle::with_template(
                "{spinner} {msg:>12} [{bar:40}] {pos}/{len} ({elapsed}, eta {eta})",
            )
            .expect("valid template")
            .progress_chars("=> ")
        } else {
            ProgressStyle::with_template("{spinner} {msg:>12} ({elapsed})").expect("valid template")
        };
        self.pb.set_style(style);
        self.pb.set_message(phase.to_string());
        if total > 0 {
            self.pb.set_length(total);
        } else {
            self.pb.unset_length();
        }
        self.pb.reset();
        if self.visible {
            self.pb.enable_steady_tick(TICK);
        }
    }
    fn inc(&self, n: u64) {
        // A hidden bar's position is never read, and indicatif reads the clock on
        // every step (a marching mesher steps once per grid row).
        if self.visible {
            self.pb.inc(n);
        }
    }
    fn finish(&self) {
        self.pb.finish_and_clear();
    }
}

impl Drop for Bar {
    fn drop(&mut self) {
        self.pb.finish_and_clear();
    }
}
