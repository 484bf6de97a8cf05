//! The built binary running in the background, its output read as it comes, for the
//! tests that signal a run in the middle; and the Ctrl-C during a dwell that several
//! families' tests share.

#[cfg(unix)]
use crate::support::{command, send_signal};
use crate::support::{assert_has, repo_root, scratch_file};
use std::path::Path;
use std::process::Stdio;

/// `drivescript ARGS` running in the background (from the repository root), its standard
/// output read as it comes: for the tests that signal a run in the middle.
pub struct LiveRun {
    child: std::process::Child,
    out: std::process::ChildStdout,
    seen: String,
    /// Under Wine, the name by which the Linux side finds its process to interrupt.
    #[cfg(windows)]
    mark: crate::wine_host::Marked,
}

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
        #[cfg(unix)]
        let mut command = command();
        #[cfg(windows)]
        let (mut command, mark) = crate::wine_host::marked_command();
        let mut child = command
            .args(args)
            .current_dir(repo_root())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the run starts");
        let out = child.stdout.take().expect("stdout is piped");
        LiveRun {
            child,
            out,
            seen: String::new(),
            #[cfg(windows)]
            mark,
        }
    }

    /// Reads the output until it holds `text` (at most 30 s); fails the test otherwise.
    pub fn wait_for(&mut self, text: &str) -> &str {
        use std::io::Read;
        let started = std::time::Instant::now();
        let mut buf = [0u8; 512];
        while !self.seen.contains(text) && started.elapsed() < std::time::Duration::from_secs(30) {
            let n = self.out.read(&mut buf).expect("read the run's output");
            if n == 0 {
                break;
            }
            self.seen.push_str(&String::from_utf8_lossy(&buf[..n]));
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

    /// Waits for the run to end: its exit code and all it wrote to standard output.
    pub fn finish(mut self) -> (Option<i32>, String) {
        use std::io::Read;
        self.out
            .read_to_string(&mut self.seen)
            .expect("the rest of the output");
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

/// A run that enables `drive`, sets `speed` (`300 rpm`) and dwells an hour, on `port` at
/// 9600 baud with odd parity (not the family's default, so the run is seen to use them),
/// interrupted by Ctrl-C `pause` after the setpoint was written. Fails unless it showed
/// `connected` (the drive on its port and line settings) before the signal, then the safe
/// stop's `stopped` lines, `INTERRUPTED` and the exit code 130.
pub fn ctrl_c_during_a_dwell(
    (drive, speed): (&str, &str),
    port: &str,
    pause: std::time::Duration,
    connected: &str,
    stopped: &[&str],
) {
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
    assert_has(&seen, &[connected]);
    assert_eq!(code, Some(130), "{all}");
    assert_has(&all, &[stopped, &["INTERRUPTED"]].concat());
}
