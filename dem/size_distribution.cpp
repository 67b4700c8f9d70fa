#include "dem/size_distribution.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace demcal::dem {

namespace {

// Truncations that keep fewer draws than this would make the rejection loop
// crawl (over a thousand normals per particle) and almost always mean a typo
// in the parameters, so they are refused rather than silently slow.
constexpr double kMinAcceptance = 1e-3;

// Simpson panels for the truncated moments. The integration window is cut to
// where the integrand is not negligible, so a fixed count resolves it finely
// whatever the ratio of the spread to the truncation interval.
constexpr int kQuadraturePanels = 2000;

// Beyond this many standard deviations the Gaussian factor is below e^-84
// and contributes nothing a double can hold next to the bulk.
constexpr double kGaussianWindow = 13.0;

std::string number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

[[noreturn]] void fail(std::string_view kind, const std::string& what) {
  throw std::invalid_argument("size distribution '" + std::string(kind) + "': " + what);
}

void require_diameter(std::string_view kind, std::string_view name, double value_m) {
  if (!std::isfinite(value_m) || !(value_m > 0.0))
    fail(kind, std::string(name) + " (" + number(value_m) +
                   ") must be a positive, finite diameter in metres");
}

void require_bounds(std::string_view kind, double min_m, double max_m) {
  require_diameter(kind, "min_diameter_m", min_m);
  require_diameter(kind, "max_diameter_m", max_m);
  if (min_m > max_m)
    fail(kind, "min_diameter_m (" + number(min_m) + ") must not exceed max_diameter_m (" +
                   number(max_m) + ")");
}

void require_spread(std::string_view kind, std::string_view name, double value) {
  if (!std::isfinite(value) || value < 0.0)
    fail(kind, std::string(name) + " (" + number(value) + ") must be finite and non-negative");
}

// One display unit for every length in a description, picked from the largest,
// so "300-600 um" rather than "0.0003-0.0006 m".
struct DisplayUnit {
  double per_metre;
  const char* symbol;
};

DisplayUnit unit_for(double largest_m) {
  if (largest_m < 1e-3) return {1e6, "um"};
  if (largest_m < 1.0) return {1e3, "mm"};
  return {1.0, "m"};
}

std::string length(double value_m, DisplayUnit unit) {
  std::ostringstream out;
  out << std::setprecision(4) << value_m * unit.per_metre;
  return out.str();
}

std::string range(double min_m, double max_m, DisplayUnit unit) {
  return length(min_m, unit) + "-" + length(max_m, unit) + " " + unit.symbol;
}

// Phi(beta) - Phi(alpha) for alpha <= beta. Taking the difference on the side
// of the nearer tail keeps its relative accuracy when both limits lie far out,
// which is exactly where the acceptance check has to be trusted.
double normal_probability(double alpha, double beta) {
  constexpr double inv_sqrt2 = 1.0 / std::numbers::sqrt2;
  if (alpha >= 0.0) return 0.5 * (std::erfc(alpha * inv_sqrt2) - std::erfc(beta * inv_sqrt2));
  if (beta <= 0.0) return 0.5 * (std::erfc(-beta * inv_sqrt2) - std::erfc(-alpha * inv_sqrt2));
  return 1.0 - 0.5 * std::erfc(-alpha * inv_sqrt2) - 0.5 * std::erfc(beta * inv_sqrt2);
}

void require_acceptance(std::string_view kind, double acceptance, const std::string& spread) {
  if (!(acceptance >= kMinAcceptance))
    fail(kind, "only a fraction " + number(acceptance) + " of draws from " + spread +
                   " falls inside [min_diameter_m, max_diameter_m] (at least " +
                   number(kMinAcceptance) +
                   " is needed); widen the bounds or move the centre inside them");
}

// Mean of g under the (unnormalised) density f on [lo, hi] by composite
// Simpson; dividing by the same rule's integral of f means the truncated
// density's normalising constant is never needed and its error largely cancels.
template <class Weight, class Density>
double weighted_mean(double lo, double hi, Weight g, Density f) {
  if (!(hi > lo)) return g(lo);
  const double h = (hi - lo) / kQuadraturePanels;
  double num = 0.0;
  double den = 0.0;
  for (int i = 0; i <= kQuadraturePanels; ++i) {
    const double x = (i == kQuadraturePanels) ? hi : lo + i * h;
    const double c = (i == 0 || i == kQuadraturePanels) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    const double fx = f(x);
    num += c * fx * g(x);
    den += c * fx;
  }
  return num / den;
}

class Monodisperse final : public SizeDistribution {
 public:
  explicit Monodisperse(double d_m) : d_m_(d_m) {}
  double sample_diameter_m(Random&) const override { return d_m_; }
  double min_diameter_m() const override { return d_m_; }
  double max_diameter_m() const override { return d_m_; }
  double mean_diameter_cubed_m3() const override { return d_m_ * d_m_ * d_m_; }
  std::string describe() const override {
    const DisplayUnit u = unit_for(d_m_);
    return "monodisperse " + length(d_m_, u) + " " + u.symbol;
  }

