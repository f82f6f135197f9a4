#include "deploysim/sweep/rng.h"

#include <cmath>

#include "deploysim/math/units.h"

namespace deploysim::sweep {

namespace {

std::uint64_t Rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

constexpr double kInvTwo53 = 1.0 / 9007199254740992.0;  // 2^-53

}  // namespace

std::uint64_t SplitMix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

Rng::Rng(std::uint64_t seed, std::uint64_t sample, std::uint64_t parameter) {
  // Chain the three integers through SplitMix64 so that neighbouring (sample, parameter)
  // pairs give unrelated streams.
  std::uint64_t state = seed;
  state = SplitMix64(state) ^ sample;
  state = SplitMix64(state) ^ parameter;
  for (std::uint64_t& s : s_) s = SplitMix64(state);
}

std::uint64_t Rng::NextU64() {
  const std::uint64_t result = Rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = Rotl(s_[3], 45);
  return result;
}

double Rng::Uniform() { return static_cast<double>(NextU64() >> 11) * kInvTwo53; }

double Rng::Normal() {
  // u1 in (0, 1] so that log(u1) is finite.
  const double u1 = 1.0 - Uniform();
  const double u2 = Uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(math::kTwoPi * u2);
}

std::uint64_t Rng::Below(std::uint64_t n) {
  // Reject the top partial block of 2^64 so that every residue is equally likely.
  const std::uint64_t max = ~std::uint64_t{0};
  const std::uint64_t limit = max - max % n;
  std::uint64_t x = NextU64();
  while (x >= limit) x = NextU64();
  return x % n;
}

}  // namespace deploysim::sweep
