//! The operator of a run: the answers the command line gave, and the person at the
//! terminal (its lines read by a [`TerminalInput`]); typed-ahead input is thrown away
//! before each question. Must not judge answers (the prompts do) nor print anything but
//! the input marker.

use super::TerminalInput;
use crate::session::{Given, Operator, Reply};
use std::io::{IsTerminal, Write};
use std::sync::Arc;
use std::time::Duration;

/// What the operator types in front of, on the line after the question.
const MARKER: &str = "       > ";

pub struct RunOperator {
    given: Vec<(String, Given)>,
    /// Where a person's lines come from; `None` when nobody can be asked.
    input: Option<Arc<TerminalInput>>,
}

impl RunOperator {
    /// The answers `given`; a person is asked for the others at `input`.
    pub fn new(given: Vec<(String, Given)>, input: Option<Arc<TerminalInput>>) -> Self {
        RunOperator { given, input }
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
        self.input.is_some()
    }

    fn discard_typed_ahead(&mut self) {
        if let Some(input) = &self.input {
            input.discard_typed_ahead();
        }
    }

    fn start_asking(&mut self) {
        if !self.input.as_ref().is_some_and(|i| i.marked()) {
            return;
        }
        let mut out = std::io::stdout();
        let _ = out.write_all(MARKER.as_bytes());
        let _ = out.flush();
    }

    fn next_line(&mut self, within: Duration) -> Reply {
        match &self.input {
            Some(input) => input.next(within),
            None => Reply::Closed,
        }
    }

    fn person(&self) -> String {
        ["USER", "LOGNAME"]
            .iter()
            .find_map(|v| std::env::var(v).ok().filter(|s| !s.is_empty()))
            .unwrap_or_else(|| "the operator".into())
    }
}
