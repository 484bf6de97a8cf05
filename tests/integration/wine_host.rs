//! The Linux side of the tests that run under Wine, and their way to it: what a Windows
//! process cannot start there itself — a PostgreSQL server (its programs are Linux ones)
//! and a simulated drive on a pseudo-terminal, shown to Wine as a COM port — is started
//! on request by the Linux test binary (`serve_the_tests_under_wine`, which `.ci/windows`
//! runs beside them), each on a TCP connection of its own that it lives as long as. It
//! holds no test logic: the tests are the same on both systems.

/// `HOST:PORT` where the Linux side takes requests; set by `.ci/windows`.
pub const HOST_ENV: &str = "DRIVESCRIPT_WINE_HOST";

/// A `drivescript` command whose process the Linux side can find to interrupt: Wine
/// shows a process to Linux by its program's name alone, so the program is the binary
/// under a name of its own (a hard link beside it, removed with [`Marked`]).
#[cfg(windows)]
pub fn marked_command() -> (std::process::Command, Marked) {
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let binary = std::path::PathBuf::from(env!("CARGO_BIN_EXE_drivescript"));
    // A link left by an earlier test process of the same number (Windows reuses them; a
    // link whose program still ran could not be removed) is passed over: the next name.
    let (mark, link) = loop {
        let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        let mark = format!("drivescript-marked-{}-{n}", std::process::id());
        let link = binary.with_file_name(format!("{mark}.exe"));
        let _ = std::fs::remove_file(&link);
        match std::fs::hard_link(&binary, &link) {
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            linked => linked.expect("link the binary under a name of its own"),
        }
        break (mark, link);
    };
    let mut command = std::process::Command::new(&link);
    command.env("DRIVESCRIPT_RESULTS", crate::support::tests_results_store());
    (command, Marked { mark, link })
}

/// The mark of a [`marked_command`]; its link goes when this is dropped.
#[cfg(windows)]
pub struct Marked {
    pub mark: String,
    link: std::path::PathBuf,
}

#[cfg(windows)]
impl Drop for Marked {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.link);
    }
}

/// Ctrl-C to the run marked `mark`: the Linux side sends its process a SIGINT, which Wine
/// hands to the console's handlers as the CTRL_C_EVENT a console's Ctrl-C is.
#[cfg(windows)]
#[track_caller]
pub fn interrupt(mark: &str) {
    let (_, found) = HostLine::ask(&["interrupt", mark]).expect("Ctrl-C under Wine needs the Linux side");
    assert_ne!(
        found, "0",
        "no process of the run marked {mark} on the Linux side"
    );
}

/// The Linux side: serves requests until it is killed. Ignored in a plain `cargo test`;
/// `.ci/windows` runs it with `--ignored` and `HOST_ENV` and `WINEPREFIX` set.
#[cfg(unix)]
#[test]
#[ignore = "the Linux side of the tests under Wine, run by .ci/windows"]
fn serve_the_tests_under_wine() {
    let address = std::env::var(HOST_ENV).unwrap_or_else(|_| panic!("{HOST_ENV} names where to listen"));
    let prefix = std::path::PathBuf::from(std::env::var_os("WINEPREFIX").expect("WINEPREFIX is set"));
    let listener =
        std::net::TcpListener::bind(&address).unwrap_or_else(|e| panic!("listen on {address}: {e}"));
    // COM1 to COM9 may be the prefix's own; the simulators get COM10 upwards.
    let next_com = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(10));
    for connection in listener.incoming().flatten() {
        let (prefix, next_com) = (prefix.clone(), next_com.clone());
        std::thread::spawn(move || linux::serve(connection, &prefix, &next_com));
    }
}

