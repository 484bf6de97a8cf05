//! A fresh folder for a unit test's files. Test support only: never part of the program,
//! and nothing here may hide what a test is about (it makes the folder, nothing in it).

use std::path::PathBuf;

/// `drivescript-NAME-PID` in the system's temporary folder, emptied and created: a test
/// run never sees the files of an earlier one.
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("drivescript-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch folder in the temporary folder");
    dir
}
