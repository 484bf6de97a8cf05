//! How long one read occupies a serial line: the family's own request and reply for the
//! drive's status (or speed), counted as the family's link sends and receives them against
//! its simulated drive in memory, in virtual time, and timed at the line's settings. What
//! the latency note compares an adapter's timer with; never opens the real port.

use super::drive_args::open_drive;
use super::ConnectionArgs;
use crate::bus::{BusKind, SerialSettings};
use crate::dictionary::{Dictionary, Role};
use crate::family::Registry;
use crate::link::{Direction, TelegramObserver};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// One read exchange on the line: which object, its bytes both ways, and the settings.
#[derive(Debug, Clone, PartialEq)]
pub struct LineExchange {
    pub object: String,
    pub bytes: usize,
    pub settings: SerialSettings,
}

impl LineExchange {
    /// Measures a read for a drive of `dictionary`'s family at `connection`'s address and
    /// serial settings: of the first of `sampled` (what the run reads most), else the
    /// status word, the actual speed or the first readable object. `None` for a family not
    /// on a serial line or a read the simulated drive does not answer.
    pub fn measure(
        registry: &Registry,
        connection: &ConnectionArgs,
        dictionary: &Arc<Dictionary>,
        sampled: &[String],
    ) -> Option<Self> {
        let family = registry.family(dictionary.family()).ok()?;
        if family.bus_kind() != BusKind::Bytes {
            return None;
        }
        let object = sampled
            .iter()
            .find_map(|name| dictionary.get(name))
            .or_else(|| dictionary.role(Role::StatusWord))
            .or_else(|| dictionary.role(Role::SpeedActual))
            .or_else(|| dictionary.objects().find(|o| o.readable()))?
            .name
            .clone();
        let mut simulated = connection.clone();
        (simulated.port, simulated.tcp, simulated.can) = (None, None, None);
        let counted = Arc::new(AtomicUsize::new(0));
        let observer = ByteCount(counted.clone());
        let mut open = open_drive(
            registry,
            &simulated,
            dictionary.clone(),
            true,
            Some(Box::new(observer)),
            None,
        )
        .ok()?;
        // Whatever opening the link exchanged is not part of one read.
        counted.store(0, Ordering::Relaxed);
        open.drive.read(&object).ok()?;
        let bytes = counted.load(Ordering::Relaxed);
        (bytes > 0).then(|| LineExchange {
            object,
            bytes,
            settings: connection.serial_settings(family.as_ref()),
        })
    }

    /// The time the exchange's bytes occupy the wire.
    pub fn wire_time(&self) -> Duration {
        let bits = self.bytes as f64 * f64::from(self.settings.bits_per_byte());
        Duration::from_secs_f64(bits / f64::from(self.settings.baud.max(1)))
    }
}

/// Counts the bytes of every telegram both ways.
struct ByteCount(Arc<AtomicUsize>);

impl TelegramObserver for ByteCount {
    fn telegram(&mut self, _: Duration, _: Direction, bytes: &[u8]) {
        self.0.fetch_add(bytes.len(), Ordering::Relaxed);
    }
    fn event(&mut self, _: Duration, _: &str) {}
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::{Args, Command, FromArgMatches};

    fn connection(args: &[&str]) -> ConnectionArgs {
        let matches = ConnectionArgs::augment_args(Command::new("t"))
            .try_get_matches_from(std::iter::once("t").chain(args.iter().copied()))
            .unwrap();
        ConnectionArgs::from_arg_matches(&matches).unwrap()
    }

    #[test]
    fn a_read_is_measured_in_the_familys_own_bytes_at_the_lines_settings() {
        let registry = Registry::builtin();
        let line = connection(&["--baud", "19200"]);
        for drive in ["sd2", "ct-unidrive-sp", "lenze-931"] {
            let dictionary = Arc::new(registry.load_dictionary(drive).unwrap());
            let exchange = LineExchange::measure(&registry, &line, &dictionary, &[]).unwrap();
            assert!(exchange.bytes >= 8, "{drive}: {exchange:?}");
            assert_eq!(exchange.settings.baud, 19_200);
            let bits = exchange.bytes as f64 * f64::from(exchange.settings.bits_per_byte());
            assert!(
                (exchange.wire_time().as_secs_f64() - bits / 19_200.0).abs() < 1e-9,
                "{drive}"
            );
        }
        // A CAN family is not on a serial line.
        let can = Arc::new(registry.load_dictionary("lenze-9400").unwrap());
        assert_eq!(LineExchange::measure(&registry, &line, &can, &[]), None);
    }
}
