#include "dem/measure/angle_of_repose.hpp"

#include "dem/measure/robust_line_fit.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace demcal::dem {
namespace {

// The most bins a measured surface profile may span (measure_profile_angle_of_repose).
constexpr double kMaxProfileBins = 1e6;


constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRadToDeg = 180.0 / std::numbers::pi;
// A grain resting on the floor tops out at base + d; the extra quarter
// diameter lets a slightly larger grain of a polydisperse mix count as "floor".
constexpr double kToeHeightDiameters = 1.25;
// The cone's column grid is dense; beyond this many cells a stray grain far
// away has blown up the extent and a selection box is the fix.
constexpr std::size_t kMaxGridCells = 50'000'000;

std::string fmt(double v, int precision = 3) {
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

std::string percent(double fraction) { return fmt(100.0 * fraction, 4) + " %"; }

double median(std::vector<double> v) {
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  const double upper = v[mid];
  if (v.size() % 2 == 1) return upper;
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
}

void validate_common(const std::vector<Vec3>& position_m, const std::vector<double>& radius_m,
                     const AoRCommonOptions& o) {
  if (position_m.size() != radius_m.size())
    throw std::invalid_argument("angle of repose: " + std::to_string(position_m.size()) +
                                " positions but " + std::to_string(radius_m.size()) + " radii");
  if (!(o.bin_width_diameters > 0.0) || !std::isfinite(o.bin_width_diameters))
    throw std::invalid_argument("angle of repose: bin_width_diameters must be positive");
  if (!(o.lower_fraction >= 0.0 && o.lower_fraction < o.upper_fraction && o.upper_fraction <= 1.0))
    throw std::invalid_argument(
        "angle of repose: need 0 <= lower_fraction < upper_fraction <= 1 (got " +
        fmt(o.lower_fraction) + ", " + fmt(o.upper_fraction) + ")");
  if (o.min_points < 3)
    throw std::invalid_argument(
        "angle of repose: min_points must be at least 3 (a line "
        "through 2 points has nothing left to judge it by)");
  if (!(o.min_drop_fraction >= 0.0))
    throw std::invalid_argument("angle of repose: min_drop_fraction must be >= 0");
  if (!std::isfinite(o.base_height_m))
    throw std::invalid_argument("angle of repose: base_height_m must be finite");
  if (o.selection) {
    const SelectionBox& b = *o.selection;
    if (!(b.min_m.x <= b.max_m.x && b.min_m.y <= b.max_m.y && b.min_m.z <= b.max_m.z))
      throw std::invalid_argument("angle of repose: selection box has min_m above max_m");
  }
}

// Indices of the particles that take part, and their median diameter.
struct Selection {
  std::vector<std::size_t> index;
  double diameter_m = kNaN;
};

Selection select_particles(const std::vector<Vec3>& position_m, const std::vector<double>& radius_m,
                           const AoRCommonOptions& o) {
  Selection sel;
  std::vector<double> diameters;
  for (std::size_t i = 0; i < position_m.size(); ++i) {
    const Vec3& p = position_m[i];
    if (!is_finite(p) || !(radius_m[i] > 0.0) || !std::isfinite(radius_m[i])) continue;
    if (o.selection) {
      const SelectionBox& b = *o.selection;
      if (p.x < b.min_m.x || p.y < b.min_m.y || p.z < b.min_m.z || p.x > b.max_m.x ||
          p.y > b.max_m.y || p.z > b.max_m.z)
        continue;
    }
    sel.index.push_back(i);
    diameters.push_back(2.0 * radius_m[i]);
  }
  if (sel.index.empty())
    throw std::runtime_error(
        "angle of repose: no particles to measure (none given, or none "
        "inside the selection box)");
  sel.diameter_m = median(std::move(diameters));
  return sel;
}

// One side's surface profile: bins along the side's coordinate s.
struct Profile {
  std::vector<double> centre_m;  // bin centre s
  std::vector<double> height_m;  // above the base; NaN without data
  // Where the height was taken: the s of the particle that set it (slice), the
  // mean radius of the columns averaged (cone). A bin is 1.5 d wide, which on
  // a 40 deg slope is more than a diameter of height: attributing the height to
  // the bin centre instead adds that much aliasing noise to every point.
  std::vector<double> at_s_m;
  // A bin without particles holds no data and walks step over it: near the
  // axis a cone sector's bin may be too small to hold a column, and a column
  // cell cut by a wall or the selection box may be empty although the pile
  // stands right next to it — calling either "floor" would end a slope early.
  std::vector<char> has_data;

  explicit Profile(std::size_t n)
      : centre_m(n, kNaN), height_m(n, kNaN), at_s_m(n, kNaN), has_data(n, 0) {}
  std::size_t size() const { return height_m.size(); }
  void add(std::size_t k, double s_m, double h_m) {
    if (!has_data[k] || h_m > height_m[k]) {
      height_m[k] = h_m;
      at_s_m[k] = s_m;
      has_data[k] = 1;
    }
  }
};

// Index of the crest: maximum of the 3-bin running mean over bins with data.
// Returns size() when the profile is empty.
std::size_t crest_index(const Profile& p) {
  std::size_t best = p.size();
  double best_mean = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (!p.has_data[k]) continue;
    double sum = 0.0;
    int n = 0;
    for (std::size_t j = (k == 0 ? 0 : k - 1); j <= std::min(k + 1, p.size() - 1); ++j)
      if (p.has_data[j]) {
        sum += p.height_m[j];
        ++n;
      }
    if (sum / n > best_mean) {
      best_mean = sum / n;
      best = k;
    }
  }
  return best;
}

// The raw maximum among the bins around k: the crest height.
double raw_max_around(const Profile& p, std::size_t k) {
  double h = -std::numeric_limits<double>::infinity();
  for (std::size_t j = (k == 0 ? 0 : k - 1); j <= std::min(k + 1, p.size() - 1); ++j)
    if (p.has_data[j]) h = std::max(h, p.height_m[j]);
  return h;
}

struct SideSetup {
  std::string name;
  std::string label;          // for messages: "left side", "sector_3 (135-180 deg)"
  int step = 1;               // bin index direction of "outward"
  double outward_sign = 1.0;  // +1 when s grows outward
};

struct Thresholds {
  double crest_height_m;
  double lower_m;
  double upper_m;
  double end_m;  // the walk ends below this
  double toe_m;
};

Thresholds thresholds(double crest_height_m, double d_m, const AoRCommonOptions& o) {
  Thresholds t;
  t.crest_height_m = crest_height_m;
  t.lower_m = o.lower_fraction * crest_height_m;
  t.upper_m = o.upper_fraction * crest_height_m;
  t.toe_m = kToeHeightDiameters * d_m;
  t.end_m = std::max(t.lower_m, t.toe_m);
  return t;
}

AoRSide analyse_side(const Profile& p, std::size_t crest, const SideSetup& setup,
                     const Thresholds& t, const AoRCommonOptions& o) {
  AoRSide side;
  side.name = setup.name;
  const auto in_range = [&](std::ptrdiff_t k) {
    return k >= 0 && k < static_cast<std::ptrdiff_t>(p.size());
  };

  std::vector<double> s, h;
  bool fit_ended = false;
  for (std::ptrdiff_t k = static_cast<std::ptrdiff_t>(crest) + setup.step; in_range(k);
       k += setup.step) {
    const auto ku = static_cast<std::size_t>(k);
    if (!p.has_data[ku]) continue;
    const double hk = p.height_m[ku];
    if (!fit_ended && hk < t.end_m) fit_ended = true;
    if (!fit_ended && hk >= t.lower_m && hk <= t.upper_m) {
      s.push_back(p.at_s_m[ku]);
      h.push_back(hk);
    }
    if (hk <= t.toe_m) {
      side.toe_found = true;
      side.toe_position_m = p.centre_m[ku];
      break;
    }
  }
  side.points = static_cast<int>(s.size());
  const std::string bins_in_band =
      std::to_string(side.points) + (side.points == 1 ? " bin " : " bins ") + "between " +
      percent(o.lower_fraction) + " and " + percent(o.upper_fraction) + " of the crest height";
  if (side.points < o.min_points) {
    side.invalid_reason =
        setup.label + " has " + bins_in_band + " (needs " + std::to_string(o.min_points) + ")";
    return side;
  }

  const LineFit fit = fit_line_bisquare(s, h);
  side.slope = fit.slope;
  side.intercept_m = fit.intercept;
  side.rejected_points = static_cast<int>(fit.rejected);
  const auto [lo, hi] = std::minmax_element(s.begin(), s.end());
  side.fit_from_m = *lo;
  side.fit_to_m = *hi;
  const double tan_angle = -setup.outward_sign * fit.slope;
  side.angle_deg = std::atan(tan_angle) * kRadToDeg;
  side.std_error_deg = fit.slope_std_error / (1.0 + fit.slope * fit.slope) * kRadToDeg;

  const double drop_m = tan_angle * (*hi - *lo);
  const double band_m = t.upper_m - t.lower_m;
  if (!(drop_m >= o.min_drop_fraction * band_m)) {
    side.invalid_reason = setup.label + " has " + bins_in_band +
                          " but they do not descend from the crest: the fitted line drops " +
                          fmt(drop_m * 1e3) + " mm across them, less than " +
                          percent(o.min_drop_fraction) + " of the band (" + fmt(band_m * 1e3) +
                          " mm): a flat layer, or a slope cut short by a wall or the selection";
    return side;
  }
  side.valid = true;
  return side;
}

std::vector<std::string> common_rules(const AoRCommonOptions& o, double d_m, double w_m) {
  return {
      "d = median particle diameter = " + fmt(d_m) + " m; bins " + fmt(o.bin_width_diameters) +
          " d = " + fmt(w_m) + " m",
      "height = max(z + r) - base_height_m (" + fmt(o.base_height_m) +
          " m) per bin; bins without particles hold no data and are stepped over",
      "crest: maximum of the 3-bin running mean locates it; its height is the largest raw "
      "height of the 3 bins around it",
      "fit zone: walking outward from the crest up to the first bin below max(" +
          percent(o.lower_fraction) + " of the crest height, " + fmt(kToeHeightDiameters) +
          " d), the bins between " + percent(o.lower_fraction) + " and " +
          percent(o.upper_fraction) + " of the crest height",
      "fit: robust line, IRLS with Tukey bisquare (c = 4.685) on MAD-scaled residuals from OLS; "
      "angle = atan(descent per outward distance); std error = SE(slope) / (1 + slope^2) from "
      "the weighted LS covariance at the final weights",
      "valid side: at least " + std::to_string(o.min_points) +
          " fitted bins and a fitted drop across them of at least " + percent(o.min_drop_fraction) +
          " of the band height; at least 2 valid sides",
      "mean over valid sides; uncertainty = sqrt(SEM^2 + (sqrt(sum se_i^2)/n)^2), SEM = sample "
      "std of the side angles / sqrt(n)",
      "toe: first bin outward at or below " + fmt(kToeHeightDiameters) +
          " d; base half-width = mean crest-to-toe distance",
  };
}

// Mean, uncertainty and the error for too few valid sides.
void combine_sides(AngleOfRepose& r) {
  std::vector<double> a, se;
  std::string reasons;
  double toe_sum = 0.0;
  int toes = 0;
  for (const AoRSide& s : r.sides) {
    if (s.valid) {
      a.push_back(s.angle_deg);
      se.push_back(s.std_error_deg);
    } else {
      reasons += (reasons.empty() ? "" : "; ") + s.invalid_reason;
    }
    if (s.toe_found) {
      toe_sum += r.geometry == "slice" ? std::abs(s.toe_position_m - r.crest_position_m)
                                       : s.toe_position_m;
      ++toes;
    }
  }
  r.valid_sides = static_cast<int>(a.size());
  if (toes > 0) r.base_half_width_m = toe_sum / toes;
  if (a.size() < 2)
    throw std::runtime_error("angle of repose: the pile is too flat or too small to fit a slope (" +
                             std::to_string(a.size()) + " of " + std::to_string(r.sides.size()) +
                             " sides fitted, needs 2; crest " + fmt(r.crest_height_m * 1e3) +
                             " mm above the base, d = " + fmt(r.diameter_m * 1e3) +
                             " mm): " + reasons);
  const double n = static_cast<double>(a.size());
  double mean = 0.0;
  for (double v : a) mean += v;
  mean /= n;
  double ss = 0.0, se2 = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ss += (a[i] - mean) * (a[i] - mean);
    se2 += se[i] * se[i];
  }
  r.mean_deg = mean;
  r.sem_deg = std::sqrt(ss / (n - 1.0)) / std::sqrt(n);
  r.fit_error_deg = std::sqrt(se2) / n;
  r.uncertainty_deg = std::hypot(r.sem_deg, r.fit_error_deg);
}

