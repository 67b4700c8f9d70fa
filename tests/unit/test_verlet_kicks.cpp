// The integrator's two particle loops (dem/verlet_kicks.hpp) against the
// scalar loops they replaced (dem/simulation.cpp at 4d3b4b7): the same bits
// for every particle, in whichever instruction-set version the loader picked,
// and the same verdict of the stability check for every way a particle can
// fail it.
#include "dem/verlet_kicks.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace demcal::dem {
namespace {

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

struct State {
  std::vector<Vec3> x, v, w, f, t, f_before, t_before, x_build;
  std::vector<double> im, ii;
  KickArrays arrays() { return {x.data(), v.data(), w.data(), im.data(), ii.data()}; }
};

State random_state(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto vec = [&](double scale) { return Vec3{scale * u(rng), scale * u(rng), scale * u(rng)}; };
  State s;
  for (std::size_t i = 0; i < n; ++i) {
    s.x.push_back(vec(0.05));
    s.v.push_back(vec(1.0));
    s.w.push_back(vec(100.0));
    s.f.push_back(vec(1e-3));
    s.t.push_back(vec(1e-7));
    s.f_before.push_back(vec(1e-3));
    s.t_before.push_back(vec(1e-7));
    s.x_build.push_back(s.x.back() + vec(1e-4));
    s.im.push_back(1.0 / (1e-5 * (1.5 + u(rng))));
    s.ii.push_back(1.0 / (1e-11 * (1.5 + u(rng))));
  }
  return s;
}

TEST(VerletKicks, KickAndDriftRoundsAsTheScalarLoop) {
  const std::size_t n = 1003;  // not a multiple of any vector width
  const double dt = 1e-5, h = 0.5 * dt;
  State s = random_state(n, 7);
  State ref = s;
  double max_move2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {  // the loop of 4d3b4b7
    const Vec3 dv = (h * ref.im[i]) * ref.f[i];
    const Vec3 dw = (h * ref.ii[i]) * ref.t[i];
    ref.x[i] += dt * (ref.v[i] + dv);
    ref.v[i] += 2.0 * dv;
    ref.w[i] += 2.0 * dw;
    max_move2 = std::max(max_move2, norm2(ref.x[i] - ref.x_build[i]));
  }
  // Split in two ranges, as two chunks of a team would run it.
  const double limit = 0.5 * std::sqrt(max_move2);
  const bool first =
      kick_and_drift(s.arrays(), s.f.data(), s.t.data(), s.x_build.data(), limit, 0, 500, dt);
  const bool second =
      kick_and_drift(s.arrays(), s.f.data(), s.t.data(), s.x_build.data(), limit, 500, n, dt);
  EXPECT_TRUE(first || second);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_TRUE(same_bits(s.x[i], ref.x[i])) << "position of particle " << i;
    ASSERT_TRUE(same_bits(s.v[i], ref.v[i])) << "velocity of particle " << i;
    ASSERT_TRUE(same_bits(s.w[i], ref.w[i])) << "angular velocity of particle " << i;
  }
}

TEST(VerletKicks, KickAndDriftFlagsAParticleBeyondTheLimit) {
  const std::size_t n = 64;
  State s = random_state(n, 11);
  for (auto& f : s.f) f = {};
  for (auto& v : s.v) v = {};
  for (std::size_t i = 0; i < n; ++i) s.x_build[i] = s.x[i] - Vec3{1e-4, 0, 0};
  // Every particle has moved 1e-4 m since the build.
  EXPECT_FALSE(
      kick_and_drift(s.arrays(), s.f.data(), s.t.data(), s.x_build.data(), 1.0001e-4, 0, n, 1e-5));
  s.x_build[37].x -= 1e-6;
  EXPECT_TRUE(
      kick_and_drift(s.arrays(), s.f.data(), s.t.data(), s.x_build.data(), 1.0001e-4, 0, n, 1e-5));
  EXPECT_FALSE(
      kick_and_drift(s.arrays(), s.f.data(), s.t.data(), s.x_build.data(), 1.0001e-4, 0, 37, 1e-5));
  // No build to compare with: nothing to flag.
  EXPECT_FALSE(kick_and_drift(s.arrays(), s.f.data(), s.t.data(), nullptr, 0.0, 0, n, 1e-5));
  // A NaN position is left to the stability check, as std::max left it.
  s.x_build[37] = s.x[37] - Vec3{1e-4, 0, 0};
  s.x[20].y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(
      kick_and_drift(s.arrays(), s.f.data(), s.t.data(), s.x_build.data(), 1.0001e-4, 0, n, 1e-5));
}

