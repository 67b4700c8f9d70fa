// Discharge measurement (m(t) -> discharge time, flow rate, clog) and the
// Beverloo fit, on synthetic curves whose answers are known by construction.
#include "dem/measure/beverloo.hpp"
#include "dem/measure/discharge.hpp"
#include "dem/random.hpp"
#include "dem/simulation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace demcal::dem {
namespace {

// A discharge built from three pieces with closed-form inverses: the rate
// ramps linearly from 0 to W over the start transient, stays at W, then falls
// linearly to 0 over the end tail, leaving final_kg discharged (1 % of the
// 1 kg fill stays behind, as on a hopper wall).
struct Curve {
  double rate_kg_s = 0.5;
  double start_s = 0.2;   // start transient
  double tail_s = 0.4;    // end tail
  double final_kg = 0.99;
  double fill_kg = 1.0;

  double start_mass_kg() const { return rate_kg_s * start_s / 2.0; }         // 0.05
  double tail_mass_kg() const { return final_kg - rate_kg_s * tail_s / 2.0; }  // 0.89
  double tail_start_s() const {                                              // 1.88
    return start_s + (tail_mass_kg() - start_mass_kg()) / rate_kg_s;
  }
  double end_s() const { return tail_start_s() + tail_s; }  // 2.28

  double mass_kg(double t) const {
    if (t <= 0.0) return 0.0;
    if (t < start_s) return rate_kg_s * t * t / (2.0 * start_s);
    if (t < tail_start_s()) return start_mass_kg() + rate_kg_s * (t - start_s);
    if (t < end_s()) {
      const double u = t - tail_start_s();
      return tail_mass_kg() + rate_kg_s * u - rate_kg_s * u * u / (2.0 * tail_s);
    }
    return final_kg;
  }
  double time_at_s(double m) const {
    if (m <= 0.0) return 0.0;
    if (m < start_mass_kg()) return std::sqrt(2.0 * start_s * m / rate_kg_s);
    if (m < tail_mass_kg()) return start_s + (m - start_mass_kg()) / rate_kg_s;
    if (m < final_kg) {
      return tail_start_s() +
             tail_s * (1.0 - std::sqrt(1.0 - 2.0 * (m - tail_mass_kg()) / (rate_kg_s * tail_s)));
    }
    return end_s();
  }
};

constexpr double kInterval = 0.005;

struct Series {
  std::vector<double> time_s;
  std::vector<double> mass_kg;
};

Series sample_curve(const std::function<double(double)>& mass_at, double duration_s) {
  Series s;
  const int n = static_cast<int>(std::lround(duration_s / kInterval));
  for (int i = 0; i <= n; ++i) {
    s.time_s.push_back(i * kInterval);
    s.mass_kg.push_back(mass_at(i * kInterval));
  }
  return s;
}

// The hand-computed crossings of the curve above (tail: 0.5 u - 0.625 u^2 =
// m - 0.89, u = (0.5 - sqrt(0.25 - 2.5 (m - 0.89))) / 1.25 after 1.88 s).
constexpr double kT90FillS = 1.9005266807797945;        // m = 0.9
constexpr double kT95FillS = 2.027017787186529;         // m = 0.95
constexpr double kT90DischargedS = 1.882005025157352;   // m = 0.891
constexpr double kT95DischargedS = 1.998575054410594;   // m = 0.9405
constexpr double kT98DischargedS = 2.102011236309704;   // m = 0.9702, the discharge time

template <class F>
void expect_invalid_argument(F&& f, const std::string& name) {
  try {
    f();
    ADD_FAILURE() << "expected std::invalid_argument naming " << name;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos)
        << "message '" << e.what() << "' does not name " << name;
  }
}

