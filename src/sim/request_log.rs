//! The bounded log every simulator front keeps of what it was sent (for tests to look at):
//! the latest entries only, so a simulator serving a run of days stays small.

/// How many entries a log keeps at least; it is trimmed to this when it reaches twice as
/// many, so trimming costs little per entry.
pub const LOG_KEEPS: usize = 10_000;

/// Appends `entry`, dropping the oldest half when the log is full.
pub fn keep_recent<T>(log: &mut Vec<T>, entry: T) {
    if log.len() >= 2 * LOG_KEEPS {
        log.drain(..LOG_KEEPS);
    }
    log.push(entry);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_log_stays_bounded_and_keeps_the_latest() {
        let mut log = Vec::new();
        for i in 0..5 * LOG_KEEPS {
            keep_recent(&mut log, i);
        }
        assert!(log.len() <= 2 * LOG_KEEPS);
        assert!(log.len() >= LOG_KEEPS);
        assert_eq!(log.last(), Some(&(5 * LOG_KEEPS - 1)));
    }
}
