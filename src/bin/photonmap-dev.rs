//! Development and benchmark binary: `cargo run --release -- render [scene.json] -o out.exr`.
//! The user-facing `photonmap` command (Python package) takes the same arguments.

use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};
use photonmap::cli::{run_render, Cli, Command};
use std::sync::Arc;

fn main() {
    let cli = Cli::parse();
    let Command::Render(args) = cli.command;
    let bar = if args.quiet {
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
    let progress: Arc<photonmap::render::ProgressFn> = Arc::new(move |f: f32, phase: &str| {
        pb.set_message(phase.to_string());
        pb.set_position((f * 1000.0) as u64);
    });
    match run_render(&args, Some(progress)) {
        Ok(out) => {
            bar.finish_and_clear();
            if !args.quiet {
                let secs: f64 = out.stats.seconds.values().sum();
                eprintln!(
                    "wrote {} ({}x{}, {} spp, {:.2} s)",
                    args.output.display(),
                    out.stats.width,
                    out.stats.height,
                    out.stats.spp,
                    secs
                );
                for s in &out.stats.skipped {
                    eprintln!("  {} is zero: {}", s.term, s.reason);
                }
            }
        }
        Err(e) => {
            bar.abandon();
            eprintln!("photonmap: error: {e}");
            std::process::exit(1);
        }
    }
}