TEST(Discharge, CleanCurveGivesHandComputedTimes) {
  const Curve c;
  const Series s = sample_curve([&](double t) { return c.mass_kg(t); }, 3.0);
  const DischargeAnalysis a = analyse_discharge(s.time_s, s.mass_kg, c.fill_kg);
  EXPECT_EQ(a.status, "complete");
  EXPECT_FALSE(a.clogged);
  // Linear interpolation on the quadratic tail is good to ~1e-5 s at 5 ms sampling.
  EXPECT_NEAR(a.t90_s, kT90FillS, 1e-4);
  EXPECT_NEAR(a.t95_s, kT95FillS, 1e-4);
  EXPECT_NEAR(a.t90_of_discharged_s, kT90DischargedS, 1e-4);
  EXPECT_NEAR(a.t95_of_discharged_s, kT95DischargedS, 1e-4);
  EXPECT_NEAR(a.discharge_time_s, kT98DischargedS, 1e-4);
  EXPECT_NEAR(a.flow_stopped_s, c.end_s(), kInterval + 1e-9);
  EXPECT_NEAR(a.final_discharged_mass_kg, 0.99, 1e-12);
  EXPECT_NEAR(a.discharged_fraction, 0.99, 1e-12);
  EXPECT_NEAR(a.mass_flow_rate_kg_s, 0.5, 1e-9);
  EXPECT_NEAR(a.mass_flow_rate_r_squared, 1.0, 1e-12);
  EXPECT_NEAR(a.steady_start_s, c.time_at_s(0.2 * 0.99), kInterval);
  EXPECT_NEAR(a.steady_end_s, c.time_at_s(0.8 * 0.99), kInterval);
  EXPECT_EQ(a.pauses, 0);
  EXPECT_NEAR(a.stall_time_s, 0.1, 1e-12);
  EXPECT_NEAR(a.first_discharge_s, kInterval, 1e-12);
}

// Engine-like data: the mass moves in whole particles (1e-4 kg, 9900 of them
// discharged), each arriving with a timing jitter of +-3 particles.
TEST(Discharge, ParticleNoiseRecoversRateAndTime) {
  const Curve c;
  const double particle_kg = 1e-4;
  const int discharged = 9900;
  Random rng(7);
  std::vector<double> arrival_s(discharged);
  for (int n = 0; n < discharged; ++n) {
    const double m = std::clamp((n + 0.5 + 3.0 * rng.normal()) * particle_kg, 0.0, c.final_kg);
    arrival_s[n] = c.time_at_s(m);
  }
  std::sort(arrival_s.begin(), arrival_s.end());
  const Series s = sample_curve(
      [&](double t) {
        const auto count = std::upper_bound(arrival_s.begin(), arrival_s.end(), t) - arrival_s.begin();
        return static_cast<double>(count) * particle_kg;
      },
      3.0);
  const DischargeAnalysis a = analyse_discharge(s.time_s, s.mass_kg, c.fill_kg);
  EXPECT_EQ(a.status, "complete");
  EXPECT_NEAR(a.mass_flow_rate_kg_s, 0.5, 0.005);
  EXPECT_LT(a.mass_flow_rate_std_error_kg_s, 0.005);
  EXPECT_GT(a.mass_flow_rate_r_squared, 0.999);
  EXPECT_NEAR(a.discharge_time_s, kT98DischargedS, 0.01);
  EXPECT_NEAR(a.t90_s, kT90FillS, 0.01);
  EXPECT_NEAR(a.t95_s, kT95FillS, 0.01);
  EXPECT_NEAR(a.discharged_fraction, 0.99, 1e-9);
  EXPECT_NEAR(a.flow_stopped_s, c.end_s(), 0.02);
  EXPECT_EQ(a.pauses, 0);
}

// Additive measurement noise (0.5 g): the stall tolerance is set to five noise
// amplitudes so the noisy plateau reads as a stopped flow.
TEST(Discharge, AdditiveNoiseRecoversRateAndTime) {
  const Curve c;
  const double noise_kg = 5e-4;
  Random rng(11);
  const Series s = sample_curve(
      [&](double t) { return std::clamp(c.mass_kg(t) + noise_kg * rng.normal(), 0.0, c.fill_kg); },
      3.0);
  DischargeOptions o;
  o.stall_mass_kg = 5.0 * noise_kg;
  const DischargeAnalysis a = analyse_discharge(s.time_s, s.mass_kg, c.fill_kg, o);
  EXPECT_EQ(a.status, "complete");
  EXPECT_NEAR(a.mass_flow_rate_kg_s, 0.5, 0.005);
  EXPECT_NEAR(a.final_discharged_mass_kg, 0.99, 1e-3);
  EXPECT_NEAR(a.discharge_time_s, kT98DischargedS, 0.02);
  EXPECT_EQ(a.pauses, 0);
}

