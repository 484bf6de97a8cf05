//! The command line: argument parsing and one module per subcommand. Turns results into
//! text and exit codes; must not build telegrams or touch ports itself.

mod decode_command;
mod exit_code;

pub use exit_code::*;

use clap::{Parser, Subcommand};

/// Commission and test servo and spindle drives over their serial protocols.
#[derive(Debug, Parser)]
#[command(name = "drivescript", version, about, max_term_width = 100)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    Decode(decode_command::DecodeArgs),
}

/// Runs the command line and returns the process exit code.
pub fn main() -> i32 {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() { INVALID } else { PASSED };
        }
    };
    match cli.command {
        Command::Decode(args) => decode_command::run(&args),
    }
}
