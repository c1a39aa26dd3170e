//! Development and benchmark binary: `cargo run --release -- render [scene.json] -o out.exr`.
//! The user-facing `photonmap` command (Python package) takes the same arguments.

use clap::Parser;
use photonmap::cli::{progress_bar, run_render, summary, Cli, Command};

fn main() {
    let cli = Cli::parse();
    let Command::Render(args) = cli.command;
    let (bar, progress) = progress_bar(args.quiet);
    match run_render(&args, Some(progress)) {
        Ok(out) => {
            bar.finish_and_clear();
            if !args.quiet {
                eprintln!("{}", summary(&args, &out));
            }
        }
        Err(e) => {
            bar.abandon();
            eprintln!("photonmap: error: {e}");
            std::process::exit(1);
        }
    }
}
