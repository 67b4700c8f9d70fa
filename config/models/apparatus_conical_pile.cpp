// The conical pile (dem/apparatus/conical_pile.hpp): its reader and its registration.

#include "config/models/apparatus_models.hpp"
#include "config/run_sanity.hpp"
#include "dem/apparatus/conical_pile.hpp"

namespace demcal::config {

namespace {

using namespace apparatus_reading;
using reader::Table;
using reader::format_number;

std::unique_ptr<dem::Apparatus> read_conical_pile(Table& t, const dem::GranularMaterial& m,
                                                  double max_steps, const dem::RunProtocol& p) {
  dem::ConicalPileOptions o;
  o.funnel_top_diameter_m = t.number_at_most("funnel_top_diameter_m", kPositive, kMaxLength);
  o.funnel_outlet_diameter_m = t.number_at_most("funnel_outlet_diameter_m", kPositive, kMaxLength);
  o.funnel_half_angle_deg = t.number("funnel_half_angle_deg", kHalfAngle);
  check_cone_height(t, "funnel_half_angle_deg", o.funnel_top_diameter_m, o.funnel_outlet_diameter_m,
                    o.funnel_half_angle_deg);
  o.feed_height_m = t.number_at_most("feed_height_m", kPositive, kMaxLength);
  o.drop_height_m = t.number_at_most("drop_height_m", kPositive, kMaxLength);
  o.base_diameter_m = t.number_at_most("base_diameter_m", kPositive, kMaxLength);
  o.fill_mass_kg = t.number("fill_mass_kg", kPositive);
  o.reduction = read_reduction(t, true);
  t.finish();
  check_grain_count(t, m, o.reduction, p, o.fill_mass_kg);
  check_run_estimate(t, m, o.reduction, p, max_steps);
  return build_guarded(t, [&] { return std::make_unique<dem::ConicalPile>(o, m, p); });
}

}  // namespace

void register_conical_pile(ApparatusRegistry& r) {
  const std::string len = range_of(kPositive) + ", at most " + format_number(kMaxLength.max);
  ModelInfo info{"conical_pile",
                 "a funnel pouring onto a round base: the angle of repose of the pile",
                 {{"funnel_top_diameter_m", "m", "required", len, "the funnel's top diameter"},
                  {"funnel_outlet_diameter_m", "m", "required", len, "the funnel's outlet"},
                  {"funnel_half_angle_deg", "deg", "required", range_of(kHalfAngle),
                   "the funnel's half angle from the vertical"},
                  {"feed_height_m", "m", "required", len,
                   "the height of the feed above the funnel's outlet"},
                  {"drop_height_m", "m", "required", len, "the outlet's height above the base"},
                  {"base_diameter_m", "m", "required", len, "the base the pile forms on"},
                  {"fill_mass_kg", "kg", "required", range_of(kPositive),
                   "the fill of the full apparatus; a slice takes its share"}}};
  for (ModelKey& k : reduction_keys(true)) info.keys.push_back(std::move(k));
  r.add(std::move(info), {&read_conical_pile, &dem::ConicalPile::wall_group_names});
}

}  // namespace demcal::config
