// The one registry of observables (io/observable_registry.hpp): its entries are
// complete, every older table is a view of it, each measurement writes only what
// the registry says its apparatus measures, and a recording naming an observable
// its setup's apparatus kind does not measure is refused with file and line.
#include "calibrate/report/labels.hpp"
#include "config/observables.hpp"
#include "config/recordings_csv.hpp"
#include "config/study_config.hpp"
#include "config/toml_reader.hpp"
#include "dem/apparatus/apparatus.hpp"
#include "engines/engine_measure.hpp"
#include "io/observable_registry.hpp"
#include "study/calibration_targets.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

namespace demcal {
namespace {

namespace fs = std::filesystem;
using io::ObservableKind;

TEST(ObservableRegistry, EveryEntryIsCompleteAndNamedOnce) {
  std::set<std::string_view> names;
  for (const io::ObservableInfo& o : io::observable_registry()) {
    EXPECT_TRUE(names.insert(o.name).second) << o.name << " is declared twice";
    EXPECT_FALSE(o.unit.empty()) << o.name;
    EXPECT_FALSE(o.label.empty()) << o.name;
    EXPECT_FALSE(o.short_label.empty()) << o.name;
    EXPECT_FALSE(o.display_unit.empty()) << o.name;
    EXPECT_FALSE(o.range_text.empty()) << o.name;
    EXPECT_LT(o.lo, o.hi) << o.name;
    EXPECT_FALSE(o.measured_by.empty()) << o.name << " is measured by no apparatus";
    for (std::string_view k : o.measured_by) {
      const auto& kinds = io::apparatus_kinds();
      EXPECT_NE(std::find(kinds.begin(), kinds.end(), k), kinds.end()) << o.name << ": " << k;
    }
    EXPECT_EQ(io::find_observable(o.name), &o);
  }
  EXPECT_EQ(io::find_observable("no_such_observable"), nullptr);
  // The study's apparatus kinds are the registry's.
  EXPECT_EQ(config::known_apparatus_names(), io::apparatus_kinds());
}

TEST(ObservableRegistry, TheConfigTablesAreViewsOfIt) {
  EXPECT_EQ(config::stable_observable_names(),
            (std::vector<std::string>{"angle_of_repose_deg", "discharge_time_s",
                                      "mass_flow_rate_kg_s", "bulk_density_kg_m3"}));
  EXPECT_EQ(config::series_observable_names(),
            (std::vector<std::string>{"discharge_t25_s", "discharge_t50_s", "discharge_t75_s"}));
  for (const std::string& name : config::observable_names()) {
    const io::ObservableInfo* o = io::find_observable(name);
    ASSERT_NE(o, nullptr) << name;
    EXPECT_EQ(config::unit_of_observable(name), o->unit);
    EXPECT_EQ(config::observable_range_text(name), o->range_text);
    EXPECT_TRUE(config::observable_in_range(name, o->hi));
    EXPECT_FALSE(config::observable_in_range(name, o->hi * 1.01 + 1.0));
    EXPECT_EQ(config::observable_in_range(name, o->lo), !o->lo_open);
  }
  // Only stable and series observables are recorded, so only they have a recording unit.
  EXPECT_THROW(config::unit_of_observable("pile_height_m"), std::out_of_range);
  EXPECT_EQ(config::unit_of_observable("bulk_density_kg_m3"), "kg/m3");
}

TEST(ObservableRegistry, TheReportLabelsAreViewsOfIt) {
  for (const io::ObservableInfo& o : io::observable_registry()) {
    const std::string name(o.name);
    EXPECT_EQ(calibrate::observable_name(name), o.label);
    EXPECT_EQ(calibrate::observable_short(name), o.short_label);
    EXPECT_EQ(calibrate::observable_label(name),
              std::string(o.label) + " (" + std::string(o.display_unit) + ")");
  }
  EXPECT_EQ(calibrate::observable_short("angle_of_repose_deg"), "AoR");
  EXPECT_EQ(calibrate::observable_unit_suffix("angle_of_repose_deg"), "°");
  EXPECT_EQ(calibrate::observable_unit_suffix("mass_flow_rate_kg_s"), " kg/s");
  EXPECT_EQ(calibrate::observable_unit_suffix("discharged_mass_kg"), " kg");
  EXPECT_EQ(calibrate::observable_unit_suffix("unknown"), "");
}

TEST(ObservableRegistry, SaysWhichApparatusMeasureWhat) {
  EXPECT_EQ(io::recordable_observables("sandglass"), config::observable_names());
  EXPECT_EQ(io::recordable_observables("conical_pile"),
            (std::vector<std::string>{"angle_of_repose_deg", "bulk_density_kg_m3"}));
  EXPECT_EQ(io::recordable_observables("rectangular_container"),
            (std::vector<std::string>{"angle_of_repose_deg", "bulk_density_kg_m3"}));
  EXPECT_TRUE(io::recordable_observables("poured_slab_pile").empty());
  EXPECT_TRUE(io::measures("sandglass", "discharge_t50_s"));
  EXPECT_FALSE(io::measures("conical_pile", "discharge_time_s"));
  EXPECT_FALSE(io::measures("sandglass", "no_such_observable"));
  const std::string table = io::observable_registry_table();
  for (const io::ObservableInfo& o : io::observable_registry())
    EXPECT_NE(table.find(std::string(o.name) + " | " + std::string(io::to_string(o.kind))),
              std::string::npos)
        << table;
}

// A synthetic quasi-2D heap, as an engine would dump it (grains d apart, 30 deg flanks).
engines::ParticleDump heap(double d) {
  engines::ParticleDump dump;
  const double slope = std::tan(30.0 * M_PI / 180.0);
  for (double x = -0.03 + d / 2; x < 0.03; x += d)
    for (double y = -0.03 + d / 2; y < 0.03; y += d) {
      const double top = std::max(d / 2, 0.02 - slope * std::hypot(x, y));
      for (double z = d / 2; z <= top; z += d) {
        dump.position_m.push_back({x, y, z});
        dump.radius_m.push_back(d / 2);
      }
    }
  return dump;
}

TEST(ObservableRegistry, EngineMeasurementsWriteOnlyWhatTheirApparatusMeasures) {
  const engines::ParticleDump pile = heap(2e-3);
  const auto slice = engines::measure_engine_output(
      {{"kind", "slice_angle_of_repose"}, {"apparatus", "rectangular_container"}}, pile, nullptr);
  EXPECT_TRUE(slice.observables.contains("angle_of_repose_deg"));
  EXPECT_EQ(dem::protocol::observables_not_measured_by("rectangular_container", slice.observables),
            std::vector<std::string>{});
  const auto cone = engines::measure_engine_output({{"kind", "conical_angle_of_repose"},
                                                    {"apparatus", "conical_pile"},
                                                    {"base_height_m", 0.0},
                                                    {"outlet_height_m", 0.05},
                                                    {"base_radius_m", 0.03}},
                                                   pile, nullptr);
  EXPECT_TRUE(cone.observables.contains("pile_base_diameter_m"));
  EXPECT_EQ(dem::protocol::observables_not_measured_by("conical_pile", cone.observables),
            std::vector<std::string>{});
  engines::MassSeries m;
  for (int i = 0; i <= 40; ++i) {
    const double t = 0.005 * i, out = std::min(1e-3, std::max(0.0, 0.01 * (t - 0.01)));
    m.time_s.push_back(t);
    m.discharged_kg.push_back(out);
    m.above_orifice_kg.push_back(1e-3 - out);
  }
  const auto glass = engines::measure_engine_output({{"kind", "sandglass_slice"},
                                                     {"apparatus", "sandglass"},
                                                     {"orifice_plane_z_m", 0.03},
                                                     {"orifice_width_m", 0.008},
                                                     {"form_pile", false},
                                                     {"stall_time_s", 0.05}},
                                                    engines::ParticleDump{}, &m);
  EXPECT_TRUE(glass.observables.contains("discharge_time_s"));
  EXPECT_EQ(dem::protocol::observables_not_measured_by("sandglass", glass.observables),
            std::vector<std::string>{});
  // The check sees a name the kind does not measure, and one nobody declared.
  EXPECT_EQ(dem::protocol::observables_not_measured_by("conical_pile", glass.observables),
            (std::vector<std::string>{"discharge_time_s", "mass_flow_rate_kg_s"}));
  EXPECT_EQ(dem::protocol::observables_not_measured_by("sandglass", {{"aor", 1.0}}),
            std::vector<std::string>{"aor"});
}

std::string refusal(const std::string& csv, const std::vector<config::RecordedSetup>& setups) {
  std::istringstream in(csv);
  std::vector<std::string> names;
  for (const auto& s : setups) names.push_back(s.name);
  try {
    const auto recordings = config::read_recordings_csv(in, "rec.csv", names);
    config::require_measured_by_setups(recordings, "rec.csv", setups);
  } catch (const config::ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ObservableRegistry, ARecordingTheSetupsKindDoesNotMeasureIsRefused) {
  const std::vector<config::RecordedSetup> setups = {{"glass", "sandglass"},
                                                     {"pile", "conical_pile"}};
  const std::string header = "setup,observable,value,sigma,unit\n";
  EXPECT_EQ(
      refusal(header + "glass,discharge_time_s,0.5,0.01,s\npile,angle_of_repose_deg,30,1,deg\n",
              setups),
      "");
  EXPECT_EQ(
      refusal(header + "glass,discharge_time_s,0.5,0.01,s\npile,discharge_time_s,0.5,0.01,s\n",
              setups),
      "rec.csv:3: observable \"discharge_time_s\" is not measured by setup \"pile\", a "
      "conical_pile; a conical_pile measures angle_of_repose_deg, bulk_density_kg_m3");
  EXPECT_NE(refusal(header + "pile,discharge_t50_s,0.5,0.01,s\n", setups).find("rec.csv:2: "),
            std::string::npos);
}

// None of the checked-in studies names an observable its setup does not measure.
TEST(ObservableRegistry, TheCheckedInStudiesRecordingsAreAccepted) {
  std::size_t checked = 0;
  for (const auto& dir :
       {fs::path(DEMCAL_SOURCE_DIR) / "studies", fs::path(DEMCAL_SOURCE_DIR) / "tests" / "data"}) {
    for (const auto& entry : fs::directory_iterator(dir)) {
      const fs::path file = entry.path() / "study.toml";
      if (!fs::exists(file)) continue;
      config::StudyConfig study;
      try {
        study = config::load_study_config(file, {});
      } catch (const std::exception&) {
        continue;  // not a study config (an engine deck's table and the like)
      }
      if (!study.calibration) continue;
      EXPECT_NO_THROW(study::study_recordings(study)) << file;
      ++checked;
    }
  }
  EXPECT_GE(checked, 10u);
}

}  // namespace
}  // namespace demcal
