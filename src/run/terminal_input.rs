//! Lines typed at a terminal, read by a thread of its own that hands each over a channel,
//! so the session waits for a keystroke in short slices and serves the drives and stop
//! requests in between. Reads and hands over; judges nothing.

use crate::session::Reply;
use std::io::{BufRead, BufReader, Read};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError, TryRecvError};
use std::sync::{Arc, Mutex, OnceLock, PoisonError};
use std::time::Duration;

/// Lines typed at a terminal, from a thread that reads them for the rest of the process
/// (a blocking read cannot be cancelled; a later run of the same command reuses it).
pub struct TerminalInput {
    lines: Mutex<Receiver<Reply>>,
    /// End of input was seen: every later question gets [`Reply::Closed`] too.
    closed: Mutex<bool>,
    /// Standard input: what was typed before a question is discarded.
    stdin: bool,
    /// The person types where this process's output shows: the input marker is written.
    marked: bool,
}

impl TerminalInput {
    /// Standard input, read from the first question on (one reader per process).
    pub fn stdin() -> Arc<TerminalInput> {
        static INPUT: OnceLock<Arc<TerminalInput>> = OnceLock::new();
        INPUT
            .get_or_init(|| Arc::new(Self::reading(std::io::stdin(), true, true)))
            .clone()
    }

    /// The lines of `source` (a pipe in tests), as a terminal's, each answering the next
    /// question: a typist who never types ahead, so nothing is discarded.
    pub fn of(source: impl Read + Send + 'static) -> Arc<TerminalInput> {
        Arc::new(Self::reading(source, false, true))
    }

    /// The lines of `source` typed where this process's output does not show (a browser
    /// page): as [`TerminalInput::of`], without the input marker in the output.
    pub fn typed_elsewhere(source: impl Read + Send + 'static) -> Arc<TerminalInput> {
        Arc::new(Self::reading(source, false, false))
    }

    /// Whether the input marker belongs in the output before a question's answer.
    pub fn marked(&self) -> bool {
        self.marked
    }

    fn reading(source: impl Read + Send + 'static, stdin: bool, marked: bool) -> TerminalInput {
        let (to_session, lines) = channel();
        let reader = std::thread::Builder::new()
            .name("terminal input".into())
            .spawn(move || {
                let mut source = BufReader::new(source);
                let mut line = Vec::new();
                loop {
                    line.clear();
                    let reply = match source.read_until(b'\n', &mut line) {
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
            stdin,
            marked,
        }
    }

    fn closed(&self) -> std::sync::MutexGuard<'_, bool> {
        self.closed.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Throws away what was typed before the question: what the terminal holds unread and
    /// the lines the reader has already handed over (an end of input is kept).
    pub fn discard_typed_ahead(&self) {
        if !self.stdin {
            return;
        }
        discard_terminal_input();
        let lines = self.lines.lock().unwrap_or_else(PoisonError::into_inner);
        while let Ok(reply) = lines.try_recv() {
            if reply == Reply::Closed {
                *self.closed() = true;
            }
        }
    }

    /// The next line, waiting at most `within` (real time).
    pub fn next(&self, within: Duration) -> Reply {
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
