//! The `attempts` blocks under way, as the console follows them: a failure inside an
//! attempt that another one follows reads `FAIL (attempt 1 of 3, retrying)`, because the
//! report keeps it as retried and the verdict is the last attempt's. Text only; it must
//! not decide anything about the run.

/// The open `attempts` blocks, outermost first: (step number, attempt, of).
#[derive(Debug, Default)]
pub struct OpenAttempts {
    open: Vec<(String, u32, u32)>,
}

impl OpenAttempts {
    /// Outside every `attempts` block (for lines printed after the run).
    pub const NONE: OpenAttempts = OpenAttempts { open: Vec::new() };

    /// The block `number` begins its attempt `attempt` of `of`.
    pub fn started(&mut self, number: &str, attempt: u32, of: u32) {
        self.finished(number);
        self.open.push((number.to_string(), attempt, of));
    }

    /// The step `number` finished: when it is the innermost block, the block is over.
    pub fn finished(&mut self, number: &str) {
        if self.open.last().is_some_and(|(n, ..)| n == number) {
            self.open.pop();
        }
    }

    /// The run ends in a way no attempt tries again: every failure from now on is final.
    pub fn give_up(&mut self) {
        self.open.clear();
    }

    /// How a failure reads now: `FAIL`, or inside an attempt that another follows (the
    /// innermost such: any one of them tries the failure again) `FAIL (attempt 1 of 3,
    /// retrying)`.
    pub fn fail_mark(&self) -> String {
        match self.open.iter().rev().find(|(_, k, of)| k < of) {
            Some((_, k, of)) => format!("FAIL (attempt {k} of {of}, retrying)"),
            None => "FAIL".to_string(),
        }
    }
}

/// The [`RunObserver`](crate::session::RunObserver) methods of a reporter that follows the
/// `attempts` blocks in an [`OpenAttempts`] field `attempts`, written inside its
/// `impl RunObserver`: `follow_attempts!();`.
#[macro_export]
macro_rules! follow_attempts {
    () => {
        fn attempt_started(&mut self, number: &str, attempt: u32, of: u32) {
            self.attempts.started(number, attempt, of);
        }

        fn attempts_given_up(&mut self) {
            self.attempts.give_up();
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failure_is_retrying_only_inside_an_attempt_that_another_follows() {
        let mut open = OpenAttempts::default();
        assert_eq!(open.fail_mark(), "FAIL");
        open.started("3", 1, 2);
        assert_eq!(open.fail_mark(), "FAIL (attempt 1 of 2, retrying)");
        open.started("3.2", 3, 3);
        assert_eq!(
            open.fail_mark(),
            "FAIL (attempt 1 of 2, retrying)",
            "the outer block retries"
        );
        open.finished("3.2");
        open.started("3", 2, 2);
        assert_eq!(open.fail_mark(), "FAIL", "the last attempt's failure is final");
        open.finished("3.1");
        assert_eq!(open.fail_mark(), "FAIL");
        open.finished("3");
        assert_eq!(OpenAttempts::NONE.fail_mark(), "FAIL");
        open.started("4", 1, 3);
        open.give_up();
        assert_eq!(open.fail_mark(), "FAIL", "a fault inside an attempt ends the run");
        assert!(open.open.is_empty());
    }
}
