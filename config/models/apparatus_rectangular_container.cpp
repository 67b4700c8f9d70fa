// The rectangular container (dem/apparatus/rectangular_container.hpp): its
// reader and its registration.

#include "config/models/apparatus_models.hpp"
#include "config/run_sanity.hpp"
#include "dem/apparatus/rectangular_container.hpp"

namespace demcal::config {

namespace {

using namespace apparatus_reading;
using reader::Table;
using reader::at_least;
using reader::between;
using reader::format_number;

std::unique_ptr<dem::Apparatus> read_rectangular_container(Table& t, const dem::GranularMaterial& m,
                                                           double max_steps,
                                                           const dem::RunProtocol& p) {
  dem::RectangularContainerOptions o;
  o.width_m = t.number_at_most("width_m", kPositive, kMaxLength);
  o.height_m = t.number_at_most("height_m", kPositive, kMaxLength);
  const bool has_m = t.has("thickness_m");
  const bool has_d = t.has("thickness_diameters");
  if (!has_m && !has_d)
    t.fail("thickness_m",
           "missing required key; expected thickness_m (a number > 0) or thickness_diameters "
           "(a number > 0)");
  if (has_m && has_d)
    t.fail("thickness_diameters", "give thickness_m or thickness_diameters, not both");
  if (has_m) o.thickness_m = t.number_at_most("thickness_m", kPositive, kMaxLength);
  if (has_d) o.thickness_diameters = t.number("thickness_diameters", kPositive);
  o.boundary = t.choice("boundary", {"walls", "periodic"});
  o.fill_mass_kg = t.number("fill_mass_kg", kPositive);
  o.inlet_width_m = t.number_or("inlet_width_m", 0.0, at_least(0));
  o.inlet_height_m = t.number_or("inlet_height_m", 0.0, between(0, false, o.height_m, true));
  o.inlet_speed_m_s = t.number_or("inlet_speed_m_s", 0.5, kPositive);
  o.median_band_diameters = t.number_or("median_band_diameters", 2.0, kPositive);
  o.reduction = read_reduction(t, false);
  t.finish();
  check_grain_count(t, m, o.reduction, p, o.fill_mass_kg);
  check_run_estimate(t, m, o.reduction, p, max_steps);
  return build_guarded(t, [&] { return std::make_unique<dem::RectangularContainer>(o, m, p); });
}

}  // namespace

void register_rectangular_container(ApparatusRegistry& r) {
  const std::string len = range_of(kPositive) + ", at most " + format_number(kMaxLength.max);
  ModelInfo info{
      "rectangular_container",
      "a slab filled from an inlet at one end: the heap's angle of repose",
      {{"width_m", "m", "required", len, "the container's width"},
       {"height_m", "m", "required", len, "the container's height"},
       {"thickness_m", "m", "thickness_m or thickness_diameters", len,
        "the thickness across the slab"},
       {"thickness_diameters", "1", "thickness_m or thickness_diameters", range_of(kPositive),
        "the thickness in mean grain diameters"},
       {"boundary", "", "required", "\"walls\" | \"periodic\"",
        "what bounds the slab across its thickness"},
       {"fill_mass_kg", "kg", "required", range_of(kPositive), "the fill"},
       {"inlet_width_m", "m", "0 (8 mean diameters)", range_of(at_least(0)), "the inlet's width"},
       {"inlet_height_m", "m", "0 (0.8 height_m)", "[0, height_m)", "the inlet's height"},
       {"inlet_speed_m_s", "m/s", "0.5", range_of(kPositive), "the inflow's speed, downwards"},
       {"median_band_diameters", "1", "2", range_of(kPositive),
        "the band around the median surface the heap's angle is fitted in, in mean diameters"}}};
  for (ModelKey& k : reduction_keys(false)) info.keys.push_back(std::move(k));
  r.add(std::move(info),
        {&read_rectangular_container, &dem::RectangularContainer::wall_group_names});
}

}  // namespace demcal::config