// The slice rules on a binned profile: crest, both sides, their mean.
void measure_slice_profile(AngleOfRepose& r, const Profile& p, const AoRCommonOptions& options,
                           const std::string& profile_rule) {
  const std::size_t crest = crest_index(p);
  r.crest_height_m = raw_max_around(p, crest);
  r.crest_position_m = p.centre_m[crest];
  r.profile_position_m = p.centre_m;
  r.profile_height_m = p.height_m;
  r.rules = common_rules(options, r.diameter_m, r.bin_width_m);
  r.rules.push_back(profile_rule);
  if (!(r.crest_height_m > 0.0))
    throw std::runtime_error("angle of repose: nothing tops out above the base (crest " +
                             fmt(r.crest_height_m * 1e3) + " mm); is base_height_m right?");

  const Thresholds t = thresholds(r.crest_height_m, r.diameter_m, options);
  r.sides.push_back(analyse_side(p, crest, {"left", "left side", -1, -1.0}, t, options));
  r.sides.push_back(analyse_side(p, crest, {"right", "right side", +1, +1.0}, t, options));
  combine_sides(r);
}

}  // namespace

AngleOfRepose measure_slice_angle_of_repose(const std::vector<Vec3>& position_m,
                                            const std::vector<double>& radius_m,
                                            const SliceAoROptions& options) {
  validate_common(position_m, radius_m, options);
  if (options.long_axis != 0 && options.long_axis != 1)
    throw std::invalid_argument("angle of repose: long_axis must be 0 (x) or 1 (y), got " +
                                std::to_string(options.long_axis));
  const Selection sel = select_particles(position_m, radius_m, options);
  const int axis = options.long_axis;

  AngleOfRepose r;
  r.geometry = "slice";
  r.diameter_m = sel.diameter_m;
  r.bin_width_m = options.bin_width_diameters * sel.diameter_m;
  r.base_height_m = options.base_height_m;
  r.particles_used = sel.index.size();

  double s_min = std::numeric_limits<double>::infinity();
  double s_max = -s_min;
  for (std::size_t i : sel.index) {
    s_min = std::min(s_min, position_m[i][axis]);
    s_max = std::max(s_max, position_m[i][axis]);
  }
  const double w = r.bin_width_m;
  // A profile is a laboratory heap, a few hundred bins across; a span of millions of bins is
  // a position in the wrong unit or a stray reading, and would ask for gigabytes.
  const double span_bins = std::floor((s_max - s_min) / w);
  if (!(span_bins < kMaxProfileBins))
    throw std::runtime_error("angle of repose: the profile spans " +
                             std::to_string(s_max - s_min) + " m, more than " +
                             std::to_string(static_cast<long>(kMaxProfileBins)) + " bins of " +
                             std::to_string(w) + " m (a position in the wrong unit?)");
  const auto bins = static_cast<std::size_t>(span_bins) + 1;
  Profile p(bins);
  for (std::size_t k = 0; k < bins; ++k) p.centre_m[k] = s_min + (static_cast<double>(k) + 0.5) * w;
  for (std::size_t i : sel.index) {
    const double s = position_m[i][axis];
    const auto k = std::min(static_cast<std::size_t>((s - s_min) / w), bins - 1);
    p.add(k, s, position_m[i].z + radius_m[i] - options.base_height_m);
  }

  measure_slice_profile(
      r, p, options,
      "slice: profile along axis " + std::to_string(axis) +
          ", sides left/right of the crest, each bin fitted at the coordinate of the "
          "particle that set its height");
  return r;
}

