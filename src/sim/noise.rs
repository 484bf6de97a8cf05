//! A tiny deterministic noise source (xorshift64*) for the simulated drive's measurements.
//! It must stay seedable and free of global state, so two simulators with the same seed fed
//! the same bytes at the same times produce identical replies; it is not for cryptography.

/// xorshift64* generator. Chosen over a crate because the simulator needs a few uniform
/// numbers per telegram, bit-for-bit reproducible across platforms and versions.
#[derive(Debug, Clone)]
pub(crate) struct XorShift64 {
    state: u64,
}

impl XorShift64 {
    pub(crate) fn new(seed: u64) -> Self {
        // splitmix64 spreads small seeds (0, 1, 2 …) over the whole state, and xorshift
        // must never start at 0, where it would stay forever.
        let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        XorShift64 {
            state: if z == 0 { 0x2545_F491_4F6C_DD1D } else { z },
        }
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        let mut x = self.state;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.state = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in [-1, 1): the top 53 bits make an exact f64 fraction.
    pub(crate) fn symmetric(&mut self) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        unit * 2.0 - 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_sequence_different_seed_different_sequence() {
        let mut a = XorShift64::new(7);
        let mut b = XorShift64::new(7);
        let mut c = XorShift64::new(8);
        let sa: Vec<u64> = (0..5).map(|_| a.next_u64()).collect();
        let sb: Vec<u64> = (0..5).map(|_| b.next_u64()).collect();
        let sc: Vec<u64> = (0..5).map(|_| c.next_u64()).collect();
        assert_eq!(sa, sb);
        assert_ne!(sa, sc);
    }

    #[test]
    fn zero_seed_is_usable_and_symmetric_stays_in_range() {
        let mut r = XorShift64::new(0);
        let mut lo = 0.0f64;
        let mut hi = 0.0f64;
        for _ in 0..10_000 {
            let v = r.symmetric();
            assert!((-1.0..1.0).contains(&v), "{v}");
            lo = lo.min(v);
            hi = hi.max(v);
        }
        // Covers both signs, nearly the whole interval.
        assert!(lo < -0.99 && hi > 0.99, "{lo} {hi}");
    }
}
