//! Variable frame rate (`synthetic.vfr_jitter`): each frame's time, as the renderer
//! draws it and as the container carries it.
//!
//! Frame `k` is at `t_k = (k + j u_k) / fps`, `u_k` in [0, 1) from the seed (`u_0 = 0`),
//! rounded to the millisecond: a frame arrives late by up to `j` of a frame interval.
//! The times reach the file through FFmpeg's `setpts` filter, whose expression of the
//! frame count `N` is evaluated by FFmpeg in double precision, operation for operation
//! as [`Vfr::ms`] evaluates it here: `u_k` is a quadratic hash of `k` modulo a prime
//! below 2^20 whose every intermediate value is an integer below 2^41 (exact in a
//! double), and the rest is the same sequence of IEEE operations, so both give the same
//! millisecond. The encoder and the container then count in milliseconds.

use super::plan::stream;
use crate::rng::Rng;

/// The hash's modulus, a prime below 2^20.
const M: u64 = 1_048_573;

// Exact integers in a double throughout, for every frame a twin may have: `N^2`, and
// `(N^2 mod M) a + N b` below 2^41 (so that FFmpeg's `mod`, `x - M floor(x / M)`, is
// the exact remainder).
const MOST_FRAMES: u64 = crate::config::MAX_FRAMES as u64 + 1;
const _: () = assert!(MOST_FRAMES * MOST_FRAMES < 1 << 53);
const _: () = assert!((M - 1) * (M - 1) + MOST_FRAMES * (M - 1) < 1 << 41);

/// One video's frame times.
#[derive(Clone, Debug)]
pub(super) struct Vfr {
    /// The largest delay, in frame intervals.
    jitter: f64,
    a: u64,
    b: u64,
    /// `1000 / fps`.
    ms_per_frame: f64,
}

impl Vfr {
    pub(super) fn new(jitter: f64, fps: f64, seed: u64) -> Self {
        let mut rng = Rng::new(stream(seed, 6));
        let a = 1 + rng.next_u64() % (M - 1);
        let b = 1 + rng.next_u64() % (M - 1);
        Self {
            jitter,
            a,
            b,
            ms_per_frame: 1000.0 / fps,
        }
    }

    /// `u_k * M`: `(k^2 mod M) a + k b`, modulo `M`.
    fn hash(&self, k: u64) -> u64 {
        ((k * k % M) * self.a + k * self.b) % M
    }

    /// Time of frame `k`, whole milliseconds.
    pub(super) fn ms(&self, k: usize) -> f64 {
        let u = self.hash(k as u64) as f64;
        ((k as f64 + self.jitter * u / M as f64) * self.ms_per_frame).round()
    }

    /// The FFmpeg filters that give frame `N` the time [`Vfr::ms`] in a 1/1000 s time
    /// base (commas escaped for a filter graph).
    pub(super) fn filters(&self) -> String {
        let (j, a, b, k) = (self.jitter, self.a, self.b, self.ms_per_frame);
        format!("settb=1/1000,setpts=round((N+{j}*mod(mod(N*N\\,{M})*{a}+N*{b}\\,{M})/{M})*{k})")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_start_at_zero_increase_and_stay_within_the_jitter() {
        for (j, fps) in [(0.3, 30.0), (0.9, 25.0), (0.5, 59.94)] {
            let v = Vfr::new(j, fps, 7);
            assert_eq!(v.ms(0), 0.0);
            let mut gaps = Vec::new();
            for k in 1..20_000 {
                let (t, prev) = (v.ms(k), v.ms(k - 1));
                let nominal = k as f64 * 1000.0 / fps;
                assert!(t >= nominal.round() - 0.5 && t <= (nominal + j * 1000.0 / fps).round());
                assert!(t > prev, "{j} {fps}: frame {k} at {t} after {prev}");
                gaps.push(t - prev);
            }
            let (lo, hi) = gaps
                .iter()
                .fold((f64::MAX, f64::MIN), |(l, h), &g| (l.min(g), h.max(g)));
            // Irregular: gaps spread over most of (1 - j, 1 + j) frame intervals.
            assert!(hi - lo > 1.5 * j * 1000.0 / fps, "{j} {fps}: {lo}..{hi}");
        }
    }
}