// A run loop may stop sampling the moment the whole fill has passed; nothing
// more can pass, so that is a stop without waiting stall_time_s.
TEST(Discharge, SeriesEndingWhenTheFillIsEmptyIsComplete) {
  Curve c;
  c.fill_kg = c.final_kg;
  const Series s = sample_curve([&](double t) { return c.mass_kg(t); }, c.end_s());
  const DischargeAnalysis a = analyse_discharge(s.time_s, s.mass_kg, c.fill_kg);
  EXPECT_EQ(a.status, "complete");
  EXPECT_NEAR(a.discharged_fraction, 1.0, 1e-12);
  EXPECT_NEAR(a.discharge_time_s, kT98DischargedS, 1e-4);
}

TEST(Discharge, ClogIsReportedNotTimed) {
  const Curve c;
  // An arch forms when 60 % of the fill has passed, at t = 0.1 + 2 * 0.6 = 1.3 s.
  const Series s = sample_curve([&](double t) { return std::min(c.mass_kg(t), 0.6); }, 2.0);
  const DischargeAnalysis a = analyse_discharge(s.time_s, s.mass_kg, c.fill_kg);
  EXPECT_TRUE(a.clogged);
  EXPECT_TRUE(std::isnan(a.discharge_time_s));
  EXPECT_EQ(a.status.rfind("clogged after 60.0 % discharged at t = 1.3", 0), 0u) << a.status;
  EXPECT_NEAR(a.flow_stopped_s, 1.3, kInterval + 1e-9);
  EXPECT_NEAR(a.discharged_fraction, 0.6, 1e-12);
  EXPECT_TRUE(std::isnan(a.t90_s));
  EXPECT_TRUE(std::isnan(a.t95_s));
  // The rate before the arch formed is still a measurement.
  EXPECT_NEAR(a.mass_flow_rate_kg_s, 0.5, 1e-9);
  const nlohmann::json j = to_json(a);
  EXPECT_TRUE(j["discharge_time_s"].is_null());
  EXPECT_TRUE(j["clogged"].get<bool>());
}

TEST(Discharge, NothingFlowingIsAClogAtZero) {
  const Series s = sample_curve([](double) { return 0.0; }, 0.5);
  const DischargeAnalysis a = analyse_discharge(s.time_s, s.mass_kg, 1.0);
  EXPECT_TRUE(a.clogged);
  EXPECT_EQ(a.status, "clogged after 0.0 % discharged at t = 0.000 s");
  EXPECT_TRUE(std::isnan(a.mass_flow_rate_kg_s));
  EXPECT_TRUE(std::isnan(a.first_discharge_s));
}

TEST(Discharge, SeriesEndingMidFlowIsRunning) {
  const Curve c;
  const Series s = sample_curve([&](double t) { return c.mass_kg(t); }, 1.5);
  const DischargeAnalysis a = analyse_discharge(s.time_s, s.mass_kg, c.fill_kg);
  EXPECT_EQ(a.status, "running");
  EXPECT_FALSE(a.clogged);
  EXPECT_TRUE(std::isnan(a.discharge_time_s));
  EXPECT_TRUE(std::isnan(a.flow_stopped_s));
  EXPECT_TRUE(std::isnan(a.t90_s));
  EXPECT_TRUE(std::isnan(a.t90_of_discharged_s));
  EXPECT_NEAR(a.discharged_fraction, 0.7, 1e-12);
  EXPECT_NEAR(a.mass_flow_rate_kg_s, 0.5, 1e-9);
}

TEST(Discharge, ResumedFlowIsAPauseNotAClog) {
  const Curve c;
  const double pause_at_s = c.time_at_s(0.5), pause_s = 0.3;
  const Series s = sample_curve(
      [&](double t) {
        if (t < pause_at_s) return c.mass_kg(t);
        if (t < pause_at_s + pause_s) return 0.5;
        return c.mass_kg(t - pause_s);
      },
      3.3);
  const DischargeAnalysis a = analyse_discharge(s.time_s, s.mass_kg, c.fill_kg);
  EXPECT_EQ(a.status, "complete");
  EXPECT_EQ(a.pauses, 1);
  EXPECT_NEAR(a.discharge_time_s, kT98DischargedS + pause_s, 1e-4);
}

