//! Removes the scratch folders and files that earlier test processes left in the system's
//! temporary folder. Tests name theirs `drivescript-…-PID` after their own process; a test
//! process that is killed (a kill campaign, a cancelled `cargo test`, a timeout) cannot
//! remove its own, so the next test process removes those whose processes are gone. It
//! must never touch the scratch of a process that still runs.

use std::path::Path;
use std::sync::Once;

/// Removes, once per test process, every `drivescript-…` entry of the temporary folder
/// that names only processes that are gone.
pub fn sweep_once() {
    static SWEPT: Once = Once::new();
    SWEPT.call_once(|| sweep(&std::env::temp_dir(), process_gone));
}

/// Removes the `drivescript-…` entries of `dir` whose numbers all name processes that
/// `gone` says have ended. An entry without a number is nobody's scratch and stays.
fn sweep(dir: &Path, gone: impl Fn(u32) -> bool) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let pids = pids_in(name);
        if pids.is_empty() || !pids.iter().all(|pid| gone(*pid)) {
            continue;
        }
        let path = entry.path();
        // A test's PostgreSQL server runs as another user and outlives a killed test
        // process: its data stays while the server runs.
        if server_pid(&path).is_some_and(|pid| !gone(pid)) {
            continue;
        }
        // Another test process may sweep the same entry at the same time; either removal
        // is as good.
        let _ = if path.is_dir() {
            std::fs::remove_dir_all(&path)
        } else {
            std::fs::remove_file(&path)
        };
    }
}

/// The process id of the PostgreSQL server whose data a test keeps in `scratch/data`.
fn server_pid(scratch: &Path) -> Option<u32> {
    let text = std::fs::read_to_string(scratch.join("data/postmaster.pid")).ok()?;
    text.lines().next()?.trim().parse().ok()
}

/// The numbers a test put in a scratch name `drivescript-PART-…`: the process id, and
/// any number of the test's own (`drivescript-eds-1252-PID`). A number that is not a
/// process's only keeps the entry longer, never removes one in use.
fn pids_in(name: &str) -> Vec<u32> {
    let Some(rest) = name.strip_prefix("drivescript-") else {
        return Vec::new();
    };
    let stem = rest.split('.').next().unwrap_or(rest);
    stem.split('-').filter_map(|part| part.parse().ok()).collect()
}

#[cfg(unix)]
fn process_gone(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return true;
    };
    if pid <= 0 {
        return false;
    }
    // SAFETY: signal 0 only asks whether the process exists; nothing is sent.
    let alive = unsafe { libc::kill(pid, 0) } == 0
        || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM);
    !alive
}

/// Without a cheap way to ask about a process, nothing is taken as gone.
#[cfg(not(unix))]
fn process_gone(_pid: u32) -> bool {
    false
}

#[test]
fn scratch_of_ended_processes_is_removed_and_of_running_ones_kept() {
    let root = std::env::temp_dir().join(format!("drivescript-sweep-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let make = |name: &str| {
        let dir = root.join(name);
        std::fs::create_dir_all(dir.join("out")).expect("scratch made");
        std::fs::write(dir.join("out/samples.csv"), "t,v\n").expect("file written");
    };
    make("drivescript-history-wear-111");
    make("drivescript-csv-111-name");
    make("drivescript-eds-1252-222");
    make("drivescript-tests-222");
    make("drivescript-plain");
    make("drivescript-postgres-111");
    std::fs::create_dir_all(root.join("drivescript-postgres-111/data")).expect("data made");
    std::fs::write(
        root.join("drivescript-postgres-111/data/postmaster.pid"),
        "222\n/tmp/data\n",
    )
    .expect("server pid written");
    make("other-111");
    std::fs::write(root.join("drivescript-cyclic-111.trace"), "").expect("trace written");
    sweep(&root, |pid| pid != 222);
    let mut left: Vec<String> = std::fs::read_dir(&root)
        .expect("the sweep's folder")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        [
            "drivescript-eds-1252-222",
            "drivescript-plain",
            "drivescript-postgres-111",
            "drivescript-tests-222",
            "other-111"
        ]
    );
    std::fs::remove_dir_all(&root).expect("the sweep's folder removed");
}

#[cfg(unix)]
#[test]
fn this_process_is_not_gone_and_an_ended_child_is() {
    assert!(!process_gone(std::process::id()));
    let mut child = std::process::Command::new("true").spawn().expect("`true` starts");
    let pid = child.id();
    child.wait().expect("`true` ends");
    assert!(process_gone(pid));
}
