//! How far one recipe may expand with its includes: counts the included files loaded and the
//! steps read, over every level of includes together, so that includes of includes cannot
//! multiply into hours of checking (8 files each including the next 10 times is 10^8
//! loads); and bounds the time the steps can take, so that no sum of durations in a run
//! can outgrow the clock. Counting only: it must not read files or record problems; the
//! loader reports the refusal at the step or include that went over.

use std::time::Duration;

/// Most included files loaded for one recipe, counting a file again each time it is
/// included. Real recipes include a handful; 1 000 leaves room for generated ones, and
/// loading that many small files takes well under a second.
pub const MAX_INCLUDE_LOADS: usize = 1_000;
/// Most steps in one recipe with its includes expanded (a `repeat` counts its steps once,
/// not once per pass). Long run-ins have a few hundred; 100 000 keep checking under a
/// second and the validated recipe at a few tens of MiB.
pub const MAX_EXPANDED_STEPS: usize = 100_000;

/// The longest one list of steps may take, every timeout counted in full and repeats
/// multiplied out. A century is far beyond any bench run, and far below the 584 years at
/// which the virtual clock's nanosecond count saturates (after which a wait would never
/// see its end time come); the steps, `on_fault` and `finally` together stay below that.
pub const MAX_RUN_TIME: Duration = Duration::from_secs(100 * 365 * 24 * 3600);

/// A limit that was just exceeded, in the loader's terms.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct OverLimit {
    pub message: String,
    pub label: String,
    pub help: String,
}

/// The counts so far; shared by the recipe and every file it includes.
#[derive(Debug, Default)]
pub(crate) struct Expansion {
    loads: usize,
    steps: usize,
    over: bool,
    /// The run-time limit was reported already: once is enough, where it was first seen.
    time_reported: bool,
}

impl Expansion {
    /// True once a limit was exceeded: the loader reads no further.
    pub fn is_over(&self) -> bool {
        self.over
    }

    /// Counts one include about to be loaded.
    pub fn load(&mut self) -> Result<(), OverLimit> {
        self.loads += 1;
        let loads = self.loads;
        self.within(loads <= MAX_INCLUDE_LOADS, || OverLimit {
            message: format!(
                "this include goes over {MAX_INCLUDE_LOADS} included files for one recipe (a file counts each time it is included, includes of includes too)"
            ),
            label: format!("include number {loads}"),
            help: "includes multiply when included files include others several times; run a file several times with `repeat: { times: N, steps: [ { include: FILE } ] }`".into(),
        })
    }

    /// Checks the longest time of a list of steps up to one step; refuses once, at the
    /// first step that goes over.
    pub fn longest_time(&mut self, longest: Duration) -> Result<(), OverLimit> {
        if longest <= MAX_RUN_TIME || self.time_reported {
            return Ok(());
        }
        self.time_reported = true;
        Err(OverLimit {
            message: format!(
                "the steps up to here can take more than {} days (each timeout counted in full, repeats multiplied out)",
                MAX_RUN_TIME.as_secs() / (24 * 3600)
            ),
            label: "too long in total".into(),
            help: "check the `times` of repeats and the units of long durations".into(),
        })
    }

    /// Counts one step about to be read.
    pub fn step(&mut self) -> Result<(), OverLimit> {
        self.steps += 1;
        let steps = self.steps;
        self.within(steps <= MAX_EXPANDED_STEPS, || OverLimit {
            message: format!(
                "this recipe has more than {MAX_EXPANDED_STEPS} steps with its includes expanded"
            ),
            label: format!("step number {steps}"),
            help: "repeat steps with `repeat` instead of writing them out, and check for files included many times".into(),
        })
    }

    /// A count still `within` its limit is fine; one over it stops the reading.
    fn within(&mut self, within: bool, over: impl FnOnce() -> OverLimit) -> Result<(), OverLimit> {
        if within {
            return Ok(());
        }
        self.over = true;
        Err(over())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_to_the_limit_then_refuses_once_over() {
        let mut e = Expansion::default();
        for _ in 0..MAX_INCLUDE_LOADS {
            assert!(e.load().is_ok());
        }
        assert!(!e.is_over());
        let over = e.load().unwrap_err();
        assert!(over.message.contains("1000 included files"), "{over:?}");
        assert!(e.is_over());
        let mut e = Expansion::default();
        for _ in 0..MAX_EXPANDED_STEPS {
            assert!(e.step().is_ok());
        }
        assert!(e.step().unwrap_err().message.contains("more than 100000 steps"));
        assert!(e.longest_time(MAX_RUN_TIME).is_ok());
        assert!(e.longest_time(MAX_RUN_TIME + Duration::from_secs(1)).is_err());
        assert!(e.longest_time(Duration::MAX).is_ok(), "reported once");
    }
}