#[cfg(unix)]
mod linux {
    use crate::support::{PostgresServer, Simulator};
    use std::io::{BufRead, BufReader, Write};
    use std::net::TcpStream;
    use std::path::Path;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// One request: its first line says what (`simulate`, then the arguments of
    /// `drivescript simulate`; or `postgres` and `plain` or `tls` and a name), the
    /// answer is one line; a PostgreSQL server then takes `down` and `up`, each answered
    /// by `ok`. The end of the connection ends what it started.
    pub fn serve(connection: TcpStream, prefix: &Path, next_com: &AtomicUsize) {
        let Ok(clone) = connection.try_clone() else {
            return;
        };
        let (mut lines, mut out) = (BufReader::new(clone), connection);
        let mut line = String::new();
        if lines.read_line(&mut line).unwrap_or(0) == 0 {
            return;
        }
        let words: Vec<String> = line.trim_end().split('\t').map(String::from).collect();
        let words: Vec<&str> = words.iter().map(String::as_str).collect();
        match words.as_slice() {
            ["simulate", args @ ..] => {
                let args: Vec<String> = args.iter().map(|a| linux_path(prefix, a)).collect();
                let args: Vec<&str> = args.iter().map(String::as_str).collect();
                let sim = Simulator::start(&args);
                let n = next_com.fetch_add(1, Ordering::SeqCst);
                let link = prefix.join("dosdevices").join(format!("com{n}"));
                let _ = std::fs::remove_file(&link);
                std::os::unix::fs::symlink(&sim.endpoint, &link).expect("link the COM port to the pty");
                let serving = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(true));
                let kept = keep_line_settable(&sim.endpoint, serving.clone());
                let _ = writeln!(out, "COM{n}");
                while lines.read_line(&mut line).unwrap_or(0) > 0 {}
                serving.store(false, Ordering::SeqCst);
                let _ = kept.map(std::thread::JoinHandle::join);
                let _ = std::fs::remove_file(&link);
                drop(sim);
            }
            ["postgres", kind, name] => {
                let started = match *kind {
                    "tls" => PostgresServer::start_tls(name).map(|(s, ca)| (s, windows_path(&ca))),
                    _ => PostgresServer::start(name).map(|s| (s, String::new())),
                };
                let Some((server, ca)) = started else {
                    return;
                };
                let _ = writeln!(out, "{}\t{ca}", server.url());
                loop {
                    line.clear();
                    if lines.read_line(&mut line).unwrap_or(0) == 0 {
                        break;
                    }
                    match line.trim() {
                        "down" => server.down(),
                        _ => server.up(),
                    }
                    let _ = writeln!(out, "ok");
                }
            }
            ["interrupt", mark] => {
                let found = interrupt(mark);
                let _ = writeln!(out, "{found}");
            }
            _ => {
                let _ = writeln!(out, "unknown request {line:?}");
            }
        }
    }

    /// Lets Wine set parity or 7 data bits on the pty behind a COM port every time it is
    /// opened. A pty holds neither (Linux keeps it 8 bits, no parity), and Linux refuses
    /// with EINVAL a termios change of which nothing can be applied, which is what Wine's
    /// SetCommState asks from the second opening on (the first one also changes the raw
    /// mode's flags): "cannot open COM10: Invalid parameter". So while the port is served,
    /// IMAXBEL (meaningless in raw mode) is set again whenever Wine has cleared it, and
    /// each SetCommState has a flag to change.
    fn keep_line_settable(
        pty: &str,
        serving: std::sync::Arc<std::sync::atomic::AtomicBool>,
    ) -> Option<std::thread::JoinHandle<()>> {
        use std::os::fd::AsRawFd;
        use std::os::unix::fs::OpenOptionsExt;
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(libc::O_NOCTTY | libc::O_NONBLOCK)
            .open(pty)
            .ok()?;
        Some(std::thread::spawn(move || {
            let fd = file.as_raw_fd();
            while serving.load(Ordering::SeqCst) {
                // SAFETY: termios is plain data filled in by tcgetattr on an fd open here.
                unsafe {
                    let mut t: libc::termios = std::mem::zeroed();
                    if libc::tcgetattr(fd, &mut t) == 0 && t.c_iflag & libc::IMAXBEL == 0 {
                        t.c_iflag |= libc::IMAXBEL;
                        libc::tcsetattr(fd, libc::TCSANOW, &t);
                    }
                }
                std::thread::sleep(std::time::Duration::from_millis(2));
            }
        }))
    }

    /// Sends SIGINT to the processes of the program named `mark` (Wine shows a Windows
    /// process to Linux as its program's path, `Z:\…\MARK.exe`); how many there were.
    fn interrupt(mark: &str) -> usize {
        let wanted = format!("\\{mark}.exe");
        let mut found = 0;
        for entry in std::fs::read_dir("/proc").into_iter().flatten().flatten() {
            let Some(pid) = entry.file_name().to_str().and_then(|p| p.parse::<i32>().ok()) else {
                continue;
            };
            let cmdline = std::fs::read(entry.path().join("cmdline")).unwrap_or_default();
            let program = cmdline.split(|&b| b == 0).next().unwrap_or_default();
            if String::from_utf8_lossy(program).trim_end().ends_with(&wanted) {
                // SAFETY: kill only sends a signal to the process named; nothing is shared.
                unsafe { libc::kill(pid, libc::SIGINT) };
                found += 1;
            }
        }
        found
    }

    /// A Windows path of the tests (`C:\users\…`, a capture to serve) as Linux finds it,
    /// through the prefix's drive links; a path under the repository (its Linux path, which
    /// Wine takes as one on the current drive, `Z:`) joined with Windows' separator comes
    /// back with Linux's; any other argument as it is.
    fn linux_path(prefix: &Path, arg: &str) -> String {
        if arg.starts_with('/') {
            return arg.replace('\\', "/");
        }
        let b = arg.as_bytes();
        if b.len() > 2 && b[0].is_ascii_alphabetic() && b[1] == b':' && b[2] == b'\\' {
            let drive = format!("{}:", arg[..1].to_ascii_lowercase());
            let rest = arg[3..].replace('\\', "/");
            return prefix
                .join("dosdevices")
                .join(drive)
                .join(rest)
                .display()
                .to_string();
        }
        arg.to_string()
    }

    /// A Linux path as Wine's processes see it (drive Z: is the root).
    fn windows_path(path: &Path) -> String {
        format!("Z:{}", path.display()).replace('/', "\\")
    }
}