AngleOfRepose measure_profile_angle_of_repose(const std::vector<double>& position_m,
                                              const std::vector<double>& height_m,
                                              double diameter_m, const AoRCommonOptions& options) {
  if (position_m.size() != height_m.size())
    throw std::invalid_argument("angle of repose: the profile has " +
                                std::to_string(position_m.size()) + " positions but " +
                                std::to_string(height_m.size()) + " heights");
  if (!(diameter_m > 0.0) || !std::isfinite(diameter_m))
    throw std::invalid_argument(
        "angle of repose: the profile's grain diameter must be a positive number, got " +
        fmt(diameter_m));
  if (options.selection)
    throw std::invalid_argument(
        "angle of repose: a measured profile has no particles to select; cut the profile to the "
        "range to be read instead of giving a selection box");
  if (!(options.bin_width_diameters > 0.0) || !std::isfinite(options.bin_width_diameters))
    throw std::invalid_argument("angle of repose: bin_width_diameters must be positive");
  // Points without a reading (NaN height: the laser saw nothing there) hold no
  // data, like a bin without particles; a position must always be a number.
  double s_min = std::numeric_limits<double>::infinity();
  double s_max = -s_min;
  std::size_t readings = 0;
  for (std::size_t i = 0; i < position_m.size(); ++i) {
    if (!std::isfinite(position_m[i]))
      throw std::invalid_argument("angle of repose: profile point " + std::to_string(i + 1) +
                                  " has no finite position");
    if (std::isinf(height_m[i]))
      throw std::invalid_argument("angle of repose: profile point " + std::to_string(i + 1) +
                                  " has an infinite height");
    if (std::isnan(height_m[i])) continue;
    s_min = std::min(s_min, position_m[i]);
    s_max = std::max(s_max, position_m[i]);
    ++readings;
  }
  if (readings == 0)
    throw std::runtime_error("angle of repose: the profile has no height readings");

  AngleOfRepose r;
  r.geometry = "slice";
  r.diameter_m = diameter_m;
  r.bin_width_m = options.bin_width_diameters * diameter_m;
  r.base_height_m = options.base_height_m;
  r.particles_used = 0;
  const double w = r.bin_width_m;
  // A profile is a laboratory heap, a few hundred bins across; a span of millions of bins is
  // a position in the wrong unit or a stray reading, and would ask for gigabytes.
  const double span_bins = std::floor((s_max - s_min) / w);
  if (!(span_bins < kMaxProfileBins))
    throw std::runtime_error("angle of repose: the profile spans " +
                             std::to_string(s_max - s_min) + " m, more than " +
                             std::to_string(static_cast<long>(kMaxProfileBins)) + " bins of " +
                             std::to_string(w) + " m (a position in the wrong unit?)");
  const auto bins = static_cast<std::size_t>(span_bins) + 1;
  Profile p(bins);
  for (std::size_t k = 0; k < bins; ++k) p.centre_m[k] = s_min + (static_cast<double>(k) + 0.5) * w;
  for (std::size_t i = 0; i < position_m.size(); ++i) {
    if (std::isnan(height_m[i])) continue;
    const auto k = std::min(static_cast<std::size_t>((position_m[i] - s_min) / w), bins - 1);
    p.add(k, position_m[i], height_m[i] - options.base_height_m);
  }
  measure_slice_profile(r, p, options,
                        "measured profile h(s) of " + std::to_string(readings) +
                            " readings: each bin's height is its highest reading, fitted at that "
                            "reading's position; d is the grains' diameter as given, not measured");
  return r;
}

