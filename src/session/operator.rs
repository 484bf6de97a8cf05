//! Where the answers to operator steps come from, as the session sees it: answers given
//! beforehand (`--answer`, `--answers FILE`) and a person at a terminal, read so that the
//! session can keep serving the drive between keystrokes. A trait only: the terminal
//! itself is the run layer's; nothing here reads or writes.

use std::time::Duration;

/// What the terminal gave within a wait.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Reply {
    /// One line, without its line end.
    Line(String),
    /// End of input: the terminal closed (or Ctrl-D on an empty line). Nobody can answer.
    Closed,
    /// Nothing yet.
    Nothing,
}

/// An answer given before the run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Given {
    pub value: String,
    /// Where it was given, for the report: `--answer`, `answers.yaml`.
    pub source: String,
}

/// The run's source of answers.
pub trait Operator {
    /// The answer given beforehand for the prompt called `name`; the person is then not
    /// asked.
    fn given(&mut self, name: &str) -> Option<Given>;
    /// Whether a person can be asked (standard input is a terminal).
    fn has_terminal(&self) -> bool;
    /// Before a question appears: keystrokes typed before it (a scanner's stray Enter) are
    /// thrown away. Never after it shows: a key pressed as soon as it is read is an answer.
    fn discard_typed_ahead(&mut self);
    /// Once the question (or the request to answer again) is shown: the input marker.
    fn start_asking(&mut self);
    /// The person's next line, waiting at most `within` of real time.
    fn next_line(&mut self, within: Duration) -> Reply;
    /// Who answers at the terminal when the run's identity names no operator: the login
    /// name.
    fn person(&self) -> String;
}

/// No answers and no terminal: what a session has unless the run gives it an operator.
/// Every prompt then fails with a clear message instead of waiting for nobody.
#[derive(Debug, Default)]
pub struct Nobody;

impl Operator for Nobody {
    fn given(&mut self, _name: &str) -> Option<Given> {
        None
    }
    fn has_terminal(&self) -> bool {
        false
    }
    fn discard_typed_ahead(&mut self) {}
    fn start_asking(&mut self) {}
    fn next_line(&mut self, _within: Duration) -> Reply {
        Reply::Closed
    }
    fn person(&self) -> String {
        "nobody".into()
    }
}
