#pragma once
// Discharge of a sandglass or hopper: the discharged mass m(t) recorded while
// the orifice is open, and what is read from it — the discharge time, the
// steady mass flow rate, and whether the flow clogged. These are
// `observables.discharge_time_s` and `observables.mass_flow_rate_kg_s`.
//
// Small orifices jam at random (an arch forms over the hole), so a run can stop
// with most of the fill still in the hopper. That must come out as a clog,
// never as a discharge time: a calibration fitting "times" that are really
// arch-formation times would be fitting noise.

#include "dem/particles.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace demcal::dem {

class Simulation;

struct DischargeOptions {
  // The discharge time is when the discharged mass reaches this fraction of
  // what finally discharged. Not 1: the time of the very last grain is set by
  // one or two particles rolling off a dead zone and scatters far more than
  // the bulk discharge; 0.98 still measures "emptied" while resting on the
  // many-particle flow.
  double end_fraction = 0.98;
  // The steady part of m(t) for the flow rate, as fractions of the final
  // discharged mass: past the start transient (the flow accelerating to its
  // Beverloo rate) and before the end tail (the last heap slumping out). Same
  // window as the peer tool, so rates compare directly.
  double steady_low_fraction = 0.2;
  double steady_high_fraction = 0.8;
  // The flow has stopped once no mass passes for this long. 0 = automatic:
  // max(0.1 s, 20 median sampling intervals) — 0.1 s is many grain transit
  // times through a mm-scale orifice, and 20 samples keep a coarsely sampled
  // series from calling one quiet interval a stop.
  double stall_time_s = 0.0;
  // A gain of the discharged mass at most this large counts as "no mass
  // passes". 0 suits engine output (mass moves in whole particles); noisy
  // measured series need a few noise amplitudes.
  double stall_mass_kg = 0.0;
  // A flow that stops with less than this fraction of the fill discharged has
  // clogged. Lower it for flat-bottomed hoppers, whose dead zones keep part of
  // the fill for good.
  double complete_fraction = 0.95;
};

struct DischargeAnalysis {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  // "complete", "running" (the series ended while mass still passed), or
  // "clogged after X % discharged at t = Y s".
  std::string status;
  bool clogged = false;
  // Only for a complete discharge; NaN when clogged or running.
  double discharge_time_s = kNaN;
  // Times at which 90 % / 95 % of the *fill* had passed (NaN if never).
  double t90_s = kNaN;
  double t95_s = kNaN;
  // The peer tool's t_90 / t_95: 90 % / 95 % of the *final discharged* mass.
  double t90_of_discharged_s = kNaN;
  double t95_of_discharged_s = kNaN;
  // First time any mass had passed (NaN if none).
  double first_discharge_s = kNaN;
  // Start of the quiet period that lasts to the end of the series (NaN: running).
  double flow_stopped_s = kNaN;
  // Interruptions of at least stall_time_s after which the flow resumed.
  int pauses = 0;

  double total_mass_kg = kNaN;
  double final_discharged_mass_kg = kNaN;
  double discharged_fraction = kNaN;

  // Least-squares slope of m(t) over the steady window; NaN with fewer than 2
  // samples in it, standard error NaN with fewer than 3.
  double mass_flow_rate_kg_s = kNaN;
  double mass_flow_rate_std_error_kg_s = kNaN;
  double mass_flow_rate_r_squared = kNaN;
  std::size_t steady_samples = 0;
  double steady_start_s = kNaN;
  double steady_end_s = kNaN;

  double stall_time_s = kNaN;  // as used (resolved from the options)
  std::string criterion;       // the rules above, as a sentence with the numbers used
};

// Reads a discharge curve: time since opening (strictly increasing, finite)
// and discharged mass (finite, >= 0, at most total_mass_kg), at least two
// samples; total_mass_kg is the fill. Throws std::invalid_argument naming the
// offending argument.
DischargeAnalysis analyse_discharge(const std::vector<double>& time_s,
                                    const std::vector<double>& mass_kg, double total_mass_kg,
                                    const DischargeOptions& options = {});

// Stable names; non-finite numbers become null.
nlohmann::json to_json(const DischargeAnalysis& analysis);
// {"time_s": [...], "mass_kg": [...]}; non-finite numbers become null.
nlohmann::json series_to_json(const std::vector<double>& time_s,
                              const std::vector<double>& mass_kg);

// Records m(t) during a run. The caller samples it every sample_interval_s
// (due() says when); each sample is one O(N) pass with no allocation once
// reserve_for() has sized the series.
class DischargeRecorder {
 public:
  // True when particle i counts as discharged.
  using Predicate = std::function<bool(const Particles&, std::size_t)>;

  // Discharged = centre below the plane z = z_out_m (passed the orifice plate).
  DischargeRecorder(double z_out_m, double opening_time_s, double sample_interval_s,
                    bool latch = true);
  DischargeRecorder(Predicate discharged, double opening_time_s, double sample_interval_s,
                    bool latch = true);

  // Capacity for a run of this duration after opening, so sample() never allocates.
  void reserve_for(double duration_s);
  // True from the next point of the grid opening_time_s + k * sample_interval_s
  // not yet sampled (the grid, not "previous sample + interval", so samples
  // taken a step late do not drift).
  bool due(double time_s) const;
  // Appends (time since opening, discharged mass). Sampling again at the same
  // time replaces the last sample. Throws std::logic_error before opening or
  // if time went backwards or particles were removed.
  void sample(const Simulation& sim);
  void sample(double time_s, const Particles& particles);

  const std::vector<double>& time_s() const { return time_s_; }
  const std::vector<double>& mass_kg() const { return mass_kg_; }
  // Mass of all particles at the first sample: the fill (NaN before any sample).
  double fill_mass_kg() const { return fill_mass_kg_; }
  double opening_time_s() const { return opening_time_s_; }
  double sample_interval_s() const { return sample_interval_s_; }

  DischargeAnalysis analyse(const DischargeOptions& options = {}) const;
  nlohmann::json series_json() const { return series_to_json(time_s_, mass_kg_); }

 private:
  bool below_plane_ = false;
  double z_out_m_ = 0.0;
  Predicate discharged_;
  double opening_time_s_ = 0.0;
  double sample_interval_s_ = 0.0;
  // Once discharged, always discharged: grains in the lower bulb that bounce
  // or heap back above the plane have still passed the orifice, and m(t) must
  // not drop because of them.
  // The latch is keyed by particle id (Particles::id), not index: with spatial
  // particle order (dem/particle_order.hpp) a grain's index changes during the run.
  bool latch_ = true;
  std::vector<unsigned char> passed_;  // [id]
  std::size_t last_count_ = 0;
  std::vector<double> time_s_;
  std::vector<double> mass_kg_;
  double fill_mass_kg_ = std::numeric_limits<double>::quiet_NaN();
  double next_due_s_ = 0.0;
  double last_sim_time_s_ = -std::numeric_limits<double>::infinity();
};

}  // namespace demcal::dem