AngleOfRepose measure_conical_angle_of_repose(const std::vector<Vec3>& position_m,
                                              const std::vector<double>& radius_m,
                                              const ConicalAoROptions& options) {
  validate_common(position_m, radius_m, options);
  if (options.sectors < 2)
    throw std::invalid_argument("angle of repose: sectors must be at least 2, got " +
                                std::to_string(options.sectors));
  if (options.axis_centre_m &&
      !(std::isfinite((*options.axis_centre_m)[0]) && std::isfinite((*options.axis_centre_m)[1])))
    throw std::invalid_argument("angle of repose: axis_centre_m must be finite");
  const Selection sel = select_particles(position_m, radius_m, options);

  AngleOfRepose r;
  r.geometry = "cone";
  r.diameter_m = sel.diameter_m;
  r.bin_width_m = options.bin_width_diameters * sel.diameter_m;
  r.base_height_m = options.base_height_m;
  r.particles_used = sel.index.size();
  const double w = r.bin_width_m;
  const double base = options.base_height_m;

  // Column map: the crest, and the cap that locates the axis.
  double x_min = std::numeric_limits<double>::infinity(), y_min = x_min;
  double x_max = -x_min, y_max = -x_min;
  for (std::size_t i : sel.index) {
    x_min = std::min(x_min, position_m[i].x);
    x_max = std::max(x_max, position_m[i].x);
    y_min = std::min(y_min, position_m[i].y);
    y_max = std::max(y_max, position_m[i].y);
  }
  const auto nx = static_cast<std::size_t>(std::floor((x_max - x_min) / w)) + 1;
  const auto ny = static_cast<std::size_t>(std::floor((y_max - y_min) / w)) + 1;
  if (static_cast<double>(nx) * static_cast<double>(ny) > static_cast<double>(kMaxGridCells))
    throw std::runtime_error("angle of repose: the particles span " + fmt(x_max - x_min) + " x " +
                             fmt(y_max - y_min) + " m, " + fmt(static_cast<double>(nx * ny)) +
                             " columns of " + fmt(w) + " m; restrict them with a selection box");
  std::vector<double> col_h(nx * ny, 0.0);
  std::vector<std::size_t> col_top(nx * ny, 0);
  std::vector<char> col_occ(nx * ny, 0);
  for (std::size_t i : sel.index) {
    const auto ix = std::min(static_cast<std::size_t>((position_m[i].x - x_min) / w), nx - 1);
    const auto iy = std::min(static_cast<std::size_t>((position_m[i].y - y_min) / w), ny - 1);
    const std::size_t c = ix * ny + iy;
    const double h = position_m[i].z + radius_m[i] - base;
    if (!col_occ[c] || h > col_h[c]) {
      col_h[c] = h;
      col_top[c] = i;
      col_occ[c] = 1;
    }
  }
  const auto neighbours = [&](std::size_t c, auto&& visit) {
    const std::size_t ix = c / ny, iy = c % ny;
    for (std::size_t jx = (ix == 0 ? 0 : ix - 1); jx <= std::min(ix + 1, nx - 1); ++jx)
      for (std::size_t jy = (iy == 0 ? 0 : iy - 1); jy <= std::min(iy + 1, ny - 1); ++jy)
        visit(jx * ny + jy);
  };
  std::size_t crest_col = col_h.size();
  double best_mean = -std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < col_h.size(); ++c) {
    if (!col_occ[c]) continue;
    double sum = 0.0;
    int n = 0;
    neighbours(c, [&](std::size_t j) {
      if (col_occ[j]) {
        sum += col_h[j];
        ++n;
      }
    });
    if (sum / n > best_mean) {
      best_mean = sum / n;
      crest_col = c;
    }
  }
  std::size_t top_col = crest_col;
  neighbours(crest_col, [&](std::size_t j) {
    if (col_occ[j] && col_h[j] > col_h[top_col]) top_col = j;
  });
  r.crest_height_m = col_h[top_col];
  if (!(r.crest_height_m > 0.0))
    throw std::runtime_error("angle of repose: no particle tops out above the base (crest " +
                             fmt(r.crest_height_m * 1e3) + " mm); is base_height_m right?");

  std::string centre_rule;
  if (options.axis_centre_m) {
    r.axis_centre_m = *options.axis_centre_m;
    r.axis_centre_given = true;
    centre_rule = "cone axis: given";
  } else {
    // Flood fill of the cap from the highest column.
    const double cap_m = options.upper_fraction * r.crest_height_m;
    std::vector<char> seen(col_h.size(), 0);
    std::vector<std::size_t> stack{top_col};
    seen[top_col] = 1;
    double sx = 0.0, sy = 0.0;
    std::size_t cap_columns = 0;
    while (!stack.empty()) {
      const std::size_t c = stack.back();
      stack.pop_back();
      sx += position_m[col_top[c]].x;
      sy += position_m[col_top[c]].y;
      ++cap_columns;
      neighbours(c, [&](std::size_t j) {
        if (!seen[j] && col_occ[j] && col_h[j] >= cap_m) {
          seen[j] = 1;
          stack.push_back(j);
        }
      });
    }
    r.axis_centre_m = {sx / static_cast<double>(cap_columns),
                       sy / static_cast<double>(cap_columns)};
    centre_rule = "cone axis: centroid of the top particles of the " + std::to_string(cap_columns) +
                  " columns of " + fmt(w) + " m at or above " + percent(options.upper_fraction) +
                  " of the crest height connected to the highest column";
  }

  // Sector profiles around the axis.
  const double x0 = r.axis_centre_m[0], y0 = r.axis_centre_m[1];
  const auto sectors = static_cast<std::size_t>(options.sectors);
  const double sector_rad = 2.0 * std::numbers::pi / static_cast<double>(sectors);
  double rho_max = 0.0;
  for (std::size_t i : sel.index)
    rho_max = std::max(rho_max, std::hypot(position_m[i].x - x0, position_m[i].y - y0));
  const auto bins = static_cast<std::size_t>(std::floor(rho_max / w)) + 1;
  std::vector<Profile> prof(sectors, Profile(bins));
  for (Profile& p : prof)
    for (std::size_t k = 0; k < bins; ++k) p.centre_m[k] = (static_cast<double>(k) + 0.5) * w;
  // Each sector bin averages the column tops (columns of w x w, the crest grid)
  // that fall in it, rather than taking the one highest grain of the bin: a
  // bin's arc, and so the number of grains competing for its maximum, grows
  // with the radius, and the maximum of more rough grains sits higher — that
  // lifts the outer bins and flattens the slope (-0.3 deg at 45 deg on a
  // 20 d pile). Columns have the same area at every radius.
  std::vector<std::vector<double>> sum_h(sectors, std::vector<double>(bins, 0.0)), sum_rho = sum_h;
  std::vector<std::vector<int>> count(sectors, std::vector<int>(bins, 0));
  for (std::size_t c = 0; c < col_h.size(); ++c) {
    if (!col_occ[c]) continue;
    const double x = position_m[col_top[c]].x;
    const double y = position_m[col_top[c]].y;
    const double rho = std::hypot(x - x0, y - y0);
    double phi = std::atan2(y - y0, x - x0);
    if (phi < 0.0) phi += 2.0 * std::numbers::pi;
    const auto sector = std::min(static_cast<std::size_t>(phi / sector_rad), sectors - 1);
    const auto k = std::min(static_cast<std::size_t>(rho / w), bins - 1);
    sum_h[sector][k] += col_h[c];
    sum_rho[sector][k] += rho;
    ++count[sector][k];
  }
  for (std::size_t k = 0; k < sectors; ++k)
    for (std::size_t j = 0; j < bins; ++j)
      if (count[k][j] > 0) prof[k].add(j, sum_rho[k][j] / count[k][j], sum_h[k][j] / count[k][j]);

  const Thresholds t = thresholds(r.crest_height_m, r.diameter_m, options);
  for (std::size_t k = 0; k < sectors; ++k) {
    const double from_deg = static_cast<double>(k) * sector_rad * kRadToDeg;
    const double to_deg = static_cast<double>(k + 1) * sector_rad * kRadToDeg;
    SideSetup setup{
        "sector_" + std::to_string(k),
        "sector_" + std::to_string(k) + " (" + fmt(from_deg) + "-" + fmt(to_deg) + " deg)", +1,
        +1.0};
    const std::size_t crest = crest_index(prof[k]);
    AoRSide side;
    if (crest == prof[k].size()) {
      side.name = setup.name;
      side.invalid_reason = setup.label + " has no particles";
    } else {
      side = analyse_side(prof[k], crest, setup, t, options);
    }
    side.azimuth_from_deg = from_deg;
    side.azimuth_to_deg = to_deg;
    r.sides.push_back(std::move(side));
  }

  // Representative radial profile: the median over the sectors with data at
  // each radius.
  r.profile_position_m = prof[0].centre_m;
  r.profile_height_m.assign(bins, kNaN);
  for (std::size_t j = 0; j < bins; ++j) {
    std::vector<double> hs;
    for (std::size_t k = 0; k < sectors; ++k)
      if (prof[k].has_data[j]) hs.push_back(prof[k].height_m[j]);
    if (!hs.empty()) r.profile_height_m[j] = median(std::move(hs));
  }

  r.rules = common_rules(options, r.diameter_m, w);
  r.rules.push_back(std::move(centre_rule));
  r.rules.push_back("cone: " + std::to_string(sectors) +
                    " azimuthal sectors from +x counter-clockwise; height map of w x w columns "
                    "topped by their highest particle; a sector's radial bin = mean column top "
                    "at the columns' mean radius; each sector walks outward from its own "
                    "highest bin; crest from the column grid with a 3x3 running mean");
  combine_sides(r);
  return r;
}

