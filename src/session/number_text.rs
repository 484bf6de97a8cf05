//! The text of numbers and times that samples are written with (`6000`, `1003.647`,
//! `5.100`, `2024-06-10T06:13:20.250Z`), made without the formatting machinery where a
//! day at 100 Hz writes millions of them. Each fast path gives exactly the bytes of the
//! `format!` it stands for and hands over to that `format!` wherever it could not be sure.

use std::time::{Duration, SystemTime, UNIX_EPOCH};

/// A number without needless digits: a whole number as an integer, else rounded to six
/// decimals with trailing zeros dropped (`6000`, `0.5`, `1003.647`).
pub fn write_number(out: &mut String, v: f64) {
    let mut text = Vec::with_capacity(24);
    push_number(&mut text, v);
    out.push_str(std::str::from_utf8(&text).unwrap_or_default());
}

/// [`write_number`] appended to a row of bytes.
pub fn push_number(out: &mut Vec<u8>, v: f64) {
    if v == v.trunc() && v.abs() < 1e15 {
        push_fixed(out, v as i64, 0, false);
    } else if let Some(micros) = rounded_micros(v) {
        push_fixed(out, micros, 6, true);
    } else {
        let text = format!("{v:.6}");
        out.extend_from_slice(text.trim_end_matches('0').trim_end_matches('.').as_bytes());
    }
}

/// `at` in seconds with three decimals, as `{:.3}` writes `at.as_secs_f64()`.
pub fn push_seconds(out: &mut Vec<u8>, at: Duration) {
    // Below 2^22 s (48 days) the f64 of `at` is within a few ns of it, so only a time
    // within 1 µs of half a millisecond could round otherwise than its exact count.
    let below_half = at.subsec_nanos() % 1_000_000;
    if at.as_secs() < 1 << 22 && below_half.abs_diff(500_000) > 1_000 {
        let millis = at.as_millis() + u128::from(below_half > 500_000);
        push_fixed(out, i64::try_from(millis).unwrap_or(i64::MAX), 3, false);
    } else {
        out.extend_from_slice(format!("{:.3}", at.as_secs_f64()).as_bytes());
    }
}

/// `v × 10⁶` rounded to the nearest integer where that is certainly what `{v:.6}` shows:
/// `None` for a value so large that the product's own rounding could change it, one within
/// a hair of a tie, or one that shows as `-0.000000`.
fn rounded_micros(v: f64) -> Option<i64> {
    // NaN and the infinities fail this too.
    if v.abs() >= 1e6 || v.is_nan() {
        return None;
    }
    // |v × 10⁶| < 10¹², so the product is within 1.2·10⁻⁴ of the exact one.
    let scaled = v * 1e6;
    let rounded = scaled.round();
    ((scaled - rounded).abs() < 0.499 && rounded != 0.0).then_some(rounded as i64)
}

/// `value / 10^places` in decimals: all `places` digits, or (`trim`) without trailing
/// zeros and without the point when nothing is left after it. Made right to left in one
/// buffer and appended at once.
fn push_fixed(out: &mut Vec<u8>, value: i64, places: usize, trim: bool) {
    let mut text = [0u8; 32];
    let mut at = text.len();
    let mut magnitude = value.unsigned_abs();
    let mut fraction = places;
    if trim {
        while fraction > 0 && magnitude.is_multiple_of(10) {
            magnitude /= 10;
            fraction -= 1;
        }
    }
    for _ in 0..fraction {
        at -= 1;
        text[at] = b'0' + (magnitude % 10) as u8;
        magnitude /= 10;
    }
    if fraction > 0 {
        at -= 1;
        text[at] = b'.';
    }
    loop {
        at -= 1;
        text[at] = b'0' + (magnitude % 10) as u8;
        magnitude /= 10;
        if magnitude == 0 {
            break;
        }
    }
    if value < 0 {
        at -= 1;
        text[at] = b'-';
    }
    out.extend_from_slice(&text[at..]);
}

/// RFC 3339 UTC with milliseconds, as `humantime::format_rfc3339_millis` writes it, with
/// the text up to the second kept: samples come many to a second.
#[derive(Debug, Default)]
pub struct UtcMillis {
    /// The whole second since the epoch the kept text is of, and that text
    /// (`2024-06-10T06:13:20.`).
    second: Option<(u64, Vec<u8>)>,
}

