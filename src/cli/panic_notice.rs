//! What a user reads when drivescript itself fails (a panic): where, that it is a bug,
//! and that the safe stop runs next. The runner catches the panic and stops the drive;
//! this only replaces Rust's default message, which would say neither.

use std::io::Write;

/// Installs the notice for the rest of the process.
pub fn install() {
    std::panic::set_hook(Box::new(|info| {
        let message = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".to_string());
        let place = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        let _ = writeln!(
            std::io::stderr(),
            "\ninternal error (panic): {message}{place}\nThis is a bug in drivescript; please report it with the command line and the recipe. If a run was under way, its safe stop runs now."
        );
    }));
}
