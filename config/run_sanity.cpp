#include "config/run_sanity.hpp"

#include "dem/material.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>

namespace demcal::config {

using reader::format_number;

namespace {

double effective_modulus_pa(const dem::Material& m) {
  const double nu = m.poisson_ratio;
  return m.youngs_modulus() / (2.0 * (1.0 - nu * nu));
}

dem::Material reduced_particle(const dem::GranularMaterial& material,
                               const dem::ModelReduction& reduction) {
  dem::Material p = material.particle;
  if (reduction.shear_modulus_pa > 0.0) {
    p.shear_modulus_pa = reduction.shear_modulus_pa;
    p.youngs_modulus_pa = 0.0;
  }
  return p;
}

}  // namespace

RunEstimate estimate_run(const dem::GranularMaterial& material,
                         const dem::ModelReduction& reduction, const dem::RunProtocol& protocol) {
  RunEstimate e;
  const dem::Material particle = reduced_particle(material, reduction);
  const double radius = 0.5 * material.sizes->min_diameter_m() * reduction.coarse_graining_factor;
  const double rayleigh =
      std::min(dem::rayleigh_time_s(particle, radius), dem::rayleigh_time_s(material.wall, radius));
  e.time_step_s = protocol.time_step_fraction_of_rayleigh * rayleigh;
  e.max_simulated_s = 2.0 * protocol.max_settle_s + protocol.max_flow_s;
  e.max_steps = e.max_simulated_s / e.time_step_s;
  const double ratio =
      particle.density_kg_m3 * kImpactSpeed_m_s * kImpactSpeed_m_s / effective_modulus_pa(particle);
  e.impact_overlap_fraction = 0.75 * std::pow(ratio, 0.4);
  return e;
}

void check_rest_protocol(reader::Table& t, const dem::RunProtocol& p,
                         const dem::GranularMaterial& material) {
  const double d = dem::mean_diameter_m(*material.sizes);
  const double fastest_rest = std::sqrt(2.0 * kStandardGravity * d / 10.0);
  if (p.rest_speed_m_s > fastest_rest)
    t.fail("rest_speed_m_s", "expected at most " + format_number(fastest_rest) +
                                 " m/s (the speed a grain of the mean diameter " +
                                 format_number(d) + " m gains falling a tenth of it), got " +
                                 format_number(p.rest_speed_m_s) +
                                 ": a heap still moving that fast would be declared at rest");
  const double finest = p.rest_speed_m_s / kStandardGravity;
  if (p.check_interval_s < finest)
    t.fail("check_interval_s",
           "expected at least rest_speed_m_s / g = " + format_number(finest) + " s, got " +
               format_number(p.check_interval_s) +
               ": a check finer than the dynamics declares a fill at rest while it is still "
               "falling (a grain released from rest needs that long to reach rest_speed_m_s)");
}

void check_run_estimate(reader::Table& t, const dem::GranularMaterial& material,
                        const dem::ModelReduction& reduction, const dem::RunProtocol& protocol,
                        double max_steps) {
  const RunEstimate e = estimate_run(material, reduction, protocol);
  const bool own_modulus = reduction.shear_modulus_pa > 0.0;
  const std::string modulus_text =
      own_modulus
          ? t.key_path("shear_modulus_pa") + " = " + format_number(reduction.shear_modulus_pa)
          : "the material's modulus (E = " + format_number(material.particle.youngs_modulus()) +
                " Pa)";
  if (!(e.impact_overlap_fraction <= kMaxOverlapFraction)) {
    const std::string what = "with " + modulus_text + " two grains colliding at " +
                             format_number(kImpactSpeed_m_s) + " m/s would overlap by " +
                             format_number(std::round(e.impact_overlap_fraction * 1000) / 10) +
                             " % of their diameter (Hertz); expected at most " +
                             format_number(kMaxOverlapFraction * 100) + " %: raise the modulus";
    if (own_modulus) t.fail("shear_modulus_pa", what);
    t.fail_here(what);
  }
  if (!(e.max_steps <= max_steps)) {
    const std::string what = "a run would take up to " + format_number(e.max_steps) +
                             " time steps (dt = " + format_number(e.time_step_s) + " s from " +
                             modulus_text +
                             " and the smallest grain; 2 max_settle_s + max_flow_s = " +
                             format_number(e.max_simulated_s) +
                             " s); the cap is protocol.max_steps = " + format_number(max_steps) +
                             ": lower the modulus or raise protocol.max_steps";
    if (own_modulus) t.fail("shear_modulus_pa", what);
    t.fail_here(what);
  }
}

void check_grain_count(reader::Table& t, const dem::GranularMaterial& material,
                       const dem::ModelReduction& reduction, const dem::RunProtocol& protocol,
                       double fill_mass_kg) {
  const double f = reduction.coarse_graining_factor;
  const double grain_kg =
      dem::mean_grain_mass_kg(*material.sizes, material.particle.density_kg_m3) * f * f * f;
  const double grains = fill_mass_kg / grain_kg;
  const double cap = std::max(kMaxGrains, protocol.max_particles);
  if (!(grains <= cap))
    t.fail("fill_mass_kg",
           "expected at most " + format_number(cap) + " grains' worth, got " +
               format_number(fill_mass_kg) + " kg = " + format_number(grains) + " grains of " +
               format_number(grain_kg) +
               " kg; coarse-grain (coarse_graining_factor), fill less, or raise "
               "protocol.max_particles");
}

void check_cone_height(reader::Table& t, std::string_view angle_key, double wide_m, double narrow_m,
                       double half_angle_deg) {
  const double height =
      0.5 * std::fabs(wide_m - narrow_m) / std::tan(half_angle_deg * std::numbers::pi / 180.0);
  if (!(height <= kMaxApparatusExtent_m))
    t.fail(angle_key, "expected a half angle that keeps the cone at most " +
                          format_number(kMaxApparatusExtent_m) + " m tall, got " +
                          format_number(half_angle_deg) + " deg, which makes it " +
                          format_number(height) + " m tall");
}

void check_apparatus_extent(reader::Table& t, const dem::Apparatus& apparatus) {
  const dem::Domain& box = apparatus.simulation().options().domain;
  const dem::Vec3 length = box.length_m();
  for (int k = 0; k < 3; ++k)
    if (!(length[k] <= kMaxApparatusExtent_m))
      t.fail_here("its dimensions give a simulation box of " + reader::vec_text(length) +
                  " m, larger than " + format_number(kMaxApparatusExtent_m) +
                  " m (no laboratory test is that large); check its dimensions and angles "
                  "(a half angle near 0 makes a hopper or funnel endlessly tall)");
}

}  // namespace demcal::config