impl UtcMillis {
    pub fn push(&mut self, out: &mut Vec<u8>, utc: SystemTime) {
        let humantime = |t: SystemTime| humantime::format_rfc3339_millis(t).to_string().into_bytes();
        let Ok(since) = utc.duration_since(UNIX_EPOCH) else {
            out.extend_from_slice(&humantime(utc));
            return;
        };
        let second = since.as_secs();
        if self.second.as_ref().is_none_or(|(s, _)| *s != second) {
            let mut text = humantime(UNIX_EPOCH + Duration::from_secs(second));
            if text.len() != "2024-06-10T06:13:20.000Z".len() {
                // Beyond the years humantime writes: its own answer, whatever it is.
                self.second = None;
                out.extend_from_slice(&humantime(utc));
                return;
            }
            text.truncate(text.len() - "000Z".len());
            self.second = Some((second, text));
        }
        if let Some((_, text)) = &self.second {
            out.extend_from_slice(text);
            let millis = since.subsec_millis();
            out.extend_from_slice(&[
                b'0' + (millis / 100) as u8,
                b'0' + (millis / 10 % 10) as u8,
                b'0' + (millis % 10) as u8,
                b'Z',
            ]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// What the writers wrote before the fast paths: the formatting machinery.
    fn number_as_formatted(v: f64) -> String {
        if v == v.trunc() && v.abs() < 1e15 {
            format!("{}", v as i64)
        } else {
            let s = format!("{v:.6}");
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        }
    }

    fn number(v: f64) -> String {
        let mut s = String::new();
        write_number(&mut s, v);
        s
    }

    #[test]
    fn numbers_near_ties_zeros_and_edges_read_as_formatted() {
        for v in [
            0.0,
            -0.0,
            6000.0,
            -6000.0,
            0.5,
            -0.5,
            1003.647,
            5997.492,
            0.0000005,
            -0.0000004,
            -0.0000005,
            2.9999999999,
            -2.9999999999,
            0.1234565,
            1e-7,
            999_999.999_999_5,
            1e6 + 0.25,
            1e15 + 0.5,
            1e300,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
        ] {
            assert_eq!(number(v), number_as_formatted(v), "{v:e}");
        }
    }

    #[test]
    fn times_read_as_formatted() {
        for (secs, nanos) in [
            (0, 0),
            (5, 100_000_000),
            (86_400, 999_500_000),
            (86_400, 999_499_999),
            (3, 4_500_000),
            (3, 4_500_500),
            (1 << 22, 1),
            (u64::MAX / 2, 123_456_789),
        ] {
            let at = Duration::new(secs, nanos);
            let mut s = Vec::new();
            push_seconds(&mut s, at);
            assert_eq!(s, format!("{:.3}", at.as_secs_f64()).into_bytes(), "{at:?}");
        }
    }

    #[test]
    fn utc_reads_as_humantime_writes_it() {
        let mut utc = UtcMillis::default();
        for ms in [
            1_718_000_000_250u64,
            1_718_000_000_999,
            1_718_000_001_000,
            0,
            253_402_300_799_999,
        ] {
            let t = UNIX_EPOCH + Duration::from_millis(ms) + Duration::from_nanos(999_999);
            let mut s = Vec::new();
            utc.push(&mut s, t);
            assert_eq!(
                s,
                humantime::format_rfc3339_millis(t).to_string().into_bytes(),
                "{ms}"
            );
        }
    }

    proptest! {
        #[test]
        fn any_number_reads_as_formatted(bits in any::<u64>()) {
            let v = f64::from_bits(bits);
            prop_assert_eq!(number(v), number_as_formatted(v));
        }

        #[test]
        fn sample_sized_numbers_read_as_formatted(v in -1e7f64..1e7, places in 0i32..9) {
            let v = (v * 10f64.powi(places)).round() / 10f64.powi(places);
            prop_assert_eq!(number(v), number_as_formatted(v));
        }

        #[test]
        fn any_time_reads_as_formatted(secs in 0u64..10_000_000, nanos in 0u32..1_000_000_000) {
            let at = Duration::new(secs, nanos);
            let mut s = Vec::new();
            push_seconds(&mut s, at);
            prop_assert_eq!(s, format!("{:.3}", at.as_secs_f64()).into_bytes());
        }

        #[test]
        fn any_utc_reads_as_humantime_writes_it(ms in 0u64..4_102_444_800_000, nanos in 0u32..1_000_000) {
            let t = UNIX_EPOCH + Duration::from_millis(ms) + Duration::from_nanos(u64::from(nanos));
            let mut s = Vec::new();
            UtcMillis::default().push(&mut s, t);
            prop_assert_eq!(s, humantime::format_rfc3339_millis(t).to_string().into_bytes());
        }
    }
}