 private:
  double d_m_;
};

class Uniform final : public SizeDistribution {
 public:
  // relative_half_width < 0: written as bounds; else as mean +- that fraction.
  Uniform(double min_m, double max_m, double relative_half_width = -1.0)
      : min_m_(min_m), max_m_(max_m), relative_half_width_(relative_half_width) {}
  double sample_diameter_m(Random& rng) const override { return rng.uniform(min_m_, max_m_); }
  double min_diameter_m() const override { return min_m_; }
  double max_diameter_m() const override { return max_m_; }
  double mean_diameter_cubed_m3() const override {
    // (b^4 - a^4) / (4 (b - a)) with the division done symbolically, so that
    // a == b needs no special case and near-equal bounds do not cancel.
    const double a = min_m_;
    const double b = max_m_;
    return (a + b) * (a * a + b * b) / 4.0;
  }
  std::string describe() const override {
    const DisplayUnit u = unit_for(max_m_);
    if (relative_half_width_ < 0.0) return "uniform " + range(min_m_, max_m_, u);
    return "uniform " + length(0.5 * (min_m_ + max_m_), u) + " " + u.symbol + " +- " +
           number(100.0 * relative_half_width_) + " % (" + range(min_m_, max_m_, u) + ")";
  }

 private:
  double min_m_;
  double max_m_;
  double relative_half_width_;
};

class TruncatedNormal final : public SizeDistribution {
 public:
  TruncatedNormal(double mean_m, double sd_m, double min_m, double max_m)
      : mean_m_(mean_m), sd_m_(sd_m), min_m_(min_m), max_m_(max_m) {
    if (sd_m_ == 0.0) {
      mean_d3_m3_ = mean_m_ * mean_m_ * mean_m_;
      return;
    }
    const double lo = std::max(min_m_, mean_m_ - kGaussianWindow * sd_m_);
    const double hi = std::min(max_m_, mean_m_ + kGaussianWindow * sd_m_);
    mean_d3_m3_ = weighted_mean(
        lo, hi, [](double d) { return d * d * d; },
        [this](double d) {
          const double z = (d - mean_m_) / sd_m_;
          return std::exp(-0.5 * z * z);
        });
  }

  double sample_diameter_m(Random& rng) const override {
    if (sd_m_ == 0.0) return mean_m_;
    // Resampling, not clipping: clipping would pile probability onto the bounds.
    for (;;) {
      const double d = mean_m_ + sd_m_ * rng.normal();
      if (d >= min_m_ && d <= max_m_) return d;
    }
  }
  double min_diameter_m() const override { return min_m_; }
  double max_diameter_m() const override { return max_m_; }
  double mean_diameter_cubed_m3() const override { return mean_d3_m3_; }
  std::string describe() const override {
    const DisplayUnit u = unit_for(std::max(max_m_, mean_m_));
    return "truncated normal mean " + length(mean_m_, u) + " " + u.symbol + ", sd " +
           length(sd_m_, u) + " " + u.symbol + ", " + range(min_m_, max_m_, u);
  }

