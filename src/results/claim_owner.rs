//! Whether the process that claimed a spool for delivery (`FILE.sending-PID`) is gone, so
//! that its claim may be taken back: asked of the system, never guessed from the clock
//! where the system can tell. Must not touch the claim's records.

use std::path::Path;

/// Whether the process `pid` that made the claim `path` is gone.
#[cfg(unix)]
pub(super) fn gone(pid: u32, _path: &Path) -> bool {
    if pid == std::process::id() {
        return false;
    }
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return true;
    };
    // SAFETY: signal 0 only asks whether the process exists; nothing is sent.
    let alive = unsafe { libc::kill(pid, 0) } == 0
        || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM);
    !alive
}

/// Windows hands a process id to the next process soon after one ends, so a process
/// that holds the number is the claim's maker only if it started before the claim was
/// made (each claim is touched when made): one that started later, this one included,
/// holds a number the maker left behind. A process this one may not ask about (access
/// denied: another user's, a protected one) says nothing either way: then the claim's age
/// decides, as where the system cannot be asked at all.
#[cfg(windows)]
pub(super) fn gone(pid: u32, path: &Path) -> bool {
    let Some(claimed) = std::fs::metadata(path).and_then(|m| m.modified()).ok() else {
        // Gone already (another delivery took it): nothing of it is left to take.
        return false;
    };
    match process::asked(pid) {
        process::Owner::Running { started } => started > claimed,
        process::Owner::Ended => true,
        process::Owner::Unknown => untouched_for_long(path),
    }
}

#[cfg(windows)]
mod process {
    use std::ffi::c_void;
    use std::time::{Duration, SystemTime};

    #[repr(C)]
    #[derive(Default, Clone, Copy)]
    struct FileTime {
        low: u32,
        high: u32,
    }

    #[link(name = "kernel32")]
    extern "system" {
        fn OpenProcess(access: u32, inherit: i32, pid: u32) -> *mut c_void;
        fn GetExitCodeProcess(process: *mut c_void, code: *mut u32) -> i32;
        fn GetProcessTimes(
            process: *mut c_void,
            creation: *mut FileTime,
            exit: *mut FileTime,
            kernel: *mut FileTime,
            user: *mut FileTime,
        ) -> i32;
        fn CloseHandle(handle: *mut c_void) -> i32;
    }

    const PROCESS_QUERY_LIMITED_INFORMATION: u32 = 0x1000;
    const STILL_ACTIVE: u32 = 259;
    const ERROR_ACCESS_DENIED: i32 = 5;
    /// From 1601-01-01 (FILETIME's start) to 1970-01-01, in 100 ns.
    const UNIX_EPOCH_AS_FILETIME: u64 = 116_444_736_000_000_000;

    /// What Windows says of the process `pid`.
    pub enum Owner {
        /// One by that number runs; it started then.
        Running { started: SystemTime },
        /// None by that number runs.
        Ended,
        /// Windows refused to say (access denied), or did not say when it started.
        Unknown,
    }

    pub fn asked(pid: u32) -> Owner {
        // SAFETY: OpenProcess has no precondition; a null handle is checked below.
        let handle = unsafe { OpenProcess(PROCESS_QUERY_LIMITED_INFORMATION, 0, pid) };
        if handle.is_null() {
            let denied = std::io::Error::last_os_error().raw_os_error() == Some(ERROR_ACCESS_DENIED);
            return if denied { Owner::Unknown } else { Owner::Ended };
        }
        let (mut code, mut times) = (0u32, [FileTime::default(); 4]);
        let [creation, exit, kernel, user] = &mut times;
        // SAFETY: the handle is open until CloseHandle below; the out-pointers live here.
        let (running, timed) = unsafe {
            let running = GetExitCodeProcess(handle, &mut code) != 0 && code == STILL_ACTIVE;
            let timed = GetProcessTimes(handle, creation, exit, kernel, user) != 0;
            CloseHandle(handle);
            (running, timed)
        };
        if !running {
            return Owner::Ended;
        }
        if !timed {
            // Without its start time a process of that number cannot be told from a later
            // one that reused it: the claim's age decides.
            return Owner::Unknown;
        }
        let ticks = ((u64::from(times[0].high) << 32) | u64::from(times[0].low))
            .saturating_sub(UNIX_EPOCH_AS_FILETIME);
        let started = SystemTime::UNIX_EPOCH + Duration::from_nanos(ticks.saturating_mul(100));
        Owner::Running { started }
    }
}

/// Without a way to ask about a process, a claim untouched for ten minutes (a delivery
/// takes seconds) is taken as left by a process that is gone.
#[cfg(not(any(unix, windows)))]
pub(super) fn gone(_pid: u32, path: &Path) -> bool {
    untouched_for_long(path)
}

/// Whether the claim `path` was last touched more than [`CLAIM_AGE_LIMIT`] ago.
#[cfg_attr(unix, allow(dead_code))]
fn untouched_for_long(path: &Path) -> bool {
    std::fs::metadata(path)
        .and_then(|m| m.modified())
        .ok()
        .and_then(|t| t.elapsed().ok())
        .is_some_and(|age| age > CLAIM_AGE_LIMIT)
}

/// How long a claim whose maker cannot be asked about is left alone: a delivery takes
/// seconds.
const CLAIM_AGE_LIMIT: std::time::Duration = std::time::Duration::from_secs(600);

#[cfg(test)]
mod tests {
    use super::*;

    /// A claim file `name` in a fresh folder of this process named after `folder`:
    /// (the folder, the claim).
    fn claim_in(folder: &str, name: &str) -> (std::path::PathBuf, std::path::PathBuf) {
        let dir = std::env::temp_dir().join(format!("{folder}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let claim = dir.join(name);
        std::fs::write(&claim, "{}\n").unwrap();
        (dir, claim)
    }

    /// The rule for a maker the system will not tell about: a fresh claim is left, one
    /// untouched beyond the limit is taken back.
    #[test]
    fn a_claim_is_taken_back_by_its_age_only_beyond_the_limit() {
        let (dir, claim) = claim_in("drivescript-claim-age", "results.spool.sending-4");
        assert!(!untouched_for_long(&claim), "a fresh claim");
        let file = std::fs::OpenOptions::new().write(true).open(&claim).unwrap();
        let old = std::time::SystemTime::now() - CLAIM_AGE_LIMIT - std::time::Duration::from_secs(5);
        file.set_modified(old).unwrap();
        drop(file);
        assert!(untouched_for_long(&claim), "a claim older than the limit");
        assert!(
            !untouched_for_long(&dir.join("gone")),
            "no claim, nothing to take"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Windows: a claim by a process that runs and started before it is kept; one whose
    /// number no process holds is taken back at once.
    #[cfg(windows)]
    #[test]
    fn a_claim_of_a_running_maker_is_kept_and_of_an_ended_one_taken_back() {
        let (dir, claim) = claim_in("drivescript-claim-owner", "results.spool.sending");
        assert!(!gone(std::process::id(), &claim), "this process made it");
        let mut child = std::process::Command::new(std::env::current_exe().unwrap())
            .arg("--list")
            .stdout(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let pid = child.id();
        child.wait().unwrap();
        assert!(gone(pid, &claim), "its maker ended");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
