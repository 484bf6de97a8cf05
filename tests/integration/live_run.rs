//! The built binary running in the background, its output read as it comes, for the
//! tests that signal a run in the middle; and the Ctrl-C during a dwell that several
//! families' tests share.

use crate::support::{assert_has, repo_root, scratch_file, Simulator};
#[cfg(unix)]
use crate::support::{command, send_signal};
use std::path::Path;
use std::process::Stdio;

/// `drivescript ARGS` running in the background (from the repository root), its standard
/// output read as it comes: for the tests that signal a run in the middle. Every wait is
/// bounded: a run that neither prints nor ends fails its test, never holds the suite up.
pub struct LiveRun {
    child: std::process::Child,
    /// What a reader thread took from the run's standard output, as it came; closed at
    /// its end.
    out: std::sync::mpsc::Receiver<String>,
    stderr: Option<std::process::ChildStderr>,
    seen: String,
    /// Under Wine, the name by which the Linux side finds its process to interrupt.
    #[cfg(windows)]
    mark: crate::wine_host::Marked,
}

/// How long a run may print nothing new while a test waits for its output or its end.
const QUIET_LIMIT: std::time::Duration = std::time::Duration::from_secs(60);

impl LiveRun {
    /// `drivescript run FILE --port PORT`, then flags that each take a path (`--trace`).
    pub fn run_on(file: &Path, port: &str, path_flags: &[(&str, &Path)]) -> LiveRun {
        let mut args: Vec<&std::ffi::OsStr> =
            vec!["run".as_ref(), file.as_os_str(), "--port".as_ref(), port.as_ref()];
        for (flag, path) in path_flags {
            args.extend([flag.as_ref(), path.as_os_str()]);
        }
        LiveRun::start(args)
    }

    pub fn start<I, S>(args: I) -> LiveRun
    where
        I: IntoIterator<Item = S>,
        S: AsRef<std::ffi::OsStr>,
    {
        LiveRun::with(|command| {
            command.args(args).current_dir(repo_root());
        })
    }

