//! The operator's answers typed on the page, as the lines of a terminal: the run reads
//! them through the same [`crate::run::TerminalInput`] and operator seam as a person at a
//! terminal, so every answer is judged (and asked again) exactly as there. Only carries
//! lines; the page's view decides which answers may be sent.

use std::io::Read;
use std::sync::mpsc::{channel, Receiver, Sender};

/// Where the page's answers go in.
#[derive(Clone)]
pub struct AnswerSender(Sender<Vec<u8>>);

impl AnswerSender {
    /// Hands `answer` to the run as one typed line. Line ends in it are spaces: one
    /// answer is one line.
    pub fn send(&self, answer: &str) -> bool {
        let mut line: Vec<u8> = answer.replace(['\r', '\n'], " ").into_bytes();
        line.push(b'\n');
        self.0.send(line).is_ok()
    }
}

/// The lines sent, read as a byte stream; its end when every sender is gone (the run is
/// over).
pub struct AnswerLines {
    lines: Receiver<Vec<u8>>,
    pending: Vec<u8>,
    at: usize,
}

/// A sender and the reader its lines come out of.
pub fn answer_channel() -> (AnswerSender, AnswerLines) {
    let (tx, rx) = channel();
    (
        AnswerSender(tx),
        AnswerLines {
            lines: rx,
            pending: Vec::new(),
            at: 0,
        },
    )
}

impl Read for AnswerLines {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.at >= self.pending.len() {
            match self.lines.recv() {
                Ok(line) => {
                    self.pending = line;
                    self.at = 0;
                }
                Err(_) => return Ok(0),
            }
        }
        let n = buf.len().min(self.pending.len() - self.at);
        buf[..n].copy_from_slice(&self.pending[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::TerminalInput;
    use crate::session::Reply;
    use std::time::Duration;

    #[test]
    fn answers_arrive_as_lines_and_the_end_when_the_sender_is_gone() {
        let (tx, lines) = answer_channel();
        let input = TerminalInput::of(lines);
        assert!(tx.send("1.2 mm/s"));
        assert!(tx.send("two\nlines"));
        let wait = Duration::from_secs(5);
        assert_eq!(input.next(wait), Reply::Line("1.2 mm/s".into()));
        assert_eq!(input.next(wait), Reply::Line("two lines".into()));
        assert_eq!(input.next(Duration::from_millis(10)), Reply::Nothing);
        drop(tx);
        assert_eq!(input.next(wait), Reply::Closed);
    }
}
