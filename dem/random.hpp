#pragma once
// The engine's random numbers. std::mt19937_64 is specified bit for bit by the
// standard; the standard distributions are not, so the conversions to uniform
// and normal variates are written here and runs repeat on any platform.

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace demcal::dem {

class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}

  // Uniform in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Standard normal (Box–Muller; the second variate is discarded to keep state simple).
  double normal() {
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }
  std::uint64_t bits() { return engine_(); }

 private:
  std::mt19937_64 engine_;
};

}  // namespace demcal::dem
