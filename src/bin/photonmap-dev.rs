//! Development and benchmark binary: `cargo run --release -- render [scene.json] -o out.exr`.
//! The user-facing `photonmap` command (Python package) takes the same arguments and runs the
//! same command (`photonmap::command`).

use photonmap::cli::{Cli, Command};
use photonmap::command::{self, report, Frontend};

fn main() {
    let cli = Cli::parse_args(std::env::args_os()).unwrap_or_else(|e| e.exit());
    match cli.command {
        Command::Merge(m) => match command::run_merge(&m) {
            Ok(p) if !m.quiet => eprintln!("{}", report::merge_summary(&m, &p)),
            Ok(_) => {}
            Err(e) => {
                eprintln!("photonmap: error: {e}");
                std::process::exit(1);
            }
        },
        Command::Render(args) => {
            if let Err(f) = command::run_render(&args, Frontend::default()) {
                eprintln!("photonmap: error: {f}");
                std::process::exit(1);
            }
        }
    }
}
