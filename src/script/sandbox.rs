//! The Rhai engine a script runs in: no modules (the crate is built with `no_module`), no
//! `eval`, no file system or process access (Rhai has none unless given, and nothing here
//! gives it; `sample` writes its CSV files only under `--output-dir`, at most
//! [`MAX_CSV_FILES`]), and limits on call depth, expression depth and the sizes of strings, arrays
//! and maps. The operation limit counts operations *between drive calls*, so an endless
//! loop that never talks to the drive ends with a clear message while a run-in that loops
//! for hours (talking to the drive) does not. It must not know the drive API.

use rhai::Engine;

/// Operations a script may run without calling the drive (about a second of computing).
pub const MAX_OPERATIONS_BETWEEN_CALLS: u64 = 5_000_000;
/// Nested calls of script functions.
pub const MAX_CALL_LEVELS: usize = 64;
/// Nesting of expressions, at the top level and inside functions.
pub const MAX_EXPR_DEPTH: usize = 64;
pub const MAX_FUNCTION_EXPR_DEPTH: usize = 32;
/// Bytes of one string.
pub const MAX_STRING_SIZE: usize = 64 * 1024;
/// Items of one array (a sample window's `values` too).
pub const MAX_ARRAY_SIZE: usize = 100_000;
/// Entries of one map.
pub const MAX_MAP_SIZE: usize = 10_000;
/// Variables in scope and functions a script may define.
pub const MAX_VARIABLES: usize = 1_000;
pub const MAX_FUNCTIONS: usize = 256;
/// CSV files one run's `sample` calls may write (each under `--output-dir`).
pub const MAX_CSV_FILES: usize = 1_000;

/// The sandboxed engine without the drive API (enough to parse a script for `check`).
pub fn sandbox() -> Engine {
    let mut engine = Engine::new();
    engine
        .set_max_call_levels(MAX_CALL_LEVELS)
        .set_max_expr_depths(MAX_EXPR_DEPTH, MAX_FUNCTION_EXPR_DEPTH)
        .set_max_string_size(MAX_STRING_SIZE)
        .set_max_array_size(MAX_ARRAY_SIZE)
        .set_max_map_size(MAX_MAP_SIZE)
        .set_max_variables(MAX_VARIABLES)
        .set_max_functions(MAX_FUNCTIONS)
        // A script reads what it is given; it must not compile and run text it builds.
        .disable_symbol("eval")
        // Rhai's `print` and `debug` write to standard output by default; the drive API
        // routes them to the run's reports instead. Until then they say nothing.
        .on_print(|_| {})
        .on_debug(|_, _, _| {});
    engine
}