 private:
  double mean_m_;
  double sd_m_;
  double min_m_;
  double max_m_;
  double mean_d3_m3_ = 0.0;
};

class LogNormal final : public SizeDistribution {
 public:
  LogNormal(double median_m, double sigma_ln, double min_m, double max_m)
      : median_m_(median_m),
        mu_ln_(std::log(median_m)),
        sigma_ln_(sigma_ln),
        min_m_(min_m),
        max_m_(max_m) {
    if (sigma_ln_ == 0.0) {
      mean_d3_m3_ = median_m_ * median_m_ * median_m_;
      return;
    }
    // Integrate in t = ln d, where the density is Gaussian. Weighting by
    // e^{3t} moves the bulk up by 3 sigma^2, so the window reaches that far.
    const double s = sigma_ln_;
    const double lo = std::max(std::log(min_m_), mu_ln_ - kGaussianWindow * s);
    const double hi = std::min(std::log(max_m_), mu_ln_ + 3.0 * s * s + kGaussianWindow * s);
    // d^3 is taken relative to the window's top so wide windows cannot overflow.
    const double ratio = weighted_mean(
        lo, hi, [hi](double t) { return std::exp(3.0 * (t - hi)); },
        [this](double t) {
          const double z = (t - mu_ln_) / sigma_ln_;
          return std::exp(-0.5 * z * z);
        });
    mean_d3_m3_ = ratio * std::exp(3.0 * hi);
  }

  double sample_diameter_m(Random& rng) const override {
    if (sigma_ln_ == 0.0) return median_m_;
    for (;;) {
      const double d = std::exp(mu_ln_ + sigma_ln_ * rng.normal());
      if (d >= min_m_ && d <= max_m_) return d;
    }
  }
  double min_diameter_m() const override { return min_m_; }
  double max_diameter_m() const override { return max_m_; }
  double mean_diameter_cubed_m3() const override { return mean_d3_m3_; }
  std::string describe() const override {
    const DisplayUnit u = unit_for(std::max(max_m_, median_m_));
    return "log-normal median " + length(median_m_, u) + " " + u.symbol + ", sigma_ln " +
           number(sigma_ln_) + ", " + range(min_m_, max_m_, u);
  }

 private:
  double median_m_;
  double mu_ln_;
  double sigma_ln_;
  double min_m_;
  double max_m_;
  double mean_d3_m3_ = 0.0;
};

class SieveCurve final : public SizeDistribution {
 public:
  // openings_m[k], openings_m[k+1] bound class k; cumulative_number[k+1] is the
  // number fraction of particles in classes 0..k, with the last entry exactly 1.
  SieveCurve(std::vector<double> openings_m, std::vector<double> cumulative_number,
             double mean_d3_m3, double min_m, double max_m, std::size_t classes)
      : openings_m_(std::move(openings_m)),
        cumulative_number_(std::move(cumulative_number)),
        mean_d3_m3_(mean_d3_m3),
        min_m_(min_m),
        max_m_(max_m),
        classes_(classes) {}

  double sample_diameter_m(Random& rng) const override {
    // upper_bound (strictly greater) can never land on an empty class, whose
    // cumulative value equals its predecessor's.
    const double u_class = rng.uniform();
    const auto it =
        std::upper_bound(cumulative_number_.begin() + 1, cumulative_number_.end(), u_class);
    const auto k = static_cast<std::size_t>(it - cumulative_number_.begin()) - 1;
    const double a = openings_m_[k];
    const double b = openings_m_[k + 1];
    // Inverse CDF of a density ~ d^-3 on [a, b]: 1/d^2 is linear in the
    // probability, and as a convex combination it stays inside [a, b].
    const double u = rng.uniform();
    return 1.0 / std::sqrt((1.0 - u) / (a * a) + u / (b * b));
  }
  double min_diameter_m() const override { return min_m_; }
  double max_diameter_m() const override { return max_m_; }
  double mean_diameter_cubed_m3() const override { return mean_d3_m3_; }
  std::string describe() const override {
    return "sieve curve, " + std::to_string(classes_) + " classes, " +
           range(min_m_, max_m_, unit_for(max_m_));
  }

