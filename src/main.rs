//! The `drivescript` binary: parses the command line and hands over to the library.
fn main() {
    std::process::exit(drivescript::cli::main());
}
