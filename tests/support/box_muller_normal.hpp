#pragma once
// Standard normal deviates for statistical tests that must draw the same numbers with every
// standard library: Box-Muller on std::mt19937_64's bits (whose output the standard fixes),
// not std::normal_distribution (whose algorithm it does not).

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace demcal::testing {

struct BoxMullerNormal {
  explicit BoxMullerNormal(std::uint64_t seed) : rng(seed) {}
  double operator()() {
    const double u1 = (static_cast<double>(rng() >> 11) + 1.0) * 0x1.0p-53;
    const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }
  std::mt19937_64 rng;
};

}  // namespace demcal::testing
