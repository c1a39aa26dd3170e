//! Development and benchmark binary: `cargo run --release -- render [scene.json] -o out.exr`.
//! The user-facing `photonmap` command (Python package) takes the same arguments.

use clap::Parser;
use photonmap::cli::{progress_bar, run_merge, run_render, summary, Cli, Command};

fn main() {
    let cli = Cli::parse();
    let args = match cli.command {
        Command::Render(args) => args,
        Command::Merge(m) => {
            match run_merge(&m) {
                Ok(p) if !m.quiet => eprintln!(
                    "wrote {} ({} passes from {} partial sums)",
                    m.output.display(),
                    p.passes(),
                    m.partials.len()
                ),
                Ok(_) => {}
                Err(e) => {
                    eprintln!("photonmap: error: {e}");
                    std::process::exit(1);
                }
            }
            return;
        }
    };
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
