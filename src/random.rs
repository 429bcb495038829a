//! Deterministic numbers: one seeded generator for production (multi-start points,
//! derivative-check samples, the brick study, fuzzing) and for tests and benchmarks, so that
//! every run and machine draws the same numbers from the same seed (no `rand` dependency,
//! no state shared between tests).

/// A 64-bit linear congruential generator (Knuth's MMIX constants). Not for statistics:
/// for sample points, perturbations and mutated inputs that must repeat exactly.
#[derive(Debug, Clone)]
pub struct SeededRng {
    state: u64,
}

impl SeededRng {
    /// A generator whose first draw is the state after one step from `seed`.
    pub fn new(seed: u64) -> Self {
        SeededRng { state: seed }
    }

    /// The generator of item `item` of a run seeded with `seed`: independent of every other
    /// item's, so that one item (a fuzz input, say) can be drawn without drawing those before
    /// it. The state is `seed` and `item` mixed by SplitMix64's finaliser.
    pub fn for_item(seed: u64, item: u64) -> Self {
        let mut z = seed ^ item.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        SeededRng::new(z ^ (z >> 31))
    }

    /// The next raw 64-bit state.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self
            .state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.state
    }

    /// The next number in [0, 1) (53 random bits).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The next number in [−a, a).
    pub fn symmetric(&mut self, a: f64) -> f64 {
        a * (2.0 * self.unit() - 1.0)
    }

    /// `n` numbers in [−a, a).
    pub fn symmetric_vec(&mut self, n: usize, a: f64) -> Vec<f64> {
        (0..n).map(|_| self.symmetric(a)).collect()
    }

    /// The next number in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }

    /// The next index in 0..n (from the state's high bits); `n` must be positive.
    pub fn index(&mut self, n: usize) -> usize {
        ((self.next_u64() >> 33) as usize) % n
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn items_have_their_own_streams() {
        use super::SeededRng;
        let a: Vec<u64> = (0..4)
            .map(|i| SeededRng::for_item(1, i).next_u64())
            .collect();
        // Repeatable, and different per item and per seed.
        assert_eq!(a[2], SeededRng::for_item(1, 2).next_u64());
        for i in 0..4 {
            for j in 0..i {
                assert_ne!(a[i], a[j]);
            }
            assert_ne!(a[i], SeededRng::for_item(2, i as u64).next_u64());
        }
    }

    use super::SeededRng;

    /// Same seed, same sequence; draws stay in their ranges and are spread over them.
    #[test]
    fn repeats_and_stays_in_range() {
        let (mut a, mut b) = (SeededRng::new(7), SeededRng::new(7));
        let xs: Vec<f64> = (0..1000).map(|_| a.symmetric(2.0)).collect();
        let ys: Vec<f64> = (0..1000).map(|_| b.symmetric(2.0)).collect();
        assert_eq!(xs, ys);
        assert!(xs.iter().all(|x| (-2.0..2.0).contains(x)));
        let mean = xs.iter().sum::<f64>() / 1000.0;
        assert!(mean.abs() < 0.2, "mean {mean}");
        assert!(xs.iter().any(|&x| x > 1.5) && xs.iter().any(|&x| x < -1.5));
        let mut c = SeededRng::new(3);
        assert!((0..1000).all(|_| c.index(5) < 5));
        assert_ne!(SeededRng::new(1).unit(), SeededRng::new(2).unit());
    }
}
