//! The seeded, portable random number generator of every simulation.
//!
//! xoshiro256++ (from `rand_xoshiro`) seeded through SplitMix64, uniform doubles from the
//! top 53 bits, and normal deviates by the Box-Muller transform with `libm`: the same
//! seed gives the same numbers natively and in WebAssembly, bit for bit.

use rand_core::{Rng as _, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::f64::consts::TAU;

#[derive(Clone, Debug)]
pub struct Rng {
    state: Xoshiro256PlusPlus,
    /// The second deviate of the last Box-Muller pair, not yet handed out.
    spare_normal: Option<f64>,
}

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng {
            state: Xoshiro256PlusPlus::seed_from_u64(seed),
            spare_normal: None,
        }
    }

    /// A new generator for a named part of a simulation, independent of the others, so
    /// that adding draws to one part does not change the others.
    pub fn substream(seed: u64, part: u64) -> Self {
        let mut mixer = Rng::new(seed ^ part.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        Rng::new(mixer.state.next_u64())
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.state.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [low, high).
    pub fn uniform_in(&mut self, low: f64, high: f64) -> f64 {
        low + (high - low) * self.uniform()
    }

    /// Uniform among 0, 1, ..., n - 1 (n > 0).
    pub fn index(&mut self, n: usize) -> usize {
        ((self.uniform() * n as f64) as usize).min(n - 1)
    }

    /// `items` in an order drawn uniformly (Fisher and Yates: each place from the rest).
    pub fn shuffle<T>(&mut self, items: &mut [T]) {
        for i in (1..items.len()).rev() {
            items.swap(i, self.index(i + 1));
        }
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.uniform() < p
    }

    /// Standard normal, by the Box-Muller transform.
    pub fn standard_normal(&mut self) -> f64 {
        if let Some(spare) = self.spare_normal.take() {
            return spare;
        }
        // 1 - U lies in (0, 1], so the logarithm is finite. The square root is IEEE 754's,
        // correctly rounded on every target (an instruction natively and in wasm, where
        // libm's software one costs several times as much), so it is libm's to the bit;
        // `sincos` shares one argument reduction and gives exactly `sin` and `cos`.
        let radius = (-2.0 * libm::log(1.0 - self.uniform())).sqrt();
        let (sin, cos) = libm::sincos(TAU * self.uniform());
        self.spare_normal = Some(radius * sin);
        radius * cos
    }

    /// Standard normal, by the ziggurat method (rand_distr's): several times cheaper than
    /// `standard_normal`, for the particle filter's thousands of draws a step. Its rare
    /// draws from the tails take a logarithm or an exponential, which natively and in
    /// WebAssembly may round apart in the last bit.
    #[inline(always)]
    pub fn ziggurat_normal(&mut self) -> f64 {
        rand_distr::Distribution::sample(&rand_distr::StandardNormal, &mut self.state)
    }

    /// Normal with the given mean and standard deviation.
    pub fn normal(&mut self, mean: f64, std_dev: f64) -> f64 {
        mean + std_dev * self.standard_normal()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sincos_is_sin_and_cos_to_the_bit() {
        // What `standard_normal` and the odometry's step rely on: the angles of
        // Box-Muller, [0, 2 pi), and headings well beyond [-pi, pi).
        let mut rng = Rng::new(11);
        for _ in 0..200_000 {
            for angle in [TAU * rng.uniform(), 20.0 * (rng.uniform() - 0.5)] {
                let (sin, cos) = libm::sincos(angle);
                assert_eq!(sin.to_bits(), libm::sin(angle).to_bits(), "sin {angle}");
                assert_eq!(cos.to_bits(), libm::cos(angle).to_bits(), "cos {angle}");
            }
        }
        for angle in [0.0, -0.0, 1e-300, 1e-9, 1.2e-8, 2e-8, 0.785, -3.0, 1e6] {
            assert_eq!(libm::sincos(angle), (libm::sin(angle), libm::cos(angle)));
        }
    }

    #[test]
    fn same_seed_same_numbers_other_seed_other_numbers() {
        let draw = |seed| {
            let mut rng = Rng::new(seed);
            (0..5).map(|_| rng.standard_normal()).collect::<Vec<_>>()
        };
        assert_eq!(draw(7), draw(7));
        assert_ne!(draw(7), draw(8));
    }

    #[test]
    fn normal_deviates_have_the_right_moments() {
        let mut rng = Rng::new(1);
        let n = 200_000;
        let xs: Vec<f64> = (0..n).map(|_| rng.normal(2.0, 3.0)).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        assert!((mean - 2.0).abs() < 0.03, "mean {mean}");
        assert!((var.sqrt() - 3.0).abs() < 0.03, "std {}", var.sqrt());
    }

    #[test]
    fn uniform_stays_in_range() {
        let mut rng = Rng::new(3);
        assert!((0..10_000).all(|_| (0.0..1.0).contains(&rng.uniform())));
    }

    #[test]
    fn substreams_differ() {
        let a = Rng::substream(5, 1).uniform();
        let b = Rng::substream(5, 2).uniform();
        assert_ne!(a, b);
    }
}
