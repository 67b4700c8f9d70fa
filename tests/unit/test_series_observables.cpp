// The m(t) segments read off a run record's discharge series (study/run_record.hpp):
// interpolated between samples, null without a finished discharge.
#include "study/run_record.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace demcal::cli {
namespace {

using namespace demcal::config;
using namespace demcal::study;

TEST(SeriesObservables, TheDischargeSeriesIsReadAtAQuarterHalfAndThreeQuarters) {
  // m(t) rising linearly to 2 kg at t = 1 s after a 0.1 s delay, sampled every 0.1 s.
  nlohmann::json series = {
      {"discharged_mass",
       {{"time_s", nlohmann::json::array()}, {"mass_kg", nlohmann::json::array()}}}};
  for (int i = 0; i <= 10; ++i) {
    const double t = 0.1 * i;
    series["discharged_mass"]["time_s"].push_back(t);
    series["discharged_mass"]["mass_kg"].push_back(t <= 0.1 ? 0.0 : 2.0 * (t - 0.1) / 0.9);
  }
  const nlohmann::json finished = {{"discharge_time_s", 1.0}};
  const nlohmann::json o = series_observables(series, finished);
  // 25 % of 2 kg at t = 0.1 + 0.25 * 0.9: read between the samples, not snapped to one.
  EXPECT_NEAR(o["discharge_t25_s"].get<double>(), 0.1 + 0.25 * 0.9, 1e-12);
  EXPECT_NEAR(o["discharge_t50_s"].get<double>(), 0.1 + 0.50 * 0.9, 1e-12);
  EXPECT_NEAR(o["discharge_t75_s"].get<double>(), 0.1 + 0.75 * 0.9, 1e-12);
  // No finished discharge (a clog, or an apparatus without one): nothing read off.
  const nlohmann::json clogged = {{"discharge_time_s", nullptr}};
  EXPECT_TRUE(series_observables(series, clogged)["discharge_t50_s"].is_null());
  EXPECT_TRUE(series_observables(nlohmann::json::object(), finished)["discharge_t50_s"].is_null());
  // Every name a recording or a design table may use.
  EXPECT_EQ(observable_names().size(),
            stable_observable_names().size() + series_observable_names().size());
}

}  // namespace
}  // namespace demcal::cli