 private:
  std::vector<double> openings_m_;
  std::vector<double> cumulative_number_;
  double mean_d3_m3_;
  double min_m_;
  double max_m_;
  std::size_t classes_;
};

}  // namespace

std::unique_ptr<SizeDistribution> make_monodisperse(double diameter_m) {
  require_diameter("monodisperse", "diameter_m", diameter_m);
  return std::make_unique<Monodisperse>(diameter_m);
}

std::unique_ptr<SizeDistribution> make_uniform(double min_diameter_m, double max_diameter_m) {
  require_bounds("uniform", min_diameter_m, max_diameter_m);
  return std::make_unique<Uniform>(min_diameter_m, max_diameter_m);
}

std::unique_ptr<SizeDistribution> make_uniform_about_mean(double mean_diameter_m,
                                                          double relative_half_width) {
  require_diameter("uniform", "mean_diameter_m", mean_diameter_m);
  // w = 1 would put the smallest particle at zero size.
  if (!std::isfinite(relative_half_width) || relative_half_width < 0.0 ||
      relative_half_width >= 1.0)
    fail("uniform", "relative_half_width (" + number(relative_half_width) +
                        ") must lie in [0, 1): the diameters span mean_diameter_m * (1 -+ "
                        "relative_half_width)");
  return std::make_unique<Uniform>(mean_diameter_m * (1.0 - relative_half_width),
                                   mean_diameter_m * (1.0 + relative_half_width),
                                   relative_half_width);
}

std::unique_ptr<SizeDistribution> make_truncated_normal(double mean_diameter_m,
                                                        double std_dev_m, double min_diameter_m,
                                                        double max_diameter_m) {
  constexpr std::string_view kind = "truncated normal";
  require_diameter(kind, "mean_diameter_m", mean_diameter_m);
  require_spread(kind, "std_dev_m", std_dev_m);
  require_bounds(kind, min_diameter_m, max_diameter_m);
  if (std_dev_m == 0.0) {
    if (mean_diameter_m < min_diameter_m || mean_diameter_m > max_diameter_m)
      fail(kind, "with std_dev_m 0, mean_diameter_m (" + number(mean_diameter_m) +
                     ") must lie inside [min_diameter_m, max_diameter_m]");
  } else {
    const double alpha = (min_diameter_m - mean_diameter_m) / std_dev_m;
    const double beta = (max_diameter_m - mean_diameter_m) / std_dev_m;
    require_acceptance(kind, normal_probability(alpha, beta),
                       "normal(mean_diameter_m, std_dev_m)");
  }
  return std::make_unique<TruncatedNormal>(mean_diameter_m, std_dev_m, min_diameter_m,
                                           max_diameter_m);
}

std::unique_ptr<SizeDistribution> make_log_normal(double median_diameter_m, double sigma_ln,
                                                  double min_diameter_m, double max_diameter_m) {
  constexpr std::string_view kind = "log-normal";
  require_diameter(kind, "median_diameter_m", median_diameter_m);
  require_spread(kind, "sigma_ln", sigma_ln);
  require_bounds(kind, min_diameter_m, max_diameter_m);
  if (sigma_ln == 0.0) {
    if (median_diameter_m < min_diameter_m || median_diameter_m > max_diameter_m)
      fail(kind, "with sigma_ln 0, median_diameter_m (" + number(median_diameter_m) +
                     ") must lie inside [min_diameter_m, max_diameter_m]");
  } else {
    const double mu = std::log(median_diameter_m);
    const double alpha = (std::log(min_diameter_m) - mu) / sigma_ln;
    const double beta = (std::log(max_diameter_m) - mu) / sigma_ln;
    require_acceptance(kind, normal_probability(alpha, beta),
                       "log-normal(median_diameter_m, sigma_ln)");
  }
  return std::make_unique<LogNormal>(median_diameter_m, sigma_ln, min_diameter_m,
                                     max_diameter_m);
}

