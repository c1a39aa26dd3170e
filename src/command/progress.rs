//! The progress bar of a command on stderr.

use crate::render::ProgressFn;
use std::sync::Arc;

/// The progress bar on stderr (hidden with `--quiet`) and the callback that drives it.
pub fn progress_bar(quiet: bool) -> (indicatif::ProgressBar, Arc<ProgressFn>) {
    use indicatif::{ProgressBar, ProgressStyle};
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::new(1000);
        b.set_style(
            ProgressStyle::with_template(
                "{msg:>8} [{bar:40}] {percent:>3}% {elapsed_precise} eta {eta}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
        );
        b
    };
    let pb = bar.clone();
    let f: Arc<ProgressFn> = Arc::new(move |f: f32, phase: &str| {
        pb.set_message(phase.to_string());
        pb.set_position((f * 1000.0) as u64);
    });
    (bar, f)
}
