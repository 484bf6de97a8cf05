//! How the CT ANSI link listens for the answer to one message on a line that may echo:
//! the echo (whole, broken off, or a lone EOT that may be the drive's answer) is told from
//! the reply as the module docs of `ct_link` say, and what an attempt saw of its echo is kept
//! for the no-reply message. Part of [`CtLink`]; must not send anything.

use super::*;

/// The echo an attempt saw.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum EchoSeen {
    Whole,
    /// The first `n` bytes, then something else or nothing.
    Part(usize),
}

impl CtLink {
    /// What to check after no reply, with what the last attempt saw of its echo.
    pub(super) fn no_reply_hint(&self) -> String {
        match self.attempt_echo {
            Some(EchoSeen::Whole) => format!(
                "the echo of the message came back (the RS485 adapter echoes what it sends; drivescript skips it), but the drive did not answer: {NO_REPLY_HINT}, and the wiring from the adapter to the drive"
            ),
            Some(EchoSeen::Part(n)) => format!(
                "only the first {n} byte(s) of the echo of the message came back (the RS485 adapter echoes what it sends) and no answer after them: bytes were lost on the line or in the adapter; {NO_REPLY_HINT}, and the termination"
            ),
            None => NO_REPLY_HINT.to_string(),
        }
    }

    pub(super) fn await_reply(
        &mut self,
        t: &mut dyn Transport,
        request: &Request,
        sent_bytes: &[u8],
    ) -> Result<Reply, AttemptFailure<Refused>> {
        let sent = self.core.clock.now();
        let left_at = sent + t.still_sending();
        let deadline = left_at + self.config.reply_timeout;
        let echo_window_end = left_at + self.config.echo_wait;
        // The echo, if any, comes before everything else; after the first byte that is not
        // ours, only the reply is looked for.
        let mut echo_open = true;
        // Nothing but the reply has arrived (no echo, no noise): the line does not echo.
        let mut clean = true;
        // A reply to another message, dropped: named if this one's never comes.
        let mut dropped = None;
        self.attempt_echo = None;
        loop {
            let mut wait_until = deadline;
            if echo_open {
                match match_echo(&self.pending, sent_bytes) {
                    EchoMatch::Whole => {
                        self.pending.drain(..sent_bytes.len());
                        self.echo_skipped(EchoSeen::Whole, sent_bytes);
                        echo_open = false;
                        clean = false;
                        continue;
                    }
                    EchoMatch::Broken(n) => {
                        let part: Vec<u8> = self.pending.drain(..n).collect();
                        self.echo_skipped(EchoSeen::Part(n), &part);
                        echo_open = false;
                        clean = false;
                        continue;
                    }
                    EchoMatch::Prefix(n) => {
                        let lone_eot = n == 1 && self.pending[0] == EOT;
                        let the_drives = lone_eot
                            && match self.line_echoes {
                                Some(echoes) => !echoes,
                                None => self.core.clock.now() >= echo_window_end,
                            };
                        if the_drives {
                            if self.line_echoes.is_none() {
                                let ms = self.config.echo_wait.as_millis();
                                self.core.event(&format!(
                                    "EOT and nothing after it for {ms} ms: the drive's answer, not the start of an echo"
                                ));
                            }
                            echo_open = false;
                        } else if lone_eot && self.line_echoes.is_none() {
                            wait_until = echo_window_end.min(deadline);
                        }
                    }
                    EchoMatch::NotEcho => match split(&self.pending, Sender::Drive) {
                        // Noise before anything that could be a reply: the echo may still
                        // follow it, and its EOT must not be read as the drive's.
                        Split::Noise(n) => {
                            self.pending.drain(..n);
                            clean = false;
                            self.core.event(&format!("skipped {n} byte(s) of line noise"));
                            continue;
                        }
                        _ => echo_open = false,
                    },
                    EchoMatch::Nothing => {}
                }
            }
            if !echo_open {
                loop {
                    match split(&self.pending, Sender::Drive) {
                        Split::Incomplete => break,
                        Split::Noise(n) => {
                            self.pending.drain(..n);
                            clean = false;
                            self.core.event(&format!("skipped {n} byte(s) of line noise"));
                        }
                        Split::Message(n) => {
                            let bytes: Vec<u8> = self.pending.drain(..n).collect();
                            self.core.notify(Direction::Received, &bytes);
                            return match Reply::decode(&bytes) {
                                Ok(reply) => match answers(request, &reply) {
                                    Ok(()) => {
                                        if clean && self.line_echoes.is_none() {
                                            self.line_echoes = Some(false);
                                        }
                                        Ok(reply)
                                    }
                                    // Another message's answer (most often a late one):
                                    // never this one's; listened on.
                                    Err(problem) => {
                                        self.core.stats.mismatched_replies += 1;
                                        self.core.event(&format!(
                                            "dropped a reply that answers another message: {problem}"
                                        ));
                                        dropped = Some(Refusal {
                                            reply: bytes,
                                            problem,
                                        });
                                        clean = false;
                                        continue;
                                    }
                                },
                                Err(problem) => {
                                    self.core.stats.corrupt_replies += 1;
                                    Err(AttemptFailure::Bad(Refusal {
                                        reply: bytes,
                                        problem: problem.into(),
                                    }))
                                }
                            };
                        }
                    }
                }
            }
            let got = match self.core.read_reply(t, left_at, wait_until) {
                Ok(bytes) => {
                    self.pending.extend_from_slice(bytes);
                    continue;
                }
                Err(e) => e,
            };
            match got {
                // The echo window passed with a lone EOT: decide again.
                ReplyWait::Timeout if self.core.clock.now() < deadline => {}
                ReplyWait::Timeout => {
                    if echo_open && !self.pending.is_empty() {
                        self.attempt_echo = Some(EchoSeen::Part(self.pending.len()));
                    }
                    let note = match self.attempt_echo {
                        Some(EchoSeen::Whole) => " after the echo of our message",
                        Some(EchoSeen::Part(_)) => " after part of the echo of our message",
                        None => "",
                    };
                    return Err(match dropped.take() {
                        Some(r) => AttemptFailure::Discarded(r),
                        None => AttemptFailure::Timeout { note },
                    });
                }
                wait => return Err(wait.into()),
            }
        }
    }

    /// Counts and traces our own message (or its start) handed back by the adapter.
    fn echo_skipped(&mut self, seen: EchoSeen, bytes: &[u8]) {
        self.attempt_echo = Some(seen);
        self.line_echoes = Some(true);
        self.core.stats.echoes += 1;
        let text = match seen {
            EchoSeen::Whole => format!("echo of our message skipped: {}", show_bytes(bytes)),
            EchoSeen::Part(n) => format!(
                "skipped {n} byte(s) that began an echo of our message and broke off: {}",
                show_bytes(bytes)
            ),
        };
        self.core.event(&text);
    }
}