TEST(Discharge, InvalidInputsNameTheArgument) {
  const std::vector<double> t{0.0, 0.1, 0.2}, m{0.0, 0.1, 0.2};
  expect_invalid_argument([&] { analyse_discharge({0.0, 0.2, 0.1}, m, 1.0); }, "time_s");
  expect_invalid_argument([&] { analyse_discharge({0.0, 0.1, 0.1}, m, 1.0); }, "time_s");
  expect_invalid_argument([&] { analyse_discharge({0.0}, {0.0}, 1.0); }, "time_s");
  expect_invalid_argument([&] { analyse_discharge(t, {0.0, -0.1, 0.2}, 1.0); }, "mass_kg");
  expect_invalid_argument([&] { analyse_discharge(t, {0.0, NAN, 0.2}, 1.0); }, "mass_kg");
  expect_invalid_argument([&] { analyse_discharge(t, {0.0, 0.1}, 1.0); }, "mass_kg");
  expect_invalid_argument([&] { analyse_discharge(t, m, 0.0); }, "total_mass_kg");
  expect_invalid_argument([&] { analyse_discharge(t, m, 0.15); }, "total_mass_kg");
  DischargeOptions o;
  o.end_fraction = 1.5;
  expect_invalid_argument([&] { analyse_discharge(t, m, 1.0, o); }, "options.end_fraction");
  o = {};
  o.steady_low_fraction = 0.9;
  expect_invalid_argument([&] { analyse_discharge(t, m, 1.0, o); }, "options.steady_low_fraction");
}