/// A connection to the Linux side that keeps what it started.
#[cfg(windows)]
pub struct HostLine {
    lines: std::io::BufReader<std::net::TcpStream>,
    out: std::net::TcpStream,
}

#[cfg(windows)]
impl HostLine {
    /// Asks for `words`; the answer's line. `None` (after `tool_missing`) where no Linux
    /// side was started: the test cannot do its part under Wine without one.
    #[track_caller]
    pub fn ask(words: &[&str]) -> Option<(HostLine, String)> {
        let Ok(address) = std::env::var(HOST_ENV) else {
            crate::support::tool_missing(&format!(
                "{HOST_ENV} is not set: no Linux side serves pseudo-terminals and PostgreSQL to the tests under Wine (`.ci/windows` starts one)"
            ));
            return None;
        };
        let out = std::net::TcpStream::connect(&address)
            .unwrap_or_else(|e| panic!("the Linux side at {address}: {e}"));
        // A Linux side that stops answering (a server that does not come up) fails the
        // test instead of holding the suite up.
        let _ = out.set_read_timeout(Some(std::time::Duration::from_secs(120)));
        let mut line = HostLine {
            lines: std::io::BufReader::new(out.try_clone().expect("clone the connection")),
            out,
        };
        let answer = line.say(&words.join("\t"));
        Some((line, answer))
    }

    /// Sends one line; the answer's line, which must come.
    pub fn say(&mut self, request: &str) -> String {
        use std::io::{BufRead, Write};
        writeln!(self.out, "{request}").expect("send to the Linux side");
        let mut answer = String::new();
        self.lines.read_line(&mut answer).expect("the Linux side answers");
        assert!(
            !answer.is_empty(),
            "the Linux side ended {request:?} (see its output)"
        );
        answer.trim_end().to_string()
    }
}
