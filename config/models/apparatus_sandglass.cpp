// The sandglass (dem/apparatus/sandglass.hpp): its reader and its registration.

#include "config/models/apparatus_models.hpp"
#include "config/run_sanity.hpp"
#include "dem/apparatus/sandglass.hpp"

namespace demcal::config {

namespace {

using namespace apparatus_reading;
using reader::Table;
using reader::between;
using reader::format_number;

const reader::Range kFillSpacing = between(1, true, 3, false);

std::unique_ptr<dem::Apparatus> read_sandglass(Table& t, const dem::GranularMaterial& m,
                                               double max_steps, const dem::RunProtocol& p) {
  dem::SandglassOptions o;
  o.upper_diameter_m = t.number_at_most("upper_diameter_m", kPositive, kMaxLength);
  o.upper_height_m = t.number_at_most("upper_height_m", kPositive, kMaxLength);
  o.bottom = t.choice("bottom", {"flat", "conical"});
  if (o.bottom == "conical" || t.has("hopper_half_angle_deg"))
    o.hopper_half_angle_deg = t.number("hopper_half_angle_deg", kHalfAngle);
  o.orifice_diameter_m = t.number_at_most("orifice_diameter_m", kPositive, kMaxLength);
  if (o.bottom == "conical")
    check_cone_height(t, "hopper_half_angle_deg", o.upper_diameter_m, o.orifice_diameter_m,
                      o.hopper_half_angle_deg);
  o.fill_mass_kg = t.number("fill_mass_kg", kPositive);
  o.lower_diameter_m = t.number_at_most("lower_diameter_m", kPositive, kMaxLength);
  // Refused here, naming both: the engine's message names lower_diameter_m
  // first, which blames it when upper_diameter_m is the one too large.
  if (o.lower_diameter_m < o.upper_diameter_m)
    t.fail_here("upper_diameter_m = " + format_number(o.upper_diameter_m) +
                " exceeds lower_diameter_m = " + format_number(o.lower_diameter_m) +
                ": the lower chamber must be at least as wide as the upper one (one of the two "
                "is wrong)");
  o.drop_height_m = t.number_at_most("drop_height_m", kPositive, kMaxLength);
  o.form_pile = t.boolean_or("form_pile", o.form_pile);
  o.fill_lattice_spacing_diameters =
      t.number_or("fill_lattice_spacing_diameters", o.fill_lattice_spacing_diameters, kFillSpacing);
  o.reduction = read_reduction(t, true);
  t.finish();
  check_grain_count(t, m, o.reduction, p, o.fill_mass_kg);
  check_run_estimate(t, m, o.reduction, p, max_steps);
  return build_guarded(t, [&] { return std::make_unique<dem::Sandglass>(o, m, p); });
}

}  // namespace

void register_sandglass(ApparatusRegistry& r) {
  const dem::SandglassOptions d;
  const std::string len = range_of(kPositive) + ", at most " + format_number(kMaxLength.max);
  ModelInfo info{"sandglass",
                 "a cylinder discharging through an orifice into a lower chamber: discharge "
                 "time, mass flow and the angle of repose of the pile it leaves",
                 {{"upper_diameter_m", "m", "required", len, "the upper chamber's diameter"},
                  {"upper_height_m", "m", "required", len,
                   "the height of the upper chamber's cylindrical part"},
                  {"bottom", "", "required", "\"flat\" | \"conical\"", "the upper chamber's floor"},
                  {"hopper_half_angle_deg", "deg", "required when conical",
                   range_of(kHalfAngle), "the hopper's half angle from the vertical"},
                  {"orifice_diameter_m", "m", "required", len,
                   "the orifice (a slice's slot width)"},
                  {"fill_mass_kg", "kg", "required", range_of(kPositive),
                   "the fill of the full apparatus; a slice takes its share"},
                  {"lower_diameter_m", "m", "required", len + ", >= upper_diameter_m",
                   "the lower chamber's diameter"},
                  {"drop_height_m", "m", "required", len,
                   "the orifice plane's height above the lower chamber's floor"},
                  {"form_pile", "", d.form_pile ? "true" : "false", "true | false",
                   "false: stop after max_flow_s of discharge, no pile, no angle of repose"},
                  {"fill_lattice_spacing_diameters", "1",
                   format_number(d.fill_lattice_spacing_diameters), range_of(kFillSpacing),
                   "the fill's lattice spacing in largest diameters"}}};
  for (ModelKey& k : reduction_keys(true)) info.keys.push_back(std::move(k));
  r.add(std::move(info), {&read_sandglass, &dem::Sandglass::wall_group_names});
}

}  // namespace demcal::config
