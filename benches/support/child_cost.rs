//! What a benchmark's child process cost: its wall time, CPU time and peak resident
//! memory, from `wait4`'s resource usage. Shared by the benchmarks that run the release
//! binary as a user would; measures only, decides nothing.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// What a finished child cost.
pub struct Cost {
    pub wall: Duration,
    /// CPU time in user space (the program's own work).
    pub user: Duration,
    /// CPU time in the kernel (system calls, the pty).
    pub system: Duration,
    pub peak_rss_kb: i64,
}

/// Runs `command` to its end; its standard output and what it cost (from `wait4`).
pub fn measure_child(mut command: Command) -> Result<(String, Cost), String> {
    let started = Instant::now();
    let child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start {command:?}: {e}"))?;
    let pid = child.id() as libc::pid_t;
    let mut output = String::new();
    if let Some(out) = child.stdout {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            output.push_str(&line);
            output.push('\n');
        }
    }
    let (code, cost) = wait_cost(pid, started)?;
    if code != Some(0) {
        return Err(format!("{command:?} failed:\n{output}"));
    }
    Ok((output, cost))
}

/// Waits for the child `pid` (started at `started`) to end: its exit code (`None` when a
/// signal ended it) and what it cost.
pub fn wait_cost(pid: libc::pid_t, started: Instant) -> Result<(Option<i32>, Cost), String> {
    let mut status = 0;
    // SAFETY: an all-zero rusage is a valid value for wait4 to fill in.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: waiting for our own child with valid pointers.
    let waited = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    if waited != pid {
        return Err("wait4 failed".into());
    }
    let code = libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status));
    let time = |t: libc::timeval| Duration::new(t.tv_sec as u64, t.tv_usec as u32 * 1000);
    Ok((
        code,
        Cost {
            wall: started.elapsed(),
            user: time(usage.ru_utime),
            system: time(usage.ru_stime),
            peak_rss_kb: usage.ru_maxrss,
        },
    ))
}
