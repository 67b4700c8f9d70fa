// The concealed studies' effects run in LAMMPS from demcal's decks (issue 19),
// one short run each, checking that the mapped effect acts as demcal's does:
// a polydisperse lattice fill has the asked sizes; air drag brings a falling
// parcel to demcal's terminal speed; JKR adhesion holds a grain on the floor
// at demcal's JKR overlap, and steepens a poured heap. Labelled `engine`;
// skipped, with the reason, when LAMMPS (lmp) is not installed.
#include "dem/air_drag.hpp"
#include "dem/apparatus/sandglass.hpp"
#include "dem/contact/jkr_adhesion.hpp"
#include "engines/dump_reader.hpp"
#include "engines/engine_measure.hpp"
#include "engines/engine_run.hpp"
#include "engines/lammps_deck.hpp"
#include "tests/support/engine_fixtures.hpp"
#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <numbers>
#include <string>

namespace demcal::engines {
namespace {

std::string lammps_command() {
  const char* v = std::getenv("DEMCAL_LAMMPS");
  return v != nullptr && *v != '\0' ? std::string(v) : std::string("lmp");
}

std::string first_word(const std::string& s) { return s.substr(0, s.find(' ')); }

#define SKIP_WITHOUT_LAMMPS()                                                \
  if (!executable_available(first_word(lammps_command())))                   \
  GTEST_SKIP() << "LAMMPS not installed: \"" << first_word(lammps_command()) \
               << "\" is not on PATH (apt-get install lammps, or set DEMCAL_LAMMPS)"

EngineRunResult run(const Deck& deck, const std::string& name) {
  EngineLaunch launch;
  launch.command = lammps_command();
  return run_engine(deck, launch, testing::fresh_dir("engine", name));
}

// The deck up to the end of its fill (the first phase loop), then the dump:
// what a run looks like when it starts.
Deck cut_after_fill(Deck deck) {
  const auto at = deck.script.find("\n# --- fill:");
  deck.script = deck.script.substr(0, at) + "\nwrite_dump      all custom " + deck.final_dump_name +
                " id type x y z radius vx vy vz modify sort id\n";
  return deck;
}

// A hand-made layout: `count` grains on a sparse lattice high in a tall open
// box, nothing else; the fill phase runs max_settle_s (they never come to rest).
ApparatusLayout drop_layout(const dem::GranularMaterial& m, const dem::ModelReduction& r,
                            double diameter_m, double box_height_m, double seconds) {
  ApparatusLayout l;
  l.apparatus = "drop";
  l.variant = "test";
  const double a = 4.0 * diameter_m;
  l.box = {{-2.0 * a, -2.0 * a, -box_height_m}, {2.0 * a, 2.0 * a, 2.0 * a}};
  LatticeFill f;
  f.spacing_m = a;
  f.region = {{-a, -a, 0.0}, {a, a, a}};
  f.sites_per_layer = 4;
  f.layers = 1;
  f.count = 4;
  l.lattice = f;
  l.particles = 4;
  l.size_classes = {{diameter_m, 1.0}};
  l.density_kg_m3 = m.particle.density_kg_m3;
  l.time_step_s = 5e-5;
  l.seed = 7;
  l.protocol.check_interval_s = 0.05;
  l.protocol.max_settle_s = seconds;
  l.protocol.rest_speed_m_s = 1e-9;
  l.material = m;
  l.reduction = r;
  l.measurement = {{"kind", "none"}};
  return l;
}

TEST(EngineLammpsEffects, PolydisperseFillHasTheAskedSizes) {
  SKIP_WITHOUT_LAMMPS();
  // The concealed size-spread truth's shape: uniform, relative half-width 0.55.
  dem::SandglassOptions s;
  s.bottom = "flat";
  s.reduction.slice = true;
  s.upper_diameter_m = 0.03;
  s.orifice_diameter_m = 0.008;
  s.upper_height_m = 0.14;
  s.lower_diameter_m = 0.06;
  s.drop_height_m = 0.03;
  s.fill_mass_kg = 0.02;
  s.fill_lattice_spacing_diameters = 1.1;
  auto m = testing::peer_material();
  const double mean = 1e-3, half = 0.55;
  m.sizes = dem::make_uniform(mean * (1.0 - half), mean * (1.0 + half));
  const DeckResult deck = write_lammps_deck(s, m, dem::RunProtocol{});
  ASSERT_TRUE(deck.ok()) << deck.refusal;
  const Deck fill = cut_after_fill(*deck.deck);
  const EngineRunResult r = run(fill, "lammps-poly-fill");
  const ParticleDump dump = read_custom_dump(r.directory / fill.final_dump_name);
  // delete_atoms porosity thins the top layer at random, not to an exact count
  // (as in every lattice deck): within a few grains of the asked number.
  const auto asked = deck.deck->record["layout"]["particles"].get<std::size_t>();
  ASSERT_NEAR(static_cast<double>(dump.size()), static_cast<double>(asked), 0.01 * asked);
  double sum = 0.0, sum2 = 0.0, lo = 1.0, hi = 0.0;
  for (double radius : dump.radius_m) {
    const double d = 2.0 * radius;
    sum += d;
    sum2 += d * d;
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  const double n = static_cast<double>(dump.size());
  const double mean_d = sum / n;
  const double sd = std::sqrt(sum2 / n - mean_d * mean_d);
  // Uniform on mean (1 +- h): sd = h mean / sqrt(3); 8 equal-number classes
  // lose the within-class spread, (h/8)^2/3 of h^2/3: 0.8 % of the sd.
  const double sd_asked = half * mean / std::sqrt(3.0);
  std::cout << "LAMMPS polydisperse fill: " << dump.size() << " grains, mean diameter "
            << mean_d * 1e3 << " mm (asked " << mean * 1e3 << "), sd " << sd * 1e3 << " mm (asked "
            << sd_asked * 1e3 << ", relative half-width " << std::sqrt(3.0) * sd / mean_d << " vs "
            << half << "), range " << lo * 1e3 << " - " << hi * 1e3 << " mm, wall time "
            << r.wall_time_s << " s\n";
  EXPECT_NEAR(mean_d, mean, 0.01 * mean);
  EXPECT_NEAR(sd, sd_asked, 0.03 * sd_asked);
  EXPECT_GE(lo, mean * (1.0 - half));
  EXPECT_LE(hi, mean * (1.0 + half));
  EXPECT_GT(hi - lo, 0.8 * 2.0 * half * mean);  // the classes span the range
  // Every type is back to 1 (the deck's walls and measurement see one material).
  for (int t : dump.type) ASSERT_EQ(t, 1);
}

TEST(EngineLammpsEffects, AirDragGivesDemcalsTerminalSpeed) {
  SKIP_WITHOUT_LAMMPS();
  // The concealed base study's parcel: 0.2 mm quartz grains coarse-grained x14.
  auto m = testing::peer_material();
  const double f = 14.0, d = 0.2e-3 * f;
  m.sizes = dem::make_monodisperse(d);
  m.air_drag = dem::AirProperties{};
  dem::ModelReduction red;
  red.coarse_graining_factor = f;
  const ApparatusLayout l = drop_layout(m, red, d, 2.5, 1.2);
  const DeckResult deck = write_lammps_deck(l);
  ASSERT_TRUE(deck.ok()) << deck.refusal;
  const EngineRunResult r = run(*deck.deck, "lammps-air-drag");
  const ParticleDump dump = read_custom_dump(r.directory / deck.deck->final_dump_name);
  ASSERT_EQ(dump.size(), 4u);
  // demcal's terminal speed: weight = AirDrag's force on the parcel (bisection).
  const double mass = m.particle.density_kg_m3 * std::numbers::pi / 6.0 * d * d * d;
  dem::Particles p;
  p.add({0.0, 0.0, 0.0}, 0.5 * d, m.particle.density_kg_m3, 0, 1);
  const dem::AirDrag drag(*m.air_drag, f);
  auto drag_at = [&](double v) {
    p.velocity_m_s[0] = {0.0, 0.0, -v};
    std::vector<dem::Vec3> force(1), torque(1);
    drag.add(p, 0, 1, force, torque);
    return force[0].z;
  };
  double lo = 0.0, hi = 100.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (drag_at(mid) < mass * 9.81 ? lo : hi) = mid;
  }
  const double terminal = 0.5 * (lo + hi);
  double speed = 0.0;
  for (const auto& v : dump.velocity_m_s) speed += -v.z / 4.0;
  std::cout << "LAMMPS air drag: parcel " << d * 1e3 << " mm (f = " << f << "), fall speed after "
            << l.protocol.max_settle_s << " s " << speed << " m/s, demcal's terminal speed "
            << terminal << " m/s (" << 100.0 * (speed / terminal - 1.0)
            << " %), free fall would be " << 9.81 * l.protocol.max_settle_s << " m/s; wall time "
            << r.wall_time_s << " s\n";
  // 1.2 s is eight of the drag's time constants v_t / g: the speed is terminal.
  EXPECT_NEAR(speed, terminal, 0.01 * terminal);
}

TEST(EngineLammpsEffects, JkrHoldsTwoGrainsAtDemcalsEquilibriumOverlap) {
  SKIP_WITHOUT_LAMMPS();
  // Two grains placed just touching pull each other in and come to rest where
  // the JKR force vanishes (they fall together: gravity does not load the
  // contact). demcal's JKR curve gives that overlap from E*, gamma and R*.
  auto m = testing::peer_material();
  const double d = 1e-3, gamma = 0.05;
  m.contact.adhesion = "jkr";
  m.particle_particle.surface_energy_j_m2 = gamma;
  ApparatusLayout l = drop_layout(m, {}, d, 0.01, 0.02);
  const double a = d * (1.0 - 1e-4);  // 100 nm initial overlap
  l.box = {{-4.0 * d, -2.0 * d, -0.01}, {4.0 * d, 2.0 * d, 2.0 * d}};
  l.lattice->spacing_m = a;
  l.lattice->region = {{-a, 0.0, 0.0}, {a, a, a}};
  l.lattice->sites_per_layer = 2;
  l.lattice->count = 2;
  l.particles = 2;
  l.time_step_s = 2e-6;
  l.protocol.check_interval_s = 0.005;
  const DeckResult deck = write_lammps_deck(l);
  ASSERT_TRUE(deck.ok()) << deck.refusal;
  const EngineRunResult r = run(*deck.deck, "lammps-jkr-pair");
  const ParticleDump dump = read_custom_dump(r.directory / deck.deck->final_dump_name);
  ASSERT_EQ(dump.size(), 2u);
  const double e_star = 1e7 / (2.0 * (1.0 - 0.3 * 0.3));
  const double reff = 0.25 * d;
  // demcal's zero-force overlap (F_JKR rises through 0 on the stable branch).
  double lo = 0.0, hi = 0.1 * reff;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (dem::jkr::contact(e_star, gamma, reff, mid).force_n < 0.0 ? lo : hi) = mid;
  }
  const double expected = 0.5 * (lo + hi);
  const double overlap = d - norm(dump.position_m[1] - dump.position_m[0]);
  const double relative_speed = norm(dump.velocity_m_s[1] - dump.velocity_m_s[0]);
  std::cout << "LAMMPS JKR pair at rest: overlap " << overlap * 1e9
            << " nm, demcal's JKR zero-force overlap " << expected * 1e9 << " nm ("
            << 100.0 * (overlap / expected - 1.0) << " %); relative speed " << relative_speed
            << " m/s; wall time " << r.wall_time_s << " s\n";
  EXPECT_LT(relative_speed, 1e-4);
  EXPECT_NEAR(overlap, expected, 0.01 * expected);
}

TEST(EngineLammpsEffects, CohesionSteepensAPouredHeap) {
  SKIP_WITHOUT_LAMMPS();
  // The rectangular container, periodic across a 4 d slab, poured dry and with
  // JKR adhesion between the grains at a Bond number of about 10 (F_po = 3 pi
  // gamma R*, R* = d/4); the floor and side walls stay dry (parameter_mapping.hpp).
  dem::RectangularContainerOptions o;
  o.width_m = 0.06;
  o.height_m = 0.04;
  o.thickness_diameters = 4.0;
  o.boundary = "periodic";
  o.fill_mass_kg = 0.0015;
  dem::RunProtocol p;
  p.rest_speed_m_s = 5e-3;
  p.max_flow_s = 3.0;
  auto aor = [&](double gamma, const std::string& name) {
    auto m = testing::peer_material();
    if (gamma > 0.0) {
      m.contact.adhesion = "jkr";
      m.particle_particle.surface_energy_j_m2 = gamma;
    }
    const DeckResult deck = write_lammps_deck(o, m, p);
    EXPECT_TRUE(deck.ok()) << deck.refusal;
    const EngineRunResult r = run(*deck.deck, name);
    const dem::ApparatusResult res = measure_engine_run(*deck.deck, r.directory);
    const double a = res.observables["angle_of_repose_deg"].is_null()
                         ? std::nan("")
                         : res.observables["angle_of_repose_deg"].get<double>();
    std::cout << "LAMMPS poured heap, gamma " << gamma << " J/m2: AoR " << a << " deg, "
              << res.details["particles"] << " particles, wall time " << r.wall_time_s << " s\n";
    return a;
  };
  const double weight = 2650.0 * std::numbers::pi / 6.0 * 1e-9 * 9.81;
  const double gamma = 10.0 * weight / (3.0 * std::numbers::pi * 0.25e-3);
  const double dry = aor(0.0, "lammps-heap-dry");
  const double wet = aor(gamma, "lammps-heap-jkr");
  ASSERT_FALSE(std::isnan(dry));
  ASSERT_FALSE(std::isnan(wet));
  EXPECT_GT(wet, dry + 5.0);
}

TEST(EngineLammpsEffects, SandglassSliceHopperEmptiesTheChamber) {
  SKIP_WITHOUT_LAMMPS();
  // tests/engine/test_engine_lammps.cpp's slice, with the base study's hopper
  // (30 deg from the vertical) instead of the flat bottom: the grains slide
  // down the plates to the slot; no dead zones stay beside it.
  const dem::SandglassOptions s = testing::small_hopper_slice();
  dem::RunProtocol protocol;
  protocol.max_flow_s = 2.0;
  const DeckResult deck = write_lammps_deck(s, testing::peer_material(), protocol);
  ASSERT_TRUE(deck.ok()) << deck.refusal;
  const EngineRunResult r = run(*deck.deck, "lammps-hopper");
  const dem::ApparatusResult res = measure_engine_run(*deck.deck, r.directory);
  const double fraction = res.details["discharge"]["discharged_fraction"].get<double>();
  std::cout << "LAMMPS sandglass slice with hopper: " << res.details["particles"]
            << " particles, discharge time " << res.observables["discharge_time_s"]
            << " s, flow rate " << res.observables["mass_flow_rate_kg_s"] << " kg/s, "
            << 100.0 * fraction << " % discharged ("
            << res.details["discharge"]["status"].get<std::string>() << "), wall time "
            << r.wall_time_s << " s\n";
  EXPECT_GT(fraction, 0.98);
  ASSERT_FALSE(res.observables["mass_flow_rate_kg_s"].is_null());
  // The bulk density of the settled fill, by dem::Sandglass's rule, against
  // demcal's own run of the same slice (the same lattice fill, settled).
  ASSERT_FALSE(res.observables["bulk_density_kg_m3"].is_null()) << res.observables.dump();
  const double lammps_rho = res.observables["bulk_density_kg_m3"].get<double>();
  dem::Sandglass own(s, testing::peer_material(), protocol);
  const dem::ApparatusResult mine = own.run({});
  const double demcal_rho = mine.observables["bulk_density_kg_m3"].get<double>();
  std::cout << "bulk density of the settled fill: LAMMPS " << lammps_rho << " kg/m3, demcal "
            << demcal_rho << " kg/m3 (" << 100.0 * (lammps_rho / demcal_rho - 1.0)
            << " %); discharge time demcal " << mine.observables["discharge_time_s"] << " s\n";
  EXPECT_NEAR(lammps_rho, demcal_rho, 0.05 * demcal_rho);
  // Measured: 0.196 s LAMMPS, 0.202 s demcal (one seed each).
  const double demcal_t = mine.observables["discharge_time_s"].get<double>();
  EXPECT_NEAR(res.observables["discharge_time_s"].get<double>(), demcal_t, 0.2 * demcal_t);
}

}  // namespace
}  // namespace demcal::engines
