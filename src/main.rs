//! The `drivescript` binary: builds the registry of drive families once and hands the
//! command line over to the library.
fn main() {
    let registry = drivescript::family::Registry::builtin();
    std::process::exit(drivescript::cli::main(&registry));
}
