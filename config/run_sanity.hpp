#pragma once
// Physical sanity of a study before anything runs: values that are legal
// types and within their keys' ranges but make a run meaningless or endless.
// Each rule is checked where the study is read (config/study_config.cpp), and a
// failure is a ConfigError at the key that decides it, with the reason:
//
// - Rest check finer than the dynamics: a grain released from rest reaches
//   rest_speed_m_s after rest_speed_m_s / g; a check before that declares a
//   falling fill at rest. Rule: check_interval_s >= rest_speed_m_s / g.
// - An absurd rest speed: "at rest" must be slower than a grain that has
//   fallen a tenth of its (mean, unscaled) diameter: rest_speed_m_s <=
//   sqrt(2 g d / 10).
// - Overlaps: two grains colliding head-on at kImpactSpeed (1 m/s) must not
//   overlap by more than kMaxOverlapFraction (10 %) of their diameter (Hertz:
//   delta/d = 0.75 (rho v^2 / E*)^(2/5), E* = E / (2 (1 - nu^2))). A softer
//   modulus changes the packing, not only the time step.
// - The number of steps: at most (2 max_settle_s + max_flow_s) / dt, with dt
//   time_step_fraction_of_rayleigh x the Rayleigh time of the smallest (scaled)
//   grain in the stiffest material, as the engine resolves it. A run whose
//   estimate exceeds protocol.max_steps (default kDefaultMaxSteps = 1e10) is
//   refused with the estimate.
// - The number of grains: a fill estimated (its mass over the mean simulated
//   grain's) at more than protocol.max_particles (default
//   dem::RunProtocol::max_particles = 1e6) is refused by the apparatus itself,
//   before its lattice is laid out, with the estimate and what to change.

#include "config/toml_reader.hpp"
#include "dem/apparatus/apparatus.hpp"
#include "dem/apparatus/granular_material.hpp"

#include <cstdint>

namespace demcal::config {

inline constexpr double kStandardGravity = 9.81;
inline constexpr double kImpactSpeed_m_s = 1.0;
inline constexpr double kMaxOverlapFraction = 0.10;
inline constexpr double kDefaultMaxSteps = 1e10;
// More grains than this in one fill (the full apparatus', before a slice takes
// its share) is beyond a workstation: refused at fill_mass_kg, unless the study
// raised protocol.max_particles above it (then that is the cap, so one key
// decides how big a run may be, not two).
inline constexpr double kMaxGrains = 1e7;
// No laboratory test this toolkit models is larger than this in any direction.
inline constexpr double kMaxApparatusExtent_m = 100.0;

struct RunEstimate {
  double time_step_s = 0.0;
  double max_simulated_s = 0.0;  // the phase caps: 2 max_settle_s + max_flow_s
  double max_steps = 0.0;
  double impact_overlap_fraction = 0.0;  // of the diameter, at kImpactSpeed_m_s
};

RunEstimate estimate_run(const dem::GranularMaterial& material,
                         const dem::ModelReduction& reduction, const dem::RunProtocol& protocol);

// The rest-check rules, at the [protocol] table's keys.
void check_rest_protocol(reader::Table& protocol_table, const dem::RunProtocol& protocol,
                         const dem::GranularMaterial& material);

// The overlap and step-count rules for one apparatus, at its table (the
// apparatus' shear_modulus_pa when it overrides the material's).
void check_run_estimate(reader::Table& apparatus_table, const dem::GranularMaterial& material,
                        const dem::ModelReduction& reduction, const dem::RunProtocol& protocol,
                        double max_steps);

// fill_mass_kg / the mass of a mean (scaled) grain must be at most
// max(kMaxGrains, protocol.max_particles) (the full apparatus' fill, before a
// slice takes its share).
void check_grain_count(reader::Table& t, const dem::GranularMaterial& material,
                       const dem::ModelReduction& reduction, const dem::RunProtocol& protocol,
                       double fill_mass_kg);

// A cone (hopper, funnel) from `wide_m` down to `narrow_m` at `half_angle_deg`
// from the vertical must be at most kMaxApparatusExtent_m tall: refused at
// the angle's key before the apparatus is built (a 1e-9 degree hopper is 1.7e9 m tall).
void check_cone_height(reader::Table& t, std::string_view angle_key, double wide_m, double narrow_m,
                       double half_angle_deg);

// An apparatus whose simulation box exceeds kMaxApparatusExtent_m in any
// direction (a hopper_half_angle_deg of 1e-9 makes a 1.7e9 m hopper) is
// refused at its table, with the box.
void check_apparatus_extent(reader::Table& apparatus_table, const dem::Apparatus& apparatus);

}  // namespace demcal::config
