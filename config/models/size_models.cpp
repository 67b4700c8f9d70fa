// The size distributions: a section per distribution (its reader and its
// declaration), then the registry that lists them.

#include "config/models/size_models.hpp"

#include <utility>

namespace demcal::config {

namespace {

using reader::Table;
using reader::above;
using reader::at_least;
using reader::between;
using reader::format_number;
using reader::guarded;

const std::string kPositive = range_of(above(0));

// The bounds min_diameter_m <= max_diameter_m that truncate a distribution.
std::pair<double, double> read_bounds(Table& s) {
  const double lo = s.number("min_diameter_m", above(0));
  const double hi = s.number("max_diameter_m", above(0));
  if (hi < lo)
    s.fail("max_diameter_m", "expected a number >= min_diameter_m (" + format_number(lo) +
                                 "), got " + format_number(hi));
  return {lo, hi};
}

std::vector<ModelKey> bound_keys(const std::string& default_text) {
  return {{"min_diameter_m", "m", default_text, kPositive, "the smallest diameter"},
          {"max_diameter_m", "m", default_text, kPositive + ", >= min_diameter_m",
           "the largest diameter"}};
}

ModelInfo with_bounds(ModelInfo info, const std::string& default_text) {
  for (ModelKey& k : bound_keys(default_text)) info.keys.push_back(std::move(k));
  return info;
}

// ---------------------------------------------------------------- monodisperse

std::unique_ptr<dem::SizeDistribution> read_monodisperse(Table& s) {
  const double d = s.number("diameter_m", above(0));
  s.finish();
  return guarded(s, [&] { return dem::make_monodisperse(d); });
}

ModelInfo monodisperse_info() {
  return {"monodisperse",
          "one diameter",
          {{"diameter_m", "m", "required", kPositive, "the diameter"}}};
}

// ---------------------------------------------------------------- uniform

const reader::Range kHalfWidth = between(0, false, 1, true);

std::unique_ptr<dem::SizeDistribution> read_uniform(Table& s) {
  // Two forms: the bounds, or a centre and a relative width (one key a design can vary).
  if (s.has("mean_diameter_m") || s.has("relative_half_width")) {
    for (const char* k : {"min_diameter_m", "max_diameter_m"})
      if (s.contains(k))
        s.fail(k,
               "give min_diameter_m and max_diameter_m, or mean_diameter_m and "
               "relative_half_width, not both forms");
    const double mean = s.number("mean_diameter_m", above(0));
    const double w = s.number("relative_half_width", kHalfWidth);
    s.finish();
    return guarded(s, [&] { return dem::make_uniform_about_mean(mean, w); });
  }
  // Not a structured binding: clang 14 cannot capture one in the lambda below.
  const std::pair<double, double> range = read_bounds(s);
  const double lo = range.first, hi = range.second;
  s.finish();
  return guarded(s, [&] { return dem::make_uniform(lo, hi); });
}

ModelInfo uniform_info() {
  return with_bounds(
      {"uniform",
       "uniform in diameter: between two bounds, or about a mean",
       {{"mean_diameter_m", "m", "with relative_half_width, instead of the bounds", kPositive,
         "the centre"},
        {"relative_half_width", "1", "with mean_diameter_m, instead of the bounds",
         range_of(kHalfWidth), "half the width over the mean (one key a design can vary)"}}},
      "required, unless mean_diameter_m and relative_half_width are given");
}

// ---------------------------------------------------------------- truncated_normal

std::unique_ptr<dem::SizeDistribution> read_truncated_normal(Table& s) {
  const double mean = s.number("mean_diameter_m", above(0));
  const double sd = s.number("std_dev_m", at_least(0));
  // Not a structured binding: clang 14 cannot capture one in the lambda below.
  const std::pair<double, double> range = read_bounds(s);
  const double lo = range.first, hi = range.second;
  s.finish();
  return guarded(s, [&] { return dem::make_truncated_normal(mean, sd, lo, hi); });
}

ModelInfo truncated_normal_info() {
  return with_bounds({"truncated_normal",
                      "a normal distribution of diameters, truncated to the bounds",
                      {{"mean_diameter_m", "m", "required", kPositive, "the untruncated mean"},
                       {"std_dev_m", "m", "required", range_of(at_least(0)),
                        "the untruncated standard deviation"}}},
                     "required");
}

// ---------------------------------------------------------------- log_normal

std::unique_ptr<dem::SizeDistribution> read_log_normal(Table& s) {
  const double median = s.number("median_diameter_m", above(0));
  const double sigma = s.number("sigma_ln", at_least(0));
  // Not a structured binding: clang 14 cannot capture one in the lambda below.
  const std::pair<double, double> range = read_bounds(s);
  const double lo = range.first, hi = range.second;
  s.finish();
  return guarded(s, [&] { return dem::make_log_normal(median, sigma, lo, hi); });
}

ModelInfo log_normal_info() {
  return with_bounds({"log_normal",
                      "a log-normal distribution of diameters, truncated to the bounds",
                      {{"median_diameter_m", "m", "required", kPositive, "the median"},
                       {"sigma_ln", "1", "required", range_of(at_least(0)),
                        "the standard deviation of ln(diameter)"}}},
                     "required");
}

// ---------------------------------------------------------------- sieve

std::unique_ptr<dem::SizeDistribution> read_sieve(Table& s) {
  auto curve = s.number_pairs("sieve", "opening_m, cumulative_fraction_passing");
  s.finish();
  return guarded(s, [&] { return dem::make_sieve_curve(std::move(curve)); });
}

ModelInfo sieve_info() {
  return {"sieve",
          "a measured sieve curve",
          {{"sieve", "m, 1", "required", "[[opening_m, cumulative_fraction_passing], ...]",
            "the cumulative fraction passing each opening"}}};
}

}  // namespace

const SizeRegistry& size_models() {
  // Registration order is the order messages list the distributions in.
  static const SizeRegistry registry = [] {
    SizeRegistry r({"size distribution", "size",
                    "a size table ([material.size], [insertion.size]) with distribution = "
                    "\"<name>\""});
    r.add(monodisperse_info(), &read_monodisperse);
    r.add(uniform_info(), &read_uniform);
    r.add(truncated_normal_info(), &read_truncated_normal);
    r.add(log_normal_info(), &read_log_normal);
    r.add(sieve_info(), &read_sieve);
    return r;
  }();
  return registry;
}

}  // namespace demcal::config