    /// The binary as `set_up` makes its command (arguments, environment, folder).
    pub fn with(set_up: impl FnOnce(&mut std::process::Command)) -> LiveRun {
        #[cfg(unix)]
        let mut command = command();
        #[cfg(windows)]
        let (mut command, mark) = crate::wine_host::marked_command();
        set_up(&mut command);
        let mut child = crate::support::started(command.stdout(Stdio::piped()).stderr(Stdio::piped()));
        let mut stdout = child.stdout.take().expect("stdout is piped");
        let (sender, out) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            use std::io::Read;
            let mut buf = [0u8; 512];
            while let Ok(n @ 1..) = stdout.read(&mut buf) {
                if sender
                    .send(String::from_utf8_lossy(&buf[..n]).into_owned())
                    .is_err()
                {
                    break;
                }
            }
        });
        LiveRun {
            stderr: child.stderr.take(),
            child,
            out,
            seen: String::new(),
            #[cfg(windows)]
            mark,
        }
    }

    /// The run's standard error, for a test that reads it (once; piped and unread
    /// otherwise).
    pub fn take_stderr(&mut self) -> std::process::ChildStderr {
        self.stderr.take().expect("standard error is taken once")
    }

    /// Reads the output until it holds `text` (at most 30 s); fails the test otherwise.
    #[track_caller]
    pub fn wait_for(&mut self, text: &str) -> &str {
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
        while !self.seen.contains(text) {
            let left = deadline.saturating_duration_since(std::time::Instant::now());
            match self.out.recv_timeout(left) {
                Ok(more) => self.seen.push_str(&more),
                Err(_) => break,
            }
        }
        assert_has(&self.seen, &[text]);
        &self.seen
    }

    /// Sends signal `name` (`INT`, `TERM`, …) to the run. Under Wine: `INT` is Ctrl-C,
    /// the console event Wine makes of a SIGINT its process receives from the Linux side;
    /// `KILL` ends it as the Task Manager does; Windows has no other.
    pub fn signal(&self, name: &str) {
        #[cfg(unix)]
        send_signal(&self.child, name);
        #[cfg(windows)]
        match name {
            "INT" => crate::wine_host::interrupt(&self.mark.mark),
            // As the Task Manager ends a process (exit code 1); Wine's `taskkill /F`
            // leaves exit code 0, which reads as a success.
            "KILL" => {
                use std::os::windows::io::AsRawHandle;
                #[link(name = "kernel32")]
                extern "system" {
                    fn TerminateProcess(process: std::os::windows::io::RawHandle, code: u32) -> i32;
                }
                // SAFETY: the handle is the child's own, open while `self` holds it.
                let ended = unsafe { TerminateProcess(self.child.as_raw_handle(), 1) };
                assert_ne!(ended, 0, "TerminateProcess: {}", std::io::Error::last_os_error());
            }
            _ => panic!("Windows has no signal {name}"),
        }
    }

    /// Ctrl-C once the output holds `text` and `pause` more has passed, then the end: what
    /// the run had printed before the signal, its exit code and all it printed.
    #[track_caller]
    pub fn interrupt_after(
        mut self,
        text: &str,
        pause: std::time::Duration,
    ) -> (String, Option<i32>, String) {
        let before = self.wait_for(text).to_string();
        std::thread::sleep(pause);
        self.signal("INT");
        let (code, all) = self.finish();
        (before, code, all)
    }

    /// Waits for the run to end: its exit code and all it wrote to standard output. A run
    /// that prints nothing for [`QUIET_LIMIT`] without ending is killed and fails the test.
    #[track_caller]
    pub fn finish(mut self) -> (Option<i32>, String) {
        loop {
            match self.out.recv_timeout(QUIET_LIMIT) {
                Ok(more) => self.seen.push_str(&more),
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => break,
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                    let _ = self.child.kill();
                    panic!(
                        "the run neither ended nor printed for {QUIET_LIMIT:?}; killed:\n{}",
                        self.seen
                    );
                }
            }
        }
        let code = self.child.wait().expect("the run ends").code();
        (code, std::mem::take(&mut self.seen))
    }
}

/// A test that fails half way leaves no program running behind it.
impl Drop for LiveRun {
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// A run that enables `drive`, sets `speed` (`300 rpm`) and dwells an hour, on the pty of
/// a `simulate --drive DRIVE --pty` at 9600 baud with odd parity (not the family's
/// default, so the run is seen to use them), interrupted by Ctrl-C `pause` after the
/// setpoint was written. Fails unless it showed the drive's `address` on the pty at 9600
/// baud and the family's `framing` (`7O1`) before the signal, then the safe stop's
/// `stopped` lines, `INTERRUPTED` and the exit code 130. The simulator, still serving, to
/// read the drive back.
pub fn ctrl_c_during_a_dwell(
    (drive, speed): (&str, &str),
    pause: std::time::Duration,
    (address, framing): (&str, &str),
    stopped: &[&str],
) -> Simulator {
    let sim = Simulator::pty(&["--drive", drive]);
    let port = sim.endpoint.as_str();
    let (_, recipe) = scratch_file(
        &format!("ctrl-c-{drive}"),
        "run.yaml",
        &format!(
            "name: Ctrl-C during a dwell\ndrive: {drive}\nsteps:\n  - go_to: {{ state: operation_enabled, timeout: 2 s }}\n  - set: {{ speed_setpoint: {speed} }}\n  - dwell: 1 h\n"
        ),
    );
    let recipe = recipe.to_string_lossy().to_string();
    let args = [
        "run", &recipe, "--port", port, "--baud", "9600", "--parity", "odd",
    ];
    let (seen, code, all) = LiveRun::start(args).interrupt_after("set speed_setpoint", pause);
    assert_has(&seen, &[&format!("{address} on {port} at 9600 {framing}")]);
    assert_eq!(code, Some(130), "{all}");
    assert_has(&all, &[stopped, &["INTERRUPTED"]].concat());
    sim
}
