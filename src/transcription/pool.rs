//! Whether a derivative callback runs its blocks on rayon's pool or on one thread, chosen by
//! measurement while the solver runs: on an idle 2-core machine the pool nearly halves
//! LittleDog's Jacobian + Hessian, on a loaded one the wait for a worker costs more than it
//! saves (BENCHMARKS.md, issue 16). Both give the same numbers to the bit, so the choice is
//! about time alone.

use std::sync::Mutex;
use std::time::Instant;

/// Calls that try each way in turn before the faster one is used.
const WARM_UP_CALLS: u32 = 4;
/// After the warm-up, one call in this many runs the other way, so that a change of load
/// is noticed.
const PROBE_EVERY: u32 = 16;
/// Weight of the newest time in each way's running mean.
const NEWEST_WEIGHT: f64 = 0.3;

/// The two ways' running mean times of one callback and the call count.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PoolChoice {
    calls: u32,
    /// Running mean seconds on one thread, on the pool (`None` before the first).
    mean: [Option<f64>; 2],
}

impl PoolChoice {
    /// Whether the next call runs on the pool.
    pub fn next_on_pool(&self) -> bool {
        if self.calls < WARM_UP_CALLS {
            return !self.calls.is_multiple_of(2);
        }
        let faster_on_pool = match self.mean {
            [Some(serial), Some(pool)] => pool < serial,
            [None, _] => false,
            [_, None] => true,
        };
        if self.calls.is_multiple_of(PROBE_EVERY) {
            !faster_on_pool
        } else {
            faster_on_pool
        }
    }

    /// Records the seconds a call took on the pool or on one thread.
    pub fn record(&mut self, on_pool: bool, seconds: f64) {
        let mean = &mut self.mean[usize::from(on_pool)];
        *mean = Some(match *mean {
            Some(m) => (1.0 - NEWEST_WEIGHT) * m + NEWEST_WEIGHT * seconds,
            None => seconds,
        });
        self.calls = self.calls.saturating_add(1);
    }
}

/// How a transcription runs its Jacobian and Hessian blocks.
#[derive(Debug)]
pub enum Parallelism {
    /// Always on one thread.
    Serial,
    /// Always on rayon's pool.
    Pool,
    /// Chosen per callback by measurement ([`PoolChoice`]): Jacobian, Hessian.
    Measured(Mutex<[PoolChoice; 2]>),
}

/// The derivative callbacks whose blocks may run on the pool.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Callback {
    /// The constraint Jacobian.
    Jacobian,
    /// The Lagrangian Hessian.
    Hessian,
}

impl Parallelism {
    /// Measured, with no calls yet.
    pub fn measured() -> Self {
        Parallelism::Measured(Mutex::new(Default::default()))
    }

    /// Runs `evaluate(on_pool)` for `callback`, the way chosen as above, and records its time
    /// when measured.
    pub fn run<R>(&self, callback: Callback, evaluate: impl FnOnce(bool) -> R) -> R {
        let choices = match self {
            Parallelism::Serial => return evaluate(false),
            Parallelism::Pool => return evaluate(true),
            Parallelism::Measured(choices) => choices,
        };
        let slot = callback as usize;
        // A poisoned lock only means another thread panicked mid-record: the means are
        // still numbers, so keep using them.
        let on_pool = choices
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)[slot]
            .next_on_pool();
        let start = Instant::now();
        let result = evaluate(on_pool);
        let seconds = start.elapsed().as_secs_f64();
        choices
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)[slot]
            .record(on_pool, seconds);
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Warm-up alternates; then the faster way is used, with one probe of the other way in
    /// every `PROBE_EVERY` calls; when the other way becomes faster the choice follows.
    #[test]
    fn the_faster_way_is_chosen_and_a_change_of_load_is_followed() {
        let mut choice = PoolChoice::default();
        let mut ways = Vec::new();
        // The pool takes 1 ms, one thread 2 ms.
        for _ in 0..40 {
            let on_pool = choice.next_on_pool();
            ways.push(on_pool);
            choice.record(on_pool, if on_pool { 1e-3 } else { 2e-3 });
        }
        assert_eq!(&ways[..4], &[false, true, false, true]);
        let serial_after_warm_up: Vec<usize> = (4..40).filter(|&k| !ways[k]).collect();
        assert_eq!(serial_after_warm_up, vec![16, 32], "{ways:?}");
        // Load arrives: the pool now takes 5 ms. The next probe of one thread (2 ms) and the
        // pool's own rising mean move the choice to one thread.
        let mut later = Vec::new();
        for _ in 0..40 {
            let on_pool = choice.next_on_pool();
            later.push(on_pool);
            choice.record(on_pool, if on_pool { 5e-3 } else { 2e-3 });
        }
        let last_pool = later.iter().rposition(|&p| p).expect("the pool ran");
        assert!(
            later[last_pool + 1..].iter().all(|&p| !p) && last_pool < 30,
            "{later:?}"
        );
        assert!(!choice.next_on_pool() || choice.calls.is_multiple_of(PROBE_EVERY));
    }

    /// Fixed settings never measure.
    #[test]
    fn fixed_settings_run_their_way() {
        assert!(Parallelism::Pool.run(Callback::Hessian, |on_pool| on_pool));
        assert!(!Parallelism::Serial.run(Callback::Jacobian, |on_pool| on_pool));
        let measured = Parallelism::measured();
        let ways: Vec<bool> = (0..4)
            .map(|_| measured.run(Callback::Hessian, |on_pool| on_pool))
            .collect();
        assert_eq!(ways, vec![false, true, false, true]);
        // The Jacobian's choice is its own.
        assert!(!measured.run(Callback::Jacobian, |on_pool| on_pool));
    }
}
