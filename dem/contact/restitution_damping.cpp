#include "dem/contact/restitution_damping.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace demcal::dem {
namespace {

// Acceleration of the dimensionless Hertz oscillator; the total force never
// pulls (a non-cohesive contact cannot attract), which is also what the engine does.
double acceleration(double x, double v, double eta) {
  if (x <= 0.0) return 0.0;
  const double a = -std::pow(x, 1.5) - eta * std::pow(x, 0.25) * v;
  return std::min(a, 0.0);
}

}  // namespace

double restitution_for_damping_beta(double beta) {
  if (beta < 0.0) throw std::invalid_argument("damping beta must be >= 0");
  const double eta = std::sqrt(5.0) * beta;
  // Undamped half period in these units is ~3.22; 2e-4 keeps RK4 far below 1e-6 error.
  const double h = 2e-4;
  double x = 0.0;
  double v = 1.0;
  for (int step = 0; step < 2'000'000; ++step) {
    const double k1x = v, k1v = acceleration(x, v, eta);
    const double k2x = v + 0.5 * h * k1v, k2v = acceleration(x + 0.5 * h * k1x, k2x, eta);
    const double k3x = v + 0.5 * h * k2v, k3v = acceleration(x + 0.5 * h * k2x, k3x, eta);
    const double k4x = v + h * k3v, k4v = acceleration(x + h * k3x, k4x, eta);
    const double xn = x + h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double vn = v + h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (xn <= 0.0 && step > 0) {
      // The force vanishes at x = 0, so the speed there is the speed at xn to RK4 accuracy.
      return -vn;
    }
    // Once the damper outweighs the spring on the way out, the total force is
    // clamped to zero and stays so (the damping term decays more slowly with x
    // than the elastic one): the sphere leaves at its present speed.
    if (vn < 0.0 && acceleration(xn, vn, eta) == 0.0) return -vn;
    x = xn;
    v = vn;
  }
  return 0.0;
}

double smallest_resolved_restitution() {
  static const double e = restitution_for_damping_beta(kMaxResolvedDampingBeta);
  return e;
}

double damping_beta_for_restitution(double restitution) {
  if (!(restitution > 0.0 && restitution <= 1.0))
    throw std::invalid_argument("restitution must lie in (0, 1]");
  if (restitution == 1.0) return 0.0;
  if (restitution < smallest_resolved_restitution()) {
    std::ostringstream s;
    s << "restitution " << restitution << " is below the smallest the exact restitution model resolves ("
      << smallest_resolved_restitution() << "); give at least that (or restitution_model = "
      << "\"linear_spring_formula\")";
    throw std::invalid_argument(s.str());
  }
  // The search below integrates the collision some 40 times (~50 ms); every
  // run, every design point and every config check asks again for the same few
  // restitutions, so the answers are remembered. The search is a pure function
  // of its argument: a remembered answer is the bit-identical answer.
  static std::mutex memo_mutex;
  static std::unordered_map<double, double> memo;
  {
    const std::lock_guard<std::mutex> lock(memo_mutex);
    if (const auto it = memo.find(restitution); it != memo.end()) return it->second;
  }
  double lo = 0.0;
  double hi = 1.0;
  while (restitution_for_damping_beta(hi) > restitution) hi = std::min(2.0 * hi, kMaxResolvedDampingBeta);
  for (int it = 0; it < 60 && hi - lo > 1e-12; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (restitution_for_damping_beta(mid) > restitution)
      lo = mid;
    else
      hi = mid;
  }
  const double beta = 0.5 * (lo + hi);
  const std::lock_guard<std::mutex> lock(memo_mutex);
  if (memo.size() >= 4096) memo.clear();  // a fuzzer's stream of new values must not grow it
  memo.emplace(restitution, beta);
  return beta;
}

double linear_spring_damping_beta(double restitution) {
  if (!(restitution > 0.0 && restitution <= 1.0))
    throw std::invalid_argument("restitution must lie in (0, 1]");
  const double l = std::log(restitution);
  return -l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
}

}  // namespace demcal::dem