TEST(Discharge, JsonHasStableNames) {
  const Curve c;
  const Series s = sample_curve([&](double t) { return c.mass_kg(t); }, 3.0);
  const nlohmann::json j = to_json(analyse_discharge(s.time_s, s.mass_kg, c.fill_kg));
  for (const char* key : {"discharge_time_s", "t90_s", "t95_s", "mass_flow_rate_kg_s",
                          "mass_flow_rate_std_error_kg_s", "discharged_fraction", "status",
                          "clogged", "criterion", "flow_stopped_s"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["status"], "complete");
  EXPECT_NE(j["criterion"].get<std::string>().find("98 %"), std::string::npos);
  const nlohmann::json series = series_to_json({0.0, 0.1}, {0.0, NAN});
  EXPECT_EQ(series["time_s"].size(), 2u);
  EXPECT_TRUE(series["mass_kg"][1].is_null());
}

// --- DischargeRecorder on a real Simulation ---

double sphere_mass_kg(double radius_m) {
  return 2650.0 * 4.0 / 3.0 * std::numbers::pi * radius_m * radius_m * radius_m;
}

struct FallScene {
  std::unique_ptr<Simulation> sim;
  int material = 0;
};

FallScene make_fall_scene() {
  SimulationOptions o;
  o.domain.lower_m = {-0.01, -0.01, -0.01};
  o.domain.upper_m = {0.01, 0.01, 0.01};
  Material sand;
  sand.name = "sand";
  sand.density_kg_m3 = 2650.0;
  sand.youngs_modulus_pa = 1e7;
  sand.poisson_ratio = 0.3;
  InteractionParameters p;
  p.restitution = 0.5;
  p.sliding_friction = 0.3;
  FallScene s{std::make_unique<Simulation>(o), 0};
  s.material = s.sim->add_material(sand);
  s.sim->set_interaction(s.material, s.material, p);
  // Far apart: no contacts. Three below the plane z = 0, one 0.2 mm above it
  // (below after sqrt(2 * 0.2 mm / g) = 6.4 ms of free fall), one well above.
  s.sim->add_particle({-0.005, 0, -0.003}, 0.5e-3, s.material);
  s.sim->add_particle({0, 0, -0.003}, 1.0e-3, s.material);
  s.sim->add_particle({0.005, 0, -0.005}, 0.5e-3, s.material);
  s.sim->add_particle({-0.005, 0.005, 0.0002}, 0.5e-3, s.material);
  s.sim->add_particle({0.005, 0.005, 0.005}, 0.5e-3, s.material);
  return s;
}

TEST(DischargeRecorder, CountsMassBelowThePlane) {
  FallScene s = make_fall_scene();
  const double small_kg = sphere_mass_kg(0.5e-3), large_kg = sphere_mass_kg(1.0e-3);
  DischargeRecorder latched(0.0, 0.0, 0.005);
  DischargeRecorder unlatched(0.0, 0.0, 0.005, false);
  DischargeRecorder left_half([](const Particles& p, std::size_t i) { return p.position_m[i].x < 0; },
                              0.0, 0.005);
  latched.reserve_for(0.02);
  for (DischargeRecorder* r : {&latched, &unlatched, &left_half}) r->sample(*s.sim);
  while (s.sim->time_s() < 0.02) {
    s.sim->step();
    for (DischargeRecorder* r : {&latched, &unlatched, &left_half}) {
      if (r->due(s.sim->time_s())) r->sample(*s.sim);
    }
  }
  const auto& t = latched.time_s();
  const auto& m = latched.mass_kg();
  ASSERT_GE(t.size(), 4u);
  const double dt = s.sim->time_step_s();
  for (std::size_t i = 0; i < t.size(); ++i) {
    // On the grid k * 0.005 s, at most one step late.
    EXPECT_GE(t[i], i * 0.005 - 1e-12);
    EXPECT_LE(t[i], i * 0.005 + dt + 1e-12);
  }
  EXPECT_NEAR(latched.fill_mass_kg(), 4 * small_kg + large_kg, 1e-15);
  EXPECT_NEAR(m[0], 2 * small_kg + large_kg, 1e-15);
  EXPECT_NEAR(m[1], 2 * small_kg + large_kg, 1e-15);  // ~5 ms: still above
  EXPECT_NEAR(m.back(), 3 * small_kg + large_kg, 1e-15);
  EXPECT_NEAR(left_half.mass_kg().back(), 2 * small_kg, 1e-15);

  // A discharged grain thrown back over the plane has still passed the orifice.
  s.sim->mutable_particles().position_m[0].z = 0.008;
  s.sim->run_until(0.025);
  latched.sample(*s.sim);
  unlatched.sample(*s.sim);
  EXPECT_NEAR(latched.mass_kg().back(), 3 * small_kg + large_kg, 1e-15);
  EXPECT_NEAR(unlatched.mass_kg().back(), 2 * small_kg + large_kg, 1e-15);

  // Sampling twice at one time replaces the sample rather than duplicating the time.
  const std::size_t samples = latched.time_s().size();
  latched.sample(*s.sim);
  EXPECT_EQ(latched.time_s().size(), samples);

  DischargeRecorder not_yet_open(0.0, 1.0, 0.005);
  EXPECT_THROW(not_yet_open.sample(*s.sim), std::logic_error);
  expect_invalid_argument([] { DischargeRecorder(0.0, 0.0, 0.0); }, "sample_interval_s");
}

// --- Beverloo ---

constexpr double kC = 0.58, kK = 1.5;

BeverlooSetup setup(OrificeShape shape) {
  BeverlooSetup b;
  b.shape = shape;
  b.bulk_density_kg_m3 = 0.6 * 2650.0;
  b.gravity_m_s2 = 9.81;
  b.particle_diameter_m = 1e-3;
  b.slot_length_m = 0.02;  // a periodic slice 20 d deep
  return b;
}

TEST(Beverloo, ForwardLawMatchesHandValues) {
  // 0.58 * 1590 * sqrt(9.81) * (10 mm - 1.5 mm)^2.5, and * 0.02 m * (8.5 mm)^1.5.
  EXPECT_NEAR(beverloo_flow_rate_kg_s(setup(OrificeShape::circle), 0.010, kC, kK),
              0.01924008276279177, 1e-12);
  EXPECT_NEAR(beverloo_flow_rate_kg_s(setup(OrificeShape::slot), 0.010, kC, kK),
              0.04527078297127476, 1e-12);
}

void check_recovery(OrificeShape shape, std::uint64_t seed) {
  const BeverlooSetup b = setup(shape);
  const std::vector<double> d0{0.005, 0.006, 0.007, 0.008, 0.010, 0.012, 0.015};
  Random rng(seed);
  std::vector<double> w, sigma;
  for (double d : d0) {
    const double exact = beverloo_flow_rate_kg_s(b, d, kC, kK);
    w.push_back(exact * (1.0 + 0.01 * rng.normal()));
    sigma.push_back(0.01 * exact);
  }
  for (bool weighted : {false, true}) {
    SCOPED_TRACE(weighted ? "weighted" : "unweighted");
    const BeverlooFit f = fit_beverloo(b, d0, w, weighted ? sigma : std::vector<double>{});
    EXPECT_NEAR(f.c, kC, 0.03);
    EXPECT_NEAR(f.k, kK, 0.2);
    EXPECT_GT(f.c_std_error, 0.0);
    EXPECT_LT(f.c_std_error, 0.05);
    EXPECT_GT(f.k_std_error, 0.0);
    EXPECT_LT(f.k_std_error, 0.3);
    EXPECT_EQ(f.weighted, weighted);
    ASSERT_EQ(f.residuals_kg_s.size(), d0.size());
    for (std::size_t i = 0; i < d0.size(); ++i) EXPECT_LT(std::abs(f.residuals_kg_s[i]), 0.05 * w[i]);
    if (weighted) {
      EXPECT_TRUE(std::isfinite(f.reduced_chi_squared));
    }
  }
}

TEST(Beverloo, RecoversCircularLawFromNoisyData) { check_recovery(OrificeShape::circle, 3); }
TEST(Beverloo, RecoversSlotLawFromNoisyData) { check_recovery(OrificeShape::slot, 5); }

TEST(Beverloo, TwoPointsFitExactlyWithoutErrors) {
  for (OrificeShape shape : {OrificeShape::circle, OrificeShape::slot}) {
    const BeverlooSetup b = setup(shape);
    const std::vector<double> d0{0.006, 0.012};
    const std::vector<double> w{beverloo_flow_rate_kg_s(b, d0[0], kC, kK),
                                beverloo_flow_rate_kg_s(b, d0[1], kC, kK)};
    const BeverlooFit f = fit_beverloo(b, d0, w);
    EXPECT_NEAR(f.c, kC, 1e-10);
    EXPECT_NEAR(f.k, kK, 1e-8);
    EXPECT_TRUE(std::isnan(f.c_std_error));
    EXPECT_TRUE(std::isnan(f.k_std_error));
    for (std::size_t i = 0; i < 2; ++i) EXPECT_NEAR(f.residuals_kg_s[i], 0.0, 1e-12 * w[i] + 1e-16);
    // The line in the documented variables: (W / L_or_1)^(1/p) = slope D0 + intercept.
    const double p = shape == OrificeShape::circle ? 2.5 : 1.5;
    const double length = shape == OrificeShape::circle ? 1.0 : b.slot_length_m;
    EXPECT_NEAR(std::pow(w[1] / length, 1.0 / p), f.slope * d0[1] + f.intercept, 1e-12);
    EXPECT_NEAR(-f.intercept / (f.slope * b.particle_diameter_m), kK, 1e-8);
  }
}

TEST(Beverloo, InvalidInputsNameTheArgument) {
  const BeverlooSetup b = setup(OrificeShape::circle);
  expect_invalid_argument([&] { beverloo_flow_rate_kg_s(b, 0.0015, kC, kK); }, "orifice_m");
  expect_invalid_argument([&] { beverloo_flow_rate_kg_s(b, 0.001, kC, kK); }, "orifice_m");
  expect_invalid_argument([&] { beverloo_flow_rate_kg_s(b, 0.01, 0.0, kK); }, "c");
  BeverlooSetup bad = b;
  bad.bulk_density_kg_m3 = 0.0;
  expect_invalid_argument([&] { beverloo_flow_rate_kg_s(bad, 0.01, kC, kK); },
                          "setup.bulk_density_kg_m3");
  bad = setup(OrificeShape::slot);
  bad.slot_length_m = 0.0;
  expect_invalid_argument([&] { beverloo_flow_rate_kg_s(bad, 0.01, kC, kK); },
                          "setup.slot_length_m");
  expect_invalid_argument([&] { fit_beverloo(b, {0.01}, {0.02}); }, "orifice_m");
  expect_invalid_argument([&] { fit_beverloo(b, {0.01, 0.01}, {0.02, 0.021}); }, "orifice_m");
  expect_invalid_argument([&] { fit_beverloo(b, {0.01, 0.02}, {0.02, -0.1}); }, "flow_rate_kg_s");
  expect_invalid_argument([&] { fit_beverloo(b, {0.01, 0.02}, {0.02, 0.1}, {0.001}); },
                          "flow_rate_std_error_kg_s");
  expect_invalid_argument([&] { fit_beverloo(b, {0.01, 0.02}, {0.02}); }, "flow_rate_kg_s");
}

}  // namespace
}  // namespace demcal::dem
