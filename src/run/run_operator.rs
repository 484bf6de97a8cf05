//! The operator of a run: the answers the command line gave, and the person at the
//! terminal (standard input). The terminal is read by a thread of its own that hands each
//! line over a channel, so the session waits for a keystroke in short slices and serves
//! the drives and stop requests in between; typed-ahead input is flushed before each
//! question. Must not judge answers (the prompts do) nor print anything but the input
//! marker.

use crate::session::{Given, Operator, Reply};
use std::io::{BufRead, IsTerminal, Write};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError, TryRecvError};
use std::sync::{Mutex, OnceLock, PoisonError};
use std::time::Duration;

/// What the operator types in front of, on the line after the question.
const MARKER: &str = "       > ";

pub struct RunOperator {
    given: Vec<(String, Given)>,
    terminal: bool,
}

impl RunOperator {
    /// The answers `given`; a person is asked for the others when `terminal` (standard
    /// input is one).
    pub fn new(given: Vec<(String, Given)>, terminal: bool) -> Self {
        RunOperator { given, terminal }
    }

    /// Whether standard input is a terminal a person can answer at.
    pub fn stdin_is_terminal() -> bool {
        std::io::stdin().is_terminal()
    }
}

impl Operator for RunOperator {
    fn given(&mut self, name: &str) -> Option<Given> {
        self.given.iter().find(|(n, _)| n == name).map(|(_, g)| g.clone())
    }

    fn has_terminal(&self) -> bool {
        self.terminal
    }

    fn start_asking(&mut self, fresh: bool) {
        if fresh {
            input().discard_typed_ahead();
        }
        let mut out = std::io::stdout();
        let _ = out.write_all(MARKER.as_bytes());
        let _ = out.flush();
    }

    fn next_line(&mut self, within: Duration) -> Reply {
        input().next(within)
    }

    fn person(&self) -> String {
        ["USER", "LOGNAME"]
            .iter()
            .find_map(|v| std::env::var(v).ok().filter(|s| !s.is_empty()))
            .unwrap_or_else(|| "the operator".into())
    }
}

/// Standard input, line by line, from a thread that reads it for the rest of the process
/// (a blocking read cannot be cancelled; a later run of the same command reuses it).
struct TerminalInput {
    lines: Mutex<Receiver<Reply>>,
    /// End of input was seen: every later question gets [`Reply::Closed`] too.
    closed: Mutex<bool>,
}

fn input() -> &'static TerminalInput {
    static INPUT: OnceLock<TerminalInput> = OnceLock::new();
    INPUT.get_or_init(|| {
        let (to_session, lines) = channel();
        let reader = std::thread::Builder::new()
            .name("terminal input".into())
            .spawn(move || {
                let stdin = std::io::stdin();
                let mut line = Vec::new();
                loop {
                    line.clear();
                    let reply = match stdin.lock().read_until(b'\n', &mut line) {
                        Ok(0) | Err(_) => Reply::Closed,
                        Ok(_) => Reply::Line(
                            String::from_utf8_lossy(&line)
                                .trim_end_matches(['\r', '\n'])
                                .to_string(),
                        ),
                    };
                    let closed = reply == Reply::Closed;
                    if to_session.send(reply).is_err() || closed {
                        return;
                    }
                }
            });
        TerminalInput {
            lines: Mutex::new(lines),
            // Without a reader nobody can answer.
            closed: Mutex::new(reader.is_err()),
        }
    })
}

impl TerminalInput {
    fn closed(&self) -> std::sync::MutexGuard<'_, bool> {
        self.closed.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Throws away what was typed before the question: what the terminal holds unread and
    /// the lines the reader has already handed over (an end of input is kept).
    fn discard_typed_ahead(&self) {
        discard_terminal_input();
        let lines = self.lines.lock().unwrap_or_else(PoisonError::into_inner);
        while let Ok(reply) = lines.try_recv() {
            if reply == Reply::Closed {
                *self.closed() = true;
            }
        }
    }

    fn next(&self, within: Duration) -> Reply {
        if *self.closed() {
            return Reply::Closed;
        }
        let lines = self.lines.lock().unwrap_or_else(PoisonError::into_inner);
        let reply = if within.is_zero() {
            match lines.try_recv() {
                Ok(r) => r,
                Err(TryRecvError::Empty) => Reply::Nothing,
                Err(TryRecvError::Disconnected) => Reply::Closed,
            }
        } else {
            match lines.recv_timeout(within) {
                Ok(r) => r,
                Err(RecvTimeoutError::Timeout) => Reply::Nothing,
                Err(RecvTimeoutError::Disconnected) => Reply::Closed,
            }
        };
        if reply == Reply::Closed {
            *self.closed() = true;
        }
        reply
    }
}

/// Discards input the terminal has received but nobody has read (POSIX `tcflush`).
#[cfg(unix)]
fn discard_terminal_input() {
    // SAFETY: tcflush only takes a descriptor and a constant; on a descriptor that is no
    // terminal it fails harmlessly.
    unsafe {
        libc::tcflush(libc::STDIN_FILENO, libc::TCIFLUSH);
    }
}

#[cfg(not(unix))]
fn discard_terminal_input() {}