nlohmann::json to_json(const AngleOfRepose& r) {
  using nlohmann::json;
  const auto num = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  json j;
  j["geometry"] = r.geometry;
  j["angle_of_repose_deg"] = num(r.mean_deg);
  j["angle_of_repose_uncertainty_deg"] = num(r.uncertainty_deg);
  j["standard_error_of_mean_deg"] = num(r.sem_deg);
  j["fit_error_deg"] = num(r.fit_error_deg);
  j["valid_sides"] = r.valid_sides;
  json sides = json::array();
  for (const AoRSide& s : r.sides) {
    json o;
    o["name"] = s.name;
    o["valid"] = s.valid;
    o["angle_deg"] = num(s.angle_deg);
    o["std_error_deg"] = num(s.std_error_deg);
    o["points"] = s.points;
    o["rejected_points"] = s.rejected_points;
    o["slope"] = num(s.slope);
    o["intercept_m"] = num(s.intercept_m);
    o["fit_range_m"] = json::array({num(s.fit_from_m), num(s.fit_to_m)});
    o["toe_found"] = s.toe_found;
    o["toe_position_m"] = num(s.toe_position_m);
    if (r.geometry == "cone")
      o["azimuth_range_deg"] = json::array({num(s.azimuth_from_deg), num(s.azimuth_to_deg)});
    if (!s.valid) o["invalid_reason"] = s.invalid_reason;
    sides.push_back(std::move(o));
  }
  j["sides"] = std::move(sides);
  j["crest_height_m"] = num(r.crest_height_m);
  if (r.geometry == "cone") {
    j["crest_position_m"] = json::array({num(r.axis_centre_m[0]), num(r.axis_centre_m[1])});
    j["axis_centre_given"] = r.axis_centre_given;
  } else {
    j["crest_position_m"] = num(r.crest_position_m);
  }
  j["base_half_width_m"] = num(r.base_half_width_m);
  j["base_height_m"] = num(r.base_height_m);
  j["diameter_m"] = num(r.diameter_m);
  j["bin_width_m"] = num(r.bin_width_m);
  j["particles_used"] = r.particles_used;
  json heights = json::array();
  for (double h : r.profile_height_m) heights.push_back(num(h));
  j["profile"] = {{"position_m", r.profile_position_m}, {"height_m", std::move(heights)}};
  j["rules"] = r.rules;
  return j;
}

}  // namespace demcal::dem
