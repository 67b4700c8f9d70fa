// The full (3D) sandglass on another engine (issue 17): its LAMMPS deck against
// a golden file and against dem::Sandglass's geometry, the refusals that are
// left (a flat bottom, LIGGGHTS), and demcal's measurement of the engine's
// output with the full apparatus' rules (axisymmetric arch test, conical AoR of
// the lower pile, the whole chamber's bulk density).
#include "engines/engine_measure.hpp"
#include "engines/lammps_deck.hpp"
#include "engines/liggghts_deck.hpp"

#include "dem/measure/angle_of_repose.hpp"
#include "tests/support/engine_fixtures.hpp"
#include "tests/support/golden.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace demcal::engines {
namespace {

using testing::expect_golden;
using testing::peer_material;

constexpr double kPi = std::numbers::pi;

dem::SandglassOptions full_sandglass() { return testing::small_full_sandglass(0.005); }

double hopper_height_m() { return (0.012 - 0.004) / std::tan(kPi / 6.0); }

MassSeries series_to(double fill_kg, double out_kg) {
  MassSeries m;
  for (int i = 0; i <= 40; ++i) {
    const double t = 0.005 * i;
    const double out = std::min(out_kg, std::max(0.0, 0.01 * (t - 0.01)));
    m.time_s.push_back(t);
    m.discharged_kg.push_back(out);
    m.above_orifice_kg.push_back(fill_kg - out);
  }
  return m;
}

void add_grain(ParticleDump& d, const dem::Vec3& x, double radius_m) {
  d.id.push_back(static_cast<std::int64_t>(d.id.size()) + 1);
  d.type.push_back(1);
  d.position_m.push_back(x);
  d.radius_m.push_back(radius_m);
  d.velocity_m_s.push_back({});
}

TEST(EnginesFullSandglass, LammpsDeckGoldenAndDemcalsGeometry) {
  const auto r = write_lammps_deck(full_sandglass(), peer_material(), dem::RunProtocol{});
  ASSERT_TRUE(r.ok()) << r.refusal;
  expect_golden(r.deck->script, "engines/lammps_sandglass_full.in");
  const std::string& s = r.deck->script;
  const nlohmann::json& layout = r.deck->record["layout"];
  EXPECT_EQ(layout["variant"], "full");
  EXPECT_EQ(layout["periodic"], nlohmann::json::array({false, false, false}));
  EXPECT_EQ(r.deck->record["measurement"]["kind"], "sandglass_full");
  EXPECT_EQ(r.deck->mass_series_name, "mass_series.txt");
  EXPECT_FALSE(r.deck->fill_dump_name.empty());
  // dem::Sandglass's hopper: a cone from the orifice (r = 4 mm at z = 30 mm) to the
  // chamber (r = 12 mm) over (12 - 4) mm / tan 30 deg, then the chamber's cylinder.
  const double zc = 0.03 + hopper_height_m();
  ASSERT_EQ(layout["shells"].size(), 3u);
  EXPECT_EQ(layout["shells"][1]["name"], "hopper");
  EXPECT_DOUBLE_EQ(layout["shells"][1]["radius_lower_m"].get<double>(), 0.004);
  EXPECT_DOUBLE_EQ(layout["shells"][1]["radius_upper_m"].get<double>(), 0.012);
  EXPECT_DOUBLE_EQ(layout["shells"][1]["z_upper_m"].get<double>(), zc);
  EXPECT_DOUBLE_EQ(layout["shells"][2]["z_upper_m"].get<double>(), zc + 0.03);
  EXPECT_NE(s.find("cone z 0 0 0.004 0.012 0.03 "), std::string::npos);
  // The whole fill, not a slice's share.
  const double grain = 2650.0 * kPi / 6.0 * 1e-9;
  EXPECT_EQ(layout["particles"].get<std::size_t>(),
            static_cast<std::size_t>(std::llround(0.005 / grain)));
  // The shut orifice goes at opening, and only then.
  const auto open = s.find("open the orifice");
  ASSERT_NE(open, std::string::npos);
  EXPECT_GT(s.find("unfix           wall_orifice_shut"), open);
  EXPECT_LT(s.find("fix             wall_orifice_shut"), open);
  // What the deck leaves out is said, in the deck and in the record.
  EXPECT_NE(s.find("# approximation (geometry): the orifice plate outside"), std::string::npos);
  EXPECT_EQ(layout["approximations"].size(), 1u);
}

TEST(EnginesFullSandglass, RefusedWhereNoPrimitiveIsWritten) {
  const auto m = peer_material();
  const dem::RunProtocol p;
  auto flat = full_sandglass();
  flat.bottom = "flat";
  const auto r = write_lammps_deck(flat, m, p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.refusal.find("flat bottom"), std::string::npos) << r.refusal;
  EXPECT_NE(r.refusal.find("bottom = \"conical\""), std::string::npos) << r.refusal;
  // LIGGGHTS writes the same solids as STL meshes: the two cylinders, the cone,
  // the orifice plate with its hole (so nothing is left out) and the shut
  // orifice's disc, which goes after the fill has settled.
  const auto liggghts = write_liggghts_deck(full_sandglass(), m, p);
  ASSERT_TRUE(liggghts.ok()) << liggghts.refusal;
  EXPECT_EQ(liggghts.deck->files.size(), 5u);
  testing::expect_golden(liggghts.deck->script, "engines/liggghts_sandglass_full.in");
  const std::string& ls = liggghts.deck->script;
  const auto settled = ls.find("# the settled fill");
  ASSERT_NE(settled, std::string::npos);
  EXPECT_GT(ls.find("unfix           mesh_orifice_shut"), settled);
  EXPECT_LT(ls.find("fix             mesh_orifice_shut"), settled);
  EXPECT_EQ(ls.find("# approximation (geometry)"), std::string::npos);
  EXPECT_NE(ls.find("mesh_orifice_plate", settled), std::string::npos);  // stays after opening
  // And the flat bottom, whose fill rests on the plate: the plate and the
  // chambers' cylinders, no cone.
  const auto flat_liggghts = write_liggghts_deck(flat, m, p);
  ASSERT_TRUE(flat_liggghts.ok()) << flat_liggghts.refusal;
  testing::expect_golden(flat_liggghts.deck->script, "engines/liggghts_sandglass_full_flat.in");
  const auto& fl = flat_liggghts.deck->record["layout"];
  ASSERT_EQ(fl["shells"].size(), 2u);
  ASSERT_EQ(fl["annuli"].size(), 1u);
  EXPECT_DOUBLE_EQ(fl["annuli"][0]["inner_radius_m"].get<double>(), 0.004);
  EXPECT_DOUBLE_EQ(fl["annuli"][0]["z_upper_m"].get<double>(), 0.03);
  EXPECT_DOUBLE_EQ(fl["shells"][1]["z_lower_m"].get<double>(), 0.03);  // the chamber from the plate
  // A fill the chamber cannot hold is an error naming the keys to change, as in demcal.
  auto heavy = full_sandglass();
  heavy.fill_mass_kg = 0.1;
  try {
    (void)write_lammps_deck(heavy, m, p);
    ADD_FAILURE() << "a 0.1 kg fill was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("upper_height_m"), std::string::npos) << e.what();
  }
  // An orifice below 3 grains is an error, as in demcal, not a refusal.
  auto narrow = full_sandglass();
  narrow.orifice_diameter_m = 0.002;
  EXPECT_THROW(write_lammps_deck(narrow, m, p), std::invalid_argument);
}

nlohmann::json full_plan() {
  const auto r = write_lammps_deck(full_sandglass(), peer_material(), dem::RunProtocol{});
  return r.deck->record["measurement"];
}

TEST(EnginesFullSandglass, ArchOverTheOrificeIsJudgedAboutTheAxis) {
  // A flow that stopped at 60 % with one grain resting 2 mm above the plate. The
  // arch rule looks within a quarter of the orifice's diameter (2 mm) of the axis.
  const MassSeries m = series_to(1e-3, 0.6e-3);
  const nlohmann::json plan = full_plan();
  ParticleDump beside;  // 2.1 mm off the axis, though only 1.5 mm off it in x
  add_grain(beside, {0.0015, 0.0015, 0.032}, 0.5e-3);
  const auto kept = measure_engine_output(plan, beside, &m);
  EXPECT_FALSE(kept.observables["discharge_time_s"].is_null()) << kept.details.dump();
  EXPECT_NEAR(kept.details["retained_in_dead_zones_fraction"].get<double>(), 0.4, 1e-9);
  // The slice's rule (|x| only) would call the same grain an arch.
  nlohmann::json slice_plan = plan;
  slice_plan["kind"] = "sandglass_slice";
  EXPECT_TRUE(
      measure_engine_output(slice_plan, beside, &m).observables["discharge_time_s"].is_null());
  ParticleDump over;  // 0.7 mm off the axis: an arch
  add_grain(over, {0.0005, 0.0005, 0.032}, 0.5e-3);
  const auto clogged = measure_engine_output(plan, over, &m);
  EXPECT_TRUE(clogged.observables["discharge_time_s"].is_null());
  EXPECT_EQ(clogged.details["grains_over_orifice_at_stop"].get<int>(), 1);
}

TEST(EnginesFullSandglass, LowerPileIsMeasuredAsAConeAboutTheAxis) {
  // A cone of 1 mm grains at 30 degrees on the floor, centred on the axis, and
  // grains still in the hopper above the orifice plane (left out of the pile).
  ParticleDump d;
  const double slope = std::tan(kPi / 6.0);
  for (double x = -0.028; x <= 0.028; x += 0.001)
    for (double y = -0.028; y <= 0.028; y += 0.001) {
      const double r = std::hypot(x, y);
      if (r > 0.028) continue;
      const double top = 0.016 - r * slope;
      for (double z = 0.0005; z <= top; z += 0.001) add_grain(d, {x, y, z}, 0.5e-3);
    }
  for (int i = 0; i < 30; ++i) add_grain(d, {0.001 * (i % 6) - 0.003, 0.0, 0.035}, 0.5e-3);
  nlohmann::json plan = full_plan();
  const MassSeries m = series_to(1e-3, 1e-3);
  const auto r = measure_engine_output(plan, d, &m);
  ASSERT_TRUE(r.observables["angle_of_repose_deg"].is_number()) << r.details.dump();
  std::vector<dem::Vec3> pos;
  std::vector<double> rad;
  for (std::size_t i = 0; i < d.size(); ++i)
    if (d.position_m[i].z < 0.03) {
      pos.push_back(d.position_m[i]);
      rad.push_back(d.radius_m[i]);
    }
  dem::ConicalAoROptions a;
  a.axis_centre_m = std::array<double, 2>{0.0, 0.0};
  const double direct = dem::measure_conical_angle_of_repose(pos, rad, a).mean_deg;
  EXPECT_DOUBLE_EQ(r.observables["angle_of_repose_deg"].get<double>(), direct);
  EXPECT_NEAR(direct, 30.0, 3.0);
}

TEST(EnginesFullSandglass, BulkDensityIsTheWholeChambers) {
  // Grains of 1 mm on a square grid filling the cylinder above the hopper to a
  // flat surface 10 mm above it: the volume is the hopper's frustum plus that
  // cylinder, pi h (r0^2 + r0 ru + ru^2) / 3 + pi ru^2 10 mm.
  const double h = hopper_height_m(), zc = 0.03 + h;
  ParticleDump fill;
  for (double x = -0.0115; x <= 0.0115; x += 0.001)
    for (double y = -0.0115; y <= 0.0115; y += 0.001)
      if (std::hypot(x, y) <= 0.0115)
        for (int k = 0; k < 10; ++k) add_grain(fill, {x, y, zc + 0.0005 + 0.001 * k}, 0.5e-3);
  const double mass = static_cast<double>(fill.size()) * 2650.0 * kPi / 6.0 * 1e-9;
  const double volume =
      kPi * h * (0.004 * 0.004 + 0.004 * 0.012 + 0.012 * 0.012) / 3.0 + kPi * 0.012 * 0.012 * 0.01;
  const MassSeries m = series_to(1e-3, 1e-3);
  const auto r = measure_engine_output(full_plan(), ParticleDump{}, &m, &fill);
  ASSERT_TRUE(r.observables.contains("bulk_density_kg_m3")) << r.details.dump();
  EXPECT_NEAR(r.observables["bulk_density_kg_m3"].get<double>(), mass / volume,
              1e-9 * mass / volume);
}

}  // namespace
}  // namespace demcal::engines
