#pragma once

/// Counter-based, portable random numbers for Monte Carlo sweeps. The draws of one
/// (seed, sample, parameter) triple are a pure function of those three integers: no
/// global or shared state, identical on every thread, rank and run (STYLE.md: no global
/// RNGs). std:: distributions are implementation-defined, so the transforms are here:
///   stream seed = SplitMix64 chain over (seed, sample, parameter),
///   generator   = xoshiro256** (Blackman & Vigna 2018) seeded by SplitMix64,
///   uniform     = top 53 bits / 2^53 in [0, 1),
///   normal      = Box-Muller (uses std::log, std::sqrt, std::cos: bit-identical for a
///                 given build and C library).

#include <cstdint>

namespace deploysim::sweep {

/// One step of SplitMix64 (Steele, Lea, Flood 2014): advances `state`, returns the output.
std::uint64_t SplitMix64(std::uint64_t& state);

class Rng {
 public:
  /// The stream of parameter `parameter` of Monte Carlo sample `sample` under `seed`.
  Rng(std::uint64_t seed, std::uint64_t sample, std::uint64_t parameter);

  std::uint64_t NextU64();
  /// Uniform in [0, 1) with 53 random bits.
  double Uniform();
  /// Uniform in [lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  /// Standard normal (Box-Muller; one draw per call, the partner value is discarded so
  /// that the k-th call does not depend on how earlier values were used).
  double Normal();
  /// Uniform integer in [0, n) (n > 0), without modulo bias (rejection sampling).
  std::uint64_t Below(std::uint64_t n);

 private:
  std::uint64_t s_[4];
};

}  // namespace deploysim::sweep
