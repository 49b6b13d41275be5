//! Progress of a build: bars on a terminal, a few plain lines otherwise (CI logs stay
//! short: one line when an experiment starts a slow stage and one when it ends).

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::collections::HashMap;
use std::sync::Mutex;

/// Where progress goes.
pub enum Progress {
    /// Bars on the terminal (stderr).
    Bars {
        multi: MultiProgress,
        overall: ProgressBar,
        bars: Mutex<HashMap<String, ProgressBar>>,
    },
    /// Plain lines on stderr.
    Lines,
    /// Nothing.
    Quiet,
}

impl Progress {
    /// Bars when stderr is a terminal, plain lines otherwise (or nothing when `quiet`).
    pub fn new(experiments: usize, quiet: bool) -> Self {
        if quiet {
            return Self::Quiet;
        }
        if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
            return Self::Lines;
        }
        let multi = MultiProgress::with_draw_target(ProgressDrawTarget::stderr_with_hz(8));
        let overall = multi.add(ProgressBar::new(experiments as u64));
        overall.set_style(
            ProgressStyle::with_template(
                "{prefix:>20} [{bar:30}] {pos}/{len} experiments {elapsed}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
        );
        overall.set_prefix("build");
        overall.enable_steady_tick(std::time::Duration::from_millis(250));
        Self::Bars {
            multi,
            overall,
            bars: Mutex::new(HashMap::new()),
        }
    }

    fn bar(&self, exp: &str) -> Option<ProgressBar> {
        let Self::Bars { multi, bars, .. } = self else {
            return None;
        };
        let mut bars = bars.lock().unwrap_or_else(|e| e.into_inner());
        Some(
            bars.entry(exp.to_string())
                .or_insert_with(|| {
                    let b = multi.add(ProgressBar::new(0));
                    b.set_style(
                        ProgressStyle::with_template("{prefix:>20} [{bar:30}] {pos}/{len} {msg}")
                            .unwrap_or_else(|_| ProgressStyle::default_bar())
                            .progress_chars("=> "),
                    );
                    b.set_prefix(exp.to_string());
                    b
                })
                .clone(),
        )
    }

    /// `exp` begins `stage` (`what` says what it does, e.g. "rendering 3249 frames").
    pub fn stage(&self, exp: &str, stage: &str, what: &str) {
        match self {
            Self::Bars { .. } => {
                if let Some(b) = self.bar(exp) {
                    b.set_position(0);
                    b.set_length(0);
                    b.set_message(format!("{stage}: {what}"));
                }
            }
            Self::Lines => eprintln!("{exp}: {stage}: {what}"),
            Self::Quiet => {}
        }
    }

    /// `done` of `total` frames of the current stage.
    pub fn frames(&self, exp: &str, done: u64, total: Option<u64>) {
        if let Some(b) = self.bar(exp) {
            // Without a count (or with a header's wrong one) the bar grows with the
            // frames measured, so it never reads 0/0 or stops short.
            let len = b.length().unwrap_or(0);
            b.set_length(total.unwrap_or(len).max(done));
            b.set_position(done);
        }
    }

    /// `exp` is finished; `line` says how (printed above the bars on a terminal).
    pub fn finish(&self, exp: &str, line: &str) {
        match self {
            Self::Bars {
                multi,
                overall,
                bars,
            } => {
                let b = bars.lock().unwrap_or_else(|e| e.into_inner()).remove(exp);
                if let Some(b) = b {
                    b.finish_and_clear();
                    multi.remove(&b);
                }
                let _ = multi.println(format!("{exp}: {line}"));
                overall.inc(1);
            }
            Self::Lines => eprintln!("{exp}: {line}"),
            Self::Quiet => {}
        }
    }

    /// Remove the bars (before the final table is printed).
    pub fn clear(&self) {
        if let Self::Bars { multi, overall, .. } = self {
            overall.finish_and_clear();
            let _ = multi.clear();
        }
    }
}
