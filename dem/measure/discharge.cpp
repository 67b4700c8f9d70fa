#include "dem/measure/discharge.hpp"

#include "dem/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>

namespace demcal::dem {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string number(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

std::string percent(double fraction) { return number(100.0 * fraction) + " %"; }

nlohmann::json finite_or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

void require_fraction(double x, bool zero_allowed, const char* name) {
  const bool ok = std::isfinite(x) && x <= 1.0 && (zero_allowed ? x >= 0.0 : x > 0.0);
  if (!ok) {
    throw std::invalid_argument(std::string("analyse_discharge: ") + name + " must be in " +
                                (zero_allowed ? "[0, 1]" : "(0, 1]") + ", got " + number(x));
  }
}

void validate(const std::vector<double>& time_s, const std::vector<double>& mass_kg,
              double total_mass_kg, const DischargeOptions& o) {
  if (time_s.size() != mass_kg.size()) {
    throw std::invalid_argument("analyse_discharge: mass_kg has " +
                                std::to_string(mass_kg.size()) + " samples but time_s has " +
                                std::to_string(time_s.size()));
  }
  if (time_s.size() < 2) {
    throw std::invalid_argument("analyse_discharge: time_s needs at least 2 samples, got " +
                                std::to_string(time_s.size()));
  }
  if (!(std::isfinite(total_mass_kg) && total_mass_kg > 0.0)) {
    throw std::invalid_argument("analyse_discharge: total_mass_kg must be finite and > 0, got " +
                                number(total_mass_kg));
  }
  // Rounding in a sum of particle masses may put m a hair above the fill.
  const double mass_limit_kg = total_mass_kg * (1.0 + 1e-9);
  for (std::size_t i = 0; i < time_s.size(); ++i) {
    if (!std::isfinite(time_s[i])) {
      throw std::invalid_argument("analyse_discharge: time_s[" + std::to_string(i) +
                                  "] is not finite");
    }
    if (i > 0 && !(time_s[i] > time_s[i - 1])) {
      throw std::invalid_argument("analyse_discharge: time_s must be strictly increasing, but "
                                  "time_s[" + std::to_string(i) + "] = " + number(time_s[i]) +
                                  " follows " + number(time_s[i - 1]));
    }
    if (!(std::isfinite(mass_kg[i]) && mass_kg[i] >= 0.0)) {
      throw std::invalid_argument("analyse_discharge: mass_kg must be finite and >= 0, but "
                                  "mass_kg[" + std::to_string(i) + "] = " + number(mass_kg[i]));
    }
    if (mass_kg[i] > mass_limit_kg) {
      throw std::invalid_argument("analyse_discharge: mass_kg[" + std::to_string(i) + "] = " +
                                  number(mass_kg[i]) + " exceeds total_mass_kg = " +
                                  number(total_mass_kg) + " (is the fill mass right?)");
    }
  }
  require_fraction(o.end_fraction, false, "options.end_fraction");
  require_fraction(o.steady_low_fraction, true, "options.steady_low_fraction");
  require_fraction(o.steady_high_fraction, false, "options.steady_high_fraction");
  if (!(o.steady_low_fraction < o.steady_high_fraction)) {
    throw std::invalid_argument(
        "analyse_discharge: options.steady_low_fraction must be below "
        "options.steady_high_fraction");
  }
  require_fraction(o.complete_fraction, false, "options.complete_fraction");
  if (!(std::isfinite(o.stall_time_s) && o.stall_time_s >= 0.0)) {
    throw std::invalid_argument("analyse_discharge: options.stall_time_s must be finite and >= 0");
  }
  if (!(std::isfinite(o.stall_mass_kg) && o.stall_mass_kg >= 0.0)) {
    throw std::invalid_argument("analyse_discharge: options.stall_mass_kg must be finite and >= 0");
  }
}

double resolve_stall_time_s(const std::vector<double>& time_s, const DischargeOptions& o) {
  if (o.stall_time_s > 0.0) return o.stall_time_s;
  // The median step, so a few irregular samples (a restart, a late first
  // sample) do not set the scale.
  std::vector<double> steps(time_s.size() - 1);
  for (std::size_t i = 1; i < time_s.size(); ++i) steps[i - 1] = time_s[i] - time_s[i - 1];
  auto mid = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
  std::nth_element(steps.begin(), mid, steps.end());
  return std::max(0.1, 20.0 * *mid);
}

// First time the (monotone) envelope reaches `level`, linear between samples.
double crossing_time_s(const std::vector<double>& time_s, const std::vector<double>& envelope_kg,
                       double level_kg) {
  const auto it = std::lower_bound(envelope_kg.begin(), envelope_kg.end(), level_kg);
  if (it == envelope_kg.end()) return kNaN;
  const auto i = static_cast<std::size_t>(it - envelope_kg.begin());
  if (i == 0) return time_s[0];
  const double m0 = envelope_kg[i - 1], m1 = envelope_kg[i];
  return time_s[i - 1] + (level_kg - m0) / (m1 - m0) * (time_s[i] - time_s[i - 1]);
}

struct LineFit {
  double slope = kNaN;
  double slope_std_error = kNaN;
  double r_squared = kNaN;
};

// Ordinary least squares on samples [first, last]; centred sums, because t and
// m sit far from zero next to their spread late in a long discharge.
LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y, std::size_t first,
                 std::size_t last) {
  LineFit f;
  const std::size_t n = last - first + 1;
  if (n < 2) return f;
  double mx = 0.0, my = 0.0;
  for (std::size_t i = first; i <= last; ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (std::size_t i = first; i <= last; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  f.slope = sxy / sxx;
  const double ssr = std::max(0.0, syy - f.slope * sxy);
  if (syy > 0.0) f.r_squared = 1.0 - ssr / syy;
  if (n >= 3) f.slope_std_error = std::sqrt(ssr / static_cast<double>(n - 2) / sxx);
  return f;
}

std::string criterion_text(const DischargeOptions& o, double stall_time_s) {
  return "discharge_time_s: first time the discharged mass (running maximum of the samples, "
         "linear between samples) reaches " + percent(o.end_fraction) +
         " of the final discharged mass, given only for a complete discharge. The flow has "
         "stopped at the earliest sample after which at most " + number(o.stall_mass_kg) +
         " kg passes until the end of the series, with at least " + number(stall_time_s) +
         " s of series after it or the whole fill discharged; the final discharged mass is the mean of the samples from "
         "then on. clogged: stopped with less than " + percent(o.complete_fraction) +
         " of the fill discharged (no discharge time). running: mass still passing within the "
         "last " + number(stall_time_s) + " s (no discharge time). t90_s, t95_s: 90 % and 95 % "
         "of the fill; t90_of_discharged_s, t95_of_discharged_s: of the final discharged mass. "
         "mass_flow_rate_kg_s: least-squares slope of m(t) over the samples between " +
         percent(o.steady_low_fraction) + " and " + percent(o.steady_high_fraction) +
         " of the final discharged mass (of the mass discharged so far while running).";
}

}  // namespace

DischargeAnalysis analyse_discharge(const std::vector<double>& time_s,
                                    const std::vector<double>& mass_kg, double total_mass_kg,
                                    const DischargeOptions& options) {
  validate(time_s, mass_kg, total_mass_kg, options);
  const std::size_t n = time_s.size();
  DischargeAnalysis a;
  a.total_mass_kg = total_mass_kg;
  a.stall_time_s = resolve_stall_time_s(time_s, options);
  a.criterion = criterion_text(options, a.stall_time_s);
  const double tol_kg = options.stall_mass_kg;
  // Absorbs rounding in sample times that are multiples of a decimal interval.
  const double eps_s = 1e-9 * std::max({std::abs(time_s.front()), std::abs(time_s.back()),
                                        a.stall_time_s});

  // Running maximum: noise or a grain bouncing back over the plane must not
  // make a threshold crossing ambiguous or fake a restart of the flow.
  std::vector<double> envelope_kg(n);
  envelope_kg[0] = mass_kg[0];
  for (std::size_t i = 1; i < n; ++i) envelope_kg[i] = std::max(envelope_kg[i - 1], mass_kg[i]);
  const double last_kg = envelope_kg.back();

  // Earliest sample from which at most tol passes until the end; a stop only
  // if enough series follows it to tell a stop from a slow trickle.
  const auto stop_it = std::lower_bound(envelope_kg.begin(), envelope_kg.end(), last_kg - tol_kg);
  const auto i_stop = static_cast<std::size_t>(stop_it - envelope_kg.begin());
  // Once the whole fill has passed nothing more can, so a loop that stops
  // sampling at that moment has seen a stop without waiting stall_time_s.
  const bool emptied = last_kg >= total_mass_kg * (1.0 - 1e-9) - tol_kg;
  const bool stopped = emptied || time_s.back() - time_s[i_stop] >= a.stall_time_s - eps_s;

  const auto first_it = std::upper_bound(envelope_kg.begin(), envelope_kg.end(), tol_kg);
  if (first_it != envelope_kg.end()) {
    a.first_discharge_s = time_s[static_cast<std::size_t>(first_it - envelope_kg.begin())];
  }

  // Pauses: runs of quiet windows (stall_time_s with no mass passing) that
  // start after the first grain arrived (the fall to the plane is not a pause)
  // and after which more than the tolerance still passes — otherwise a slow
  // end tail, whose last trickle is within the tolerance, would count as one.
  // Two pointers keep it O(n).
  {
    const std::size_t begin = static_cast<std::size_t>(first_it - envelope_kg.begin());
    const std::size_t end = stopped ? i_stop : n;
    std::size_t j = begin;
    bool in_pause = false;
    std::size_t pause_end = begin;
    const auto close_pause = [&] {
      if (in_pause && last_kg - envelope_kg[pause_end] > tol_kg) ++a.pauses;
      in_pause = false;
    };
    for (std::size_t i = begin; i < end; ++i) {
      const double window_end_s = time_s[i] + a.stall_time_s;
      if (window_end_s > time_s.back() + eps_s) break;
      j = std::max(j, i);
      while (j + 1 < n && time_s[j + 1] <= window_end_s + eps_s) ++j;
      if (envelope_kg[j] - envelope_kg[i] <= tol_kg) {
        in_pause = true;
        pause_end = j;
      } else {
        close_pause();
      }
    }
    close_pause();
  }

  double reference_kg = last_kg;
  if (stopped) {
    // Mean over the plateau rather than its maximum, which noise biases upward.
    double sum = 0.0;
    for (std::size_t i = i_stop; i < n; ++i) sum += mass_kg[i];
    a.final_discharged_mass_kg = sum / static_cast<double>(n - i_stop);
    a.discharged_fraction = a.final_discharged_mass_kg / total_mass_kg;
    a.flow_stopped_s = time_s[i_stop];
    reference_kg = a.final_discharged_mass_kg;
    if (a.final_discharged_mass_kg > 0.0) {
      a.t90_of_discharged_s = crossing_time_s(time_s, envelope_kg, 0.9 * reference_kg);
      a.t95_of_discharged_s = crossing_time_s(time_s, envelope_kg, 0.95 * reference_kg);
    }
    if (a.discharged_fraction < options.complete_fraction) {
      a.clogged = true;
      char buf[128];
      std::snprintf(buf, sizeof buf, "clogged after %.1f %% discharged at t = %.3f s",
                    100.0 * a.discharged_fraction, a.flow_stopped_s);
      a.status = buf;
    } else {
      a.status = "complete";
      a.discharge_time_s = crossing_time_s(time_s, envelope_kg, options.end_fraction * reference_kg);
    }
  } else {
    a.status = "running";
    a.final_discharged_mass_kg = last_kg;
    a.discharged_fraction = last_kg / total_mass_kg;
  }
  a.t90_s = crossing_time_s(time_s, envelope_kg, 0.9 * total_mass_kg);
  a.t95_s = crossing_time_s(time_s, envelope_kg, 0.95 * total_mass_kg);

  if (reference_kg > tol_kg) {
    const double lo_kg = options.steady_low_fraction * reference_kg;
    const double hi_kg = options.steady_high_fraction * reference_kg;
    const auto lo_it = std::lower_bound(envelope_kg.begin(), envelope_kg.end(), lo_kg);
    const auto hi_it = std::upper_bound(envelope_kg.begin(), envelope_kg.end(), hi_kg);
    if (lo_it < hi_it) {
      const auto first = static_cast<std::size_t>(lo_it - envelope_kg.begin());
      const auto last = static_cast<std::size_t>(hi_it - envelope_kg.begin()) - 1;
      a.steady_samples = last - first + 1;
      a.steady_start_s = time_s[first];
      a.steady_end_s = time_s[last];
      const LineFit f = fit_line(time_s, mass_kg, first, last);
      a.mass_flow_rate_kg_s = f.slope;
      a.mass_flow_rate_std_error_kg_s = f.slope_std_error;
      a.mass_flow_rate_r_squared = f.r_squared;
    }
  }
  return a;
}

nlohmann::json to_json(const DischargeAnalysis& a) {
  nlohmann::json j;
  j["status"] = a.status;
  j["clogged"] = a.clogged;
  j["discharge_time_s"] = finite_or_null(a.discharge_time_s);
  j["t90_s"] = finite_or_null(a.t90_s);
  j["t95_s"] = finite_or_null(a.t95_s);
  j["t90_of_discharged_s"] = finite_or_null(a.t90_of_discharged_s);
  j["t95_of_discharged_s"] = finite_or_null(a.t95_of_discharged_s);
  j["first_discharge_s"] = finite_or_null(a.first_discharge_s);
  j["flow_stopped_s"] = finite_or_null(a.flow_stopped_s);
  j["pauses"] = a.pauses;
  j["total_mass_kg"] = finite_or_null(a.total_mass_kg);
  j["final_discharged_mass_kg"] = finite_or_null(a.final_discharged_mass_kg);
  j["discharged_fraction"] = finite_or_null(a.discharged_fraction);
  j["mass_flow_rate_kg_s"] = finite_or_null(a.mass_flow_rate_kg_s);
  j["mass_flow_rate_std_error_kg_s"] = finite_or_null(a.mass_flow_rate_std_error_kg_s);
  j["mass_flow_rate_r_squared"] = finite_or_null(a.mass_flow_rate_r_squared);
  j["steady_samples"] = a.steady_samples;
  j["steady_start_s"] = finite_or_null(a.steady_start_s);
  j["steady_end_s"] = finite_or_null(a.steady_end_s);
  j["stall_time_s"] = finite_or_null(a.stall_time_s);
  j["criterion"] = a.criterion;
  return j;
}

nlohmann::json series_to_json(const std::vector<double>& time_s,
                              const std::vector<double>& mass_kg) {
  if (time_s.size() != mass_kg.size()) {
    throw std::invalid_argument("series_to_json: mass_kg has " + std::to_string(mass_kg.size()) +
                                " samples but time_s has " + std::to_string(time_s.size()));
  }
  nlohmann::json t = nlohmann::json::array(), m = nlohmann::json::array();
  for (std::size_t i = 0; i < time_s.size(); ++i) {
    t.push_back(finite_or_null(time_s[i]));
    m.push_back(finite_or_null(mass_kg[i]));
  }
  return {{"time_s", std::move(t)}, {"mass_kg", std::move(m)}};
}

// --- DischargeRecorder ---

namespace {

void check_timing(double opening_time_s, double sample_interval_s) {
  if (!std::isfinite(opening_time_s)) {
    throw std::invalid_argument("DischargeRecorder: opening_time_s must be finite");
  }
  if (!(std::isfinite(sample_interval_s) && sample_interval_s > 0.0)) {
    throw std::invalid_argument("DischargeRecorder: sample_interval_s must be finite and > 0, got " +
                                number(sample_interval_s));
  }
}

}  // namespace

DischargeRecorder::DischargeRecorder(double z_out_m, double opening_time_s,
                                     double sample_interval_s, bool latch)
    : below_plane_(true),
      z_out_m_(z_out_m),
      opening_time_s_(opening_time_s),
      sample_interval_s_(sample_interval_s),
      latch_(latch),
      next_due_s_(opening_time_s) {
  if (!std::isfinite(z_out_m)) throw std::invalid_argument("DischargeRecorder: z_out_m must be finite");
  check_timing(opening_time_s, sample_interval_s);
}

DischargeRecorder::DischargeRecorder(Predicate discharged, double opening_time_s,
                                     double sample_interval_s, bool latch)
    : discharged_(std::move(discharged)),
      opening_time_s_(opening_time_s),
      sample_interval_s_(sample_interval_s),
      latch_(latch),
      next_due_s_(opening_time_s) {
  if (!discharged_) throw std::invalid_argument("DischargeRecorder: discharged predicate is empty");
  check_timing(opening_time_s, sample_interval_s);
}

void DischargeRecorder::reserve_for(double duration_s) {
  if (!(std::isfinite(duration_s) && duration_s >= 0.0)) {
    throw std::invalid_argument("DischargeRecorder::reserve_for: duration_s must be finite and >= 0");
  }
  const auto samples = static_cast<std::size_t>(std::ceil(duration_s / sample_interval_s_)) + 2;
  time_s_.reserve(time_s_.size() + samples);
  mass_kg_.reserve(mass_kg_.size() + samples);
}

bool DischargeRecorder::due(double time_s) const {
  // Relative slack so a step landing on the grid point up to rounding counts.
  return time_s >= next_due_s_ - 1e-9 * sample_interval_s_;
}

void DischargeRecorder::sample(const Simulation& sim) { sample(sim.time_s(), sim.particles()); }

void DischargeRecorder::sample(double time_s, const Particles& particles) {
  const double slack_s = 1e-9 * sample_interval_s_;
  if (!(time_s >= opening_time_s_ - slack_s)) {
    throw std::logic_error("DischargeRecorder::sample: time " + number(time_s) +
                           " s is before opening_time_s = " + number(opening_time_s_) + " s");
  }
  if (time_s < last_sim_time_s_) {
    throw std::logic_error("DischargeRecorder::sample: time went backwards (" + number(time_s) +
                           " s after " + number(last_sim_time_s_) + " s)");
  }
  const std::size_t n = particles.size();
  if (latch_) {
    if (n < last_count_) {
      throw std::logic_error(
          "DischargeRecorder::sample: particles were removed; the latch follows every particle");
    }
    // Allocates only when particles were added since the last sample. Ids are
    // dense from 0 in the engine; one far beyond the count is refused rather
    // than sized for.
    if (n > last_count_) {
      std::int64_t max_id = -1;
      for (std::size_t i = 0; i < n; ++i) {
        const std::int64_t id = particles.id[i];
        if (id < 0 || static_cast<std::uint64_t>(id) >= 4 * static_cast<std::uint64_t>(n) + 1024)
          throw std::logic_error("DischargeRecorder::sample: particle id " + std::to_string(id) +
                                 " is outside [0, 4 x count + 1024); the latch is keyed by id");
        max_id = std::max(max_id, id);
      }
      if (static_cast<std::size_t>(max_id + 1) > passed_.size())
        passed_.resize(static_cast<std::size_t>(max_id + 1), 0);
      last_count_ = n;
    }
  }
  const auto& z = particles.position_m;
  const auto& mass = particles.mass_kg;
  double discharged_kg = 0.0;
  double all_kg = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    all_kg += mass[i];
    const auto id = latch_ ? static_cast<std::size_t>(particles.id[i]) : 0;
    if (latch_ && passed_[id]) {
      discharged_kg += mass[i];
      continue;
    }
    const bool out = below_plane_ ? z[i].z < z_out_m_ : discharged_(particles, i);
    if (out) {
      discharged_kg += mass[i];
      if (latch_) passed_[id] = 1;
    }
  }
  if (std::isnan(fill_mass_kg_)) fill_mass_kg_ = all_kg;

  const double since_opening_s = std::max(0.0, time_s - opening_time_s_);
  if (!time_s_.empty() && time_s == last_sim_time_s_) {
    mass_kg_.back() = discharged_kg;
  } else {
    time_s_.push_back(since_opening_s);
    mass_kg_.push_back(discharged_kg);
  }
  last_sim_time_s_ = time_s;
  // Next point of the grid opening + k * interval, so late samples (a step
  // past the grid point) do not accumulate into a drifting interval.
  const double k = std::floor(since_opening_s / sample_interval_s_ + 1e-9) + 1.0;
  next_due_s_ = opening_time_s_ + k * sample_interval_s_;
}

DischargeAnalysis DischargeRecorder::analyse(const DischargeOptions& options) const {
  return analyse_discharge(time_s_, mass_kg_, fill_mass_kg_, options);
}

}  // namespace demcal::dem
