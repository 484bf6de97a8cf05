//! Hands every telegram and link event to several telegram observers, so `--trace FILE`
//! and `-v` can both watch the one link (which takes a single observer). Adds nothing and
//! must not block or fail the link itself.

use crate::link::{Direction, TelegramObserver};
use std::time::Duration;

#[derive(Default)]
pub struct TelegramFanOut {
    list: Vec<Box<dyn TelegramObserver>>,
}

impl TelegramFanOut {
    pub fn new() -> Self {
        TelegramFanOut::default()
    }

    pub fn push(&mut self, observer: Box<dyn TelegramObserver>) {
        self.list.push(observer);
    }

    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The one observer itself when there is only one, else the fan-out; `None` for none.
    pub fn into_observer(mut self) -> Option<Box<dyn TelegramObserver>> {
        match self.list.len() {
            0 => None,
            1 => self.list.pop(),
            _ => Some(Box::new(self)),
        }
    }
}

impl TelegramObserver for TelegramFanOut {
    fn telegram(&mut self, at: Duration, direction: Direction, bytes: &[u8]) {
        for o in &mut self.list {
            o.telegram(at, direction, bytes);
        }
    }

    fn event(&mut self, at: Duration, text: &str) {
        for o in &mut self.list {
            o.event(at, text);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};

    struct Log(Arc<Mutex<Vec<String>>>, &'static str);
    impl TelegramObserver for Log {
        fn telegram(&mut self, at: Duration, d: Direction, bytes: &[u8]) {
            self.0.lock().unwrap().push(format!(
                "{} {} {} {}",
                self.1,
                at.as_millis(),
                d.tag(),
                bytes.len()
            ));
        }
        fn event(&mut self, at: Duration, text: &str) {
            self.0
                .lock()
                .unwrap()
                .push(format!("{} {} {text}", self.1, at.as_millis()));
        }
    }

    #[test]
    fn every_observer_sees_everything_in_order() {
        let log = Arc::new(Mutex::new(Vec::new()));
        let mut fan = TelegramFanOut::new();
        assert!(fan.is_empty());
        fan.push(Box::new(Log(log.clone(), "a")));
        fan.push(Box::new(Log(log.clone(), "b")));
        let mut o = fan.into_observer().unwrap();
        o.telegram(Duration::from_millis(5), Direction::Sent, &[0, 9]);
        o.event(Duration::from_millis(6), "retry 1 of 2");
        assert_eq!(
            *log.lock().unwrap(),
            vec!["a 5 TX 2", "b 5 TX 2", "a 6 retry 1 of 2", "b 6 retry 1 of 2"]
        );
        assert!(TelegramFanOut::new().into_observer().is_none());
    }
}