TEST(VerletKicks, CorrectionRoundsAsTheScalarLoop) {
  const std::size_t n = 1001;
  const double dt = 1e-5, h = 0.5 * dt;
  State s = random_state(n, 13);
  State ref = s;
  for (std::size_t i = 0; i < n; ++i) {
    ref.v[i] += (h * ref.im[i]) * (ref.f[i] - ref.f_before[i]);
    ref.w[i] += (h * ref.ii[i]) * (ref.t[i] - ref.t_before[i]);
  }
  StabilityBounds bounds{{-1, -1, -1}, {1, 1, 1}, 100.0};
  EXPECT_EQ(correct_and_check(s.arrays(), s.f.data(), s.f_before.data(), s.t.data(),
                              s.t_before.data(), 0, n, dt, bounds, n),
            n);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_TRUE(same_bits(s.v[i], ref.v[i])) << "velocity of particle " << i;
    ASSERT_TRUE(same_bits(s.w[i], ref.w[i])) << "angular velocity of particle " << i;
  }
}

// Every way to fail the check of 4d3b4b7 (not finite, outside a bounded axis,
// too fast), placed at a few particles, some of them in the same vector.
TEST(VerletKicks, StabilityCheckReportsTheFirstFailingParticle) {
  const std::size_t n = 100;
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // x bounded in [-1, 1], y periodic, z bounded in [-1, 1]; at most 10 m/s.
  const StabilityBounds bounds{{-1, -DBL_MAX, -1}, {1, DBL_MAX, 1}, 100.0};
  struct Failure {
    const char* what;
    void (*make)(State&, std::size_t, double, double);
  };
  const Failure failures[] = {
      {"NaN position", [](State& s, std::size_t i, double, double q) { s.x[i].z = q; }},
      {"infinite position on the periodic axis",
       [](State& s, std::size_t i, double r, double) { s.x[i].y = -r; }},
      {"outside a bounded axis", [](State& s, std::size_t i, double, double) { s.x[i].x = 1.5; }},
      {"on the boundary is inside (no failure)",
       [](State& s, std::size_t i, double, double) { s.x[i].x = -1.0; }},
      {"far out on the periodic axis is fine (no failure)",
       [](State& s, std::size_t i, double, double) { s.x[i].y = 1e300; }},
      {"NaN velocity", [](State& s, std::size_t i, double, double q) { s.v[i].x = q; }},
      {"infinite velocity", [](State& s, std::size_t i, double r, double) { s.v[i].y = r; }},
      {"too fast",
       [](State& s, std::size_t i, double, double) {
         s.v[i] = {6.0, 6.0, 6.0};
       }},
  };
  for (const Failure& failure : failures) {
    for (const std::size_t at : {std::size_t{0}, std::size_t{13}, std::size_t{99}}) {
      State s = random_state(n, 17);
      for (auto& x : s.x) x = x * 10.0;  // within [-0.5, 0.5]
      failure.make(s, at, inf, nan);
      if (at != 99) failure.make(s, 99, inf, nan);  // a later failure is not the first
      const bool fails = std::string(failure.what).find("no failure") == std::string::npos;
      const std::size_t got =
          correct_and_check(s.arrays(), s.f.data(), s.f_before.data(), s.t.data(),
                            s.t_before.data(), 0, n, 1e-5, bounds, n);
      EXPECT_EQ(got, fails ? at : n) << failure.what << " at particle " << at;
      // The scalar check of 4d3b4b7 on the corrected state.
      std::size_t expected = n;
      for (std::size_t i = 0; i < n && expected == n; ++i) {
        const auto finite = [](const Vec3& a) {
          return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
        };
        bool bad = !finite(s.x[i]) || !finite(s.v[i]) || norm2(s.v[i]) > 100.0;
        if (!(s.x[i].x >= -1 && s.x[i].x <= 1) || !(s.x[i].z >= -1 && s.x[i].z <= 1)) bad = true;
        if (bad) expected = i;
      }
      EXPECT_EQ(got, expected) << failure.what << " at particle " << at;
    }
  }
}

}  // namespace
}  // namespace demcal::dem