std::unique_ptr<SizeDistribution> make_sieve_curve(
    std::vector<std::pair<double, double>> opening_m_and_fraction_passing) {
  constexpr std::string_view kind = "sieve curve";
  const std::string table = "opening_m_and_fraction_passing";
  auto& rows = opening_m_and_fraction_passing;
  if (rows.size() < 2)
    fail(kind, table + " needs at least 2 rows (sieve opening, fraction passing), got " +
                   std::to_string(rows.size()));

  // Cumulative sums typed by hand or read from a lab sheet rarely hit 1 to the
  // last bit; a difference this small is rounding, not a different curve.
  constexpr double kEndTolerance = 1e-9;

  const std::size_t last = rows.size() - 1;
  for (std::size_t i = 0; i <= last; ++i) {
    const std::string row = table + "[" + std::to_string(i) + "]";
    const auto [d, f] = rows[i];
    if (!std::isfinite(d) || !(d > 0.0))
      fail(kind, row + ": the sieve opening (" + number(d) +
                     ") must be a positive, finite diameter in metres");
    if (i > 0 && !(d > rows[i - 1].first))
      fail(kind, row + ": the sieve opening (" + number(d) +
                     ") must be larger than the previous one (" + number(rows[i - 1].first) +
                     "); list sieves from finest to coarsest");
    if (!std::isfinite(f) || f < 0.0 || f > 1.0 + kEndTolerance)
      fail(kind, row + ": the fraction passing (" + number(f) + ") must lie in [0, 1]");
    // Mass below the finest sieve would have no lower size to spread over, so
    // the finest opening is taken as the smallest particle in the material.
    if (i == 0 && f > kEndTolerance)
      fail(kind, row + ": the fraction passing the finest sieve must be 0 (its opening is the "
                       "smallest particle size), got " +
                     number(f));
    if (i == last && f < 1.0 - kEndTolerance)
      fail(kind, row + ": the fraction passing the coarsest sieve must be 1, got " + number(f));
    // Snapped before the order check, so rounding at either end cannot make a
    // valid curve look decreasing.
    const double snapped = (i == 0) ? 0.0 : (i == last) ? 1.0 : std::min(f, 1.0);
    if (i > 0 && snapped < rows[i - 1].second)
      fail(kind, row + ": the fraction passing (" + number(f) +
                     ") must not be less than the previous one (" + number(rows[i - 1].second) +
                     ")");
    rows[i].second = snapped;
  }

  // Mass spread uniformly over [a, b] with number density ~ mass density / d^3
  // gives a class number weight m (a + b) / (2 a^2 b^2).
  const std::size_t classes = rows.size() - 1;
  std::vector<double> openings_m(rows.size());
  std::vector<double> cumulative(rows.size(), 0.0);
  openings_m[0] = rows[0].first;
  std::size_t first_filled = classes;
  std::size_t last_filled = 0;
  for (std::size_t k = 0; k < classes; ++k) {
    const double a = rows[k].first;
    const double b = rows[k + 1].first;
    const double mass = rows[k + 1].second - rows[k].second;
    openings_m[k + 1] = b;
    cumulative[k + 1] = cumulative[k] + mass * (a + b) / (2.0 * a * a * b * b);
    if (mass > 0.0) {
      first_filled = std::min(first_filled, k);
      last_filled = k;
    }
  }
  const double total_number = cumulative.back();
  // Each class's mean d^3 is 2 a^2 b^2 / (a + b), which cancels its number
  // weight to leave its mass fraction: mean d^3 = total mass / total number.
  const double mean_d3_m3 = 1.0 / total_number;
  // Dividing the running sum by its own last value gives exactly 1 from the
  // last filled class on, so a trailing empty class can never be drawn.
  for (double& c : cumulative) c /= total_number;

  return std::make_unique<SieveCurve>(std::move(openings_m), std::move(cumulative), mean_d3_m3,
                                      rows[first_filled].first, rows[last_filled + 1].first,
                                      classes);
}

}  // namespace demcal::dem
