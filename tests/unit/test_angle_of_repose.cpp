// Angle of repose from synthetic piles of known slope: a ridge in a slab and a
// cone, built from spheres on a jittered lattice under an ideal surface, with a
// rough top layer. The measurement must return the slope it was built with.

#include "dem/measure/angle_of_repose.hpp"
#include "dem/measure/robust_line_fit.hpp"
#include "dem/random.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

namespace demcal::dem {
namespace {

constexpr double kD = 1e-3;  // particle diameter
constexpr double kR = 0.5 * kD;
const std::vector<double> kAngles = {20.0, 25.0, 30.0, 35.0, 40.0, 45.0};
constexpr int kSeeds = 5;

double tan_deg(double deg) { return std::tan(deg * std::numbers::pi / 180.0); }

struct Cloud {
  std::vector<Vec3> position_m;
  std::vector<double> radius_m;
  void add(const Vec3& p) {
    position_m.push_back(p);
    radius_m.push_back(kR);
  }
};

// One lattice column whose top grain tops out at top_m (at least d: a grain at
// the toe rests on the floor), filled down to the floor with slightly jittered
// grains. Roughness lives in top_m: the top grain is raised or lowered freely,
// so the surface is rough by whatever the caller drew, not by lattice steps.
void add_column(Cloud& c, Random& rng, double x, double y, double top_m) {
  double z = std::max(top_m, kD) - kR;
  c.add({x, y, z});
  for (z -= kD; z >= kR; z -= kD)
    c.add({x + 0.05 * kD * rng.uniform(-1, 1), y + 0.05 * kD * rng.uniform(-1, 1),
           z + 0.05 * kD * rng.uniform(-1, 1)});
}

// A ridge z = H - tan(theta)|x| (left and right angles may differ) in a slab
// `thickness` diameters thick along y; column tops uniform within
// +-roughness/2 diameters of the ideal surface.
Cloud ridge(double left_deg, double right_deg, double height_m, double roughness_d,
            std::uint64_t seed, double thickness_d = 5.0) {
  Random rng(seed);
  Cloud c;
  const double tl = tan_deg(left_deg), tr = tan_deg(right_deg);
  const double reach = height_m + roughness_d * kD;
  const int il = static_cast<int>(std::ceil(reach / tl / kD)) + 1;
  const int ir = static_cast<int>(std::ceil(reach / tr / kD)) + 1;
  for (int i = -il; i <= ir; ++i)
    for (int j = 0; j < static_cast<int>(thickness_d); ++j) {
      const double x = (i + 0.1 * rng.uniform(-1, 1)) * kD;
      const double y = (j + 0.5 + 0.1 * rng.uniform(-1, 1)) * kD;
      const double surface = height_m - (x < 0.0 ? -tl * x : tr * x);
      const double top = surface + roughness_d * kD * rng.uniform(-0.5, 0.5);
      if (top > 0.0) add_column(c, rng, x, y, top);
    }
  return c;
}

// A cone z = H - tan(theta) * rho around (x0, y0), same construction.
Cloud cone(double theta_deg, double height_m, double roughness_d, std::uint64_t seed,
           double x0 = 0.0, double y0 = 0.0) {
  Random rng(seed);
  Cloud c;
  const double t = tan_deg(theta_deg);
  const int n = static_cast<int>(std::ceil((height_m + roughness_d * kD) / t / kD)) + 1;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j) {
      const double x = (i + 0.1 * rng.uniform(-1, 1)) * kD;
      const double y = (j + 0.1 * rng.uniform(-1, 1)) * kD;
      const double surface = height_m - t * std::hypot(x, y);
      const double top = surface + roughness_d * kD * rng.uniform(-0.5, 0.5);
      if (top > 0.0) add_column(c, rng, x + x0, y + y0, top);
    }
  return c;
}

// A flat layer `layer_d` diameters thick over |x| <= half_length_d.
Cloud flat_slab_layer(double layer_d, double half_length_d, std::uint64_t seed) {
  Random rng(seed);
  Cloud c;
  const int n = static_cast<int>(half_length_d);
  for (int i = -n; i <= n; ++i)
    for (int j = 0; j < 5; ++j)
      add_column(c, rng, (i + 0.1 * rng.uniform(-1, 1)) * kD, (j + 0.5) * kD,
                 (layer_d + rng.uniform(-0.5, 0.5)) * kD);
  return c;
}

constexpr double kSliceHeight = 40 * kD;
constexpr double kConeHeight = 30 * kD;

std::string thrown_message(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

// ---------------------------------------------------------------- line fit

TEST(RobustLineFit, RecoversAnExactLine) {
  const std::vector<double> x = {0, 1, 2, 3, 4, 5};
  std::vector<double> y;
  for (double v : x) y.push_back(2.0 - 0.7 * v);
  const LineFit f = fit_line_bisquare(x, y);
  EXPECT_NEAR(f.slope, -0.7, 1e-12);
  EXPECT_NEAR(f.intercept, 2.0, 1e-12);
  EXPECT_TRUE(f.converged);
}

TEST(RobustLineFit, RejectsOutliersThatTiltLeastSquares) {
  Random rng(7);
  std::vector<double> x, y, w;
  for (int i = 0; i < 30; ++i) {
    x.push_back(i);
    y.push_back(1.0 + 0.5 * i + 0.05 * rng.normal());
  }
  y[25] += 8.0;  // two grains perched far above the line near one end
  y[27] += 6.0;
  w.assign(x.size(), 1.0);
  const LineFit ols = fit_line_weighted(x, y, w);
  const LineFit robust = fit_line_bisquare(x, y);
  EXPECT_GT(std::abs(ols.slope - 0.5), 0.05);
  EXPECT_NEAR(robust.slope, 0.5, 0.01);
  EXPECT_EQ(robust.weights[25], 0.0);
  EXPECT_EQ(robust.weights[27], 0.0);
  EXPECT_EQ(robust.rejected, 2u);
}

TEST(RobustLineFit, StandardErrorMatchesTheScatterOfRepeatedFits) {
  // On clean normal noise the reported SE must describe the real spread of
  // the slope, or the AoR uncertainty built on it would be fiction.
  Random rng(11);
  std::vector<double> slopes;
  double mean_se = 0.0;
  constexpr int kTrials = 400;
  for (int t = 0; t < kTrials; ++t) {
    std::vector<double> x, y;
    for (int i = 0; i < 20; ++i) {
      x.push_back(i);
      y.push_back(0.3 * i + 0.2 * rng.normal());
    }
    const LineFit f = fit_line_bisquare(x, y);
    slopes.push_back(f.slope);
    mean_se += f.slope_std_error / kTrials;
  }
  double m = 0.0, v = 0.0;
  for (double s : slopes) m += s / kTrials;
  for (double s : slopes) v += (s - m) * (s - m) / (kTrials - 1);
  EXPECT_NEAR(mean_se, std::sqrt(v), 0.15 * std::sqrt(v));
}

TEST(RobustLineFit, RefusesTooFewPoints) {
  const std::vector<double> x = {0, 1}, y = {0, 1};
  EXPECT_THROW(fit_line_bisquare(x, y), std::invalid_argument);
}

// ------------------------------------------------------------------- slice

TEST(SliceAngleOfRepose, RecoversSlopes20To45DegWithin05Deg) {
  double worst_mean = 0.0, worst_side = 0.0;
  for (double theta : kAngles)
    for (int seed = 1; seed <= kSeeds; ++seed) {
      const Cloud c = ridge(theta, theta, kSliceHeight, 1.0, 100 + seed);
      const AngleOfRepose a = measure_slice_angle_of_repose(c.position_m, c.radius_m);
      EXPECT_NEAR(a.mean_deg, theta, 0.5) << "theta " << theta << " seed " << seed;
      ASSERT_EQ(a.sides.size(), 2u);
      EXPECT_EQ(a.valid_sides, 2);
      worst_mean = std::max(worst_mean, std::abs(a.mean_deg - theta));
      for (const AoRSide& s : a.sides) {
        EXPECT_NEAR(s.angle_deg, theta, 0.5) << s.name << " theta " << theta << " seed " << seed;
        worst_side = std::max(worst_side, std::abs(s.angle_deg - theta));
        EXPECT_GE(s.points, 4);
        EXPECT_GT(s.std_error_deg, 0.0);
      }
      EXPECT_NEAR(a.crest_height_m, kSliceHeight, 0.75 * kD);
      EXPECT_NEAR(a.crest_position_m, 0.0, 1.5 * kD);
      EXPECT_NEAR(a.base_half_width_m, (kSliceHeight - kD) / tan_deg(theta), 2.0 * kD);
      EXPECT_GT(a.uncertainty_deg, 0.0);
    }
  std::printf("[ slice   ] worst |error|: mean %.3f deg, single side %.3f deg\n", worst_mean,
              worst_side);
}

TEST(SliceAngleOfRepose, AsymmetricRidgeMeasuresEachSide) {
  double worst = 0.0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const Cloud c = ridge(30.0, 40.0, kSliceHeight, 1.0, 200 + seed);
    const AngleOfRepose a = measure_slice_angle_of_repose(c.position_m, c.radius_m);
    ASSERT_EQ(a.sides.size(), 2u);
    EXPECT_EQ(a.sides[0].name, "left");
    EXPECT_EQ(a.sides[1].name, "right");
    EXPECT_NEAR(a.sides[0].angle_deg, 30.0, 0.5);
    EXPECT_NEAR(a.sides[1].angle_deg, 40.0, 0.5);
    EXPECT_GT(a.mean_deg, 30.0);
    EXPECT_LT(a.mean_deg, 40.0);
    EXPECT_NEAR(a.mean_deg, 35.0, 0.5);
    // The sides disagree by 10 deg: the SEM (5 deg) must dominate.
    EXPECT_NEAR(a.sem_deg, 5.0, 0.5);
    EXPECT_GE(a.uncertainty_deg, a.sem_deg);
    worst = std::max(
        {worst, std::abs(a.sides[0].angle_deg - 30.0), std::abs(a.sides[1].angle_deg - 40.0)});
  }
  std::printf("[ slice   ] 30/40 deg ridge, worst side |error| %.3f deg\n", worst);
}

TEST(SliceAngleOfRepose, StrayGrainsInTheFitZoneMoveItLessThan03Deg) {
  double worst = 0.0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    Cloud c = ridge(35.0, 35.0, kSliceHeight, 1.0, 300 + seed);
    const AngleOfRepose clean = measure_slice_angle_of_repose(c.position_m, c.radius_m);
    // Grains 4-6 d above the surface at 30-70 % of the height on both sides,
    // and two buried 5 d below it (those must simply be invisible).
    Random rng(seed);
    const double t = tan_deg(35.0);
    for (const double frac : {0.3, 0.5, 0.7}) {
      for (const double side : {-1.0, 1.0}) {
        const double x = side * (1.0 - frac) * kSliceHeight / t;
        c.add({x, 2.5 * kD, frac * kSliceHeight + rng.uniform(4.0, 6.0) * kD});
      }
    }
    c.add({-0.4 * kSliceHeight / t, 2.5 * kD, 0.6 * kSliceHeight - 5 * kD});
    c.add({0.4 * kSliceHeight / t, 2.5 * kD, 0.6 * kSliceHeight - 5 * kD});
    const AngleOfRepose dirty = measure_slice_angle_of_repose(c.position_m, c.radius_m);
    EXPECT_NEAR(dirty.mean_deg, clean.mean_deg, 0.3) << "seed " << seed;
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_NEAR(dirty.sides[k].angle_deg, clean.sides[k].angle_deg, 0.3) << "seed " << seed;
      worst = std::max(worst, std::abs(dirty.sides[k].angle_deg - clean.sides[k].angle_deg));
      EXPECT_GE(dirty.sides[k].rejected_points, 2) << dirty.sides[k].name;
    }
  }
  std::printf("[ slice   ] stray grains moved a side by at most %.3f deg\n", worst);
}

TEST(SliceAngleOfRepose, FlatLayerThrowsNamingTheSideAndCount) {
  const std::regex named(
      "too flat or too small.*(left|right) side has [0-9]+ bins? between 15 % and 85 % of the "
      "crest height");
  for (const double layer_d : {1.0, 2.0, 3.0, 10.0}) {
    const Cloud c = flat_slab_layer(layer_d, 60.0, 400 + static_cast<int>(layer_d));
    const std::string msg =
        thrown_message([&] { measure_slice_angle_of_repose(c.position_m, c.radius_m); });
    EXPECT_TRUE(std::regex_search(msg, named)) << "layer " << layer_d << " d: " << msg;
  }
}

TEST(SliceAngleOfRepose, TinyHeapThrowsNamingTheSideAndCount) {
  const Cloud c = ridge(30.0, 30.0, 3.0 * kD, 1.0, 500);
  const std::string msg =
      thrown_message([&] { measure_slice_angle_of_repose(c.position_m, c.radius_m); });
  EXPECT_TRUE(std::regex_search(
      msg, std::regex("left side has [0-3] bins? between 15 % and 85 % of the crest height")))
      << msg;
  EXPECT_TRUE(std::regex_search(msg, std::regex("right side has [0-3] bins?"))) << msg;
}

TEST(SliceAngleOfRepose, UncertaintyIsPositiveAndGrowsWithRoughness) {
  std::vector<double> mean_u;
  for (const double roughness_d : {0.25, 1.0, 2.0}) {
    double u = 0.0;
    for (int seed = 1; seed <= kSeeds; ++seed) {
      const Cloud c = ridge(35.0, 35.0, kSliceHeight, roughness_d, 600 + seed);
      const AngleOfRepose a = measure_slice_angle_of_repose(c.position_m, c.radius_m);
      EXPECT_GT(a.uncertainty_deg, 0.0);
      EXPECT_GT(a.fit_error_deg, 0.0);
      u += a.uncertainty_deg / kSeeds;
    }
    mean_u.push_back(u);
  }
  EXPECT_LT(mean_u[0], mean_u[1]);
  EXPECT_LT(mean_u[1], mean_u[2]);
}

TEST(SliceAngleOfRepose, LongAxisYBaseHeightAndSelectionBox) {
  const Cloud c = ridge(33.0, 33.0, kSliceHeight, 1.0, 700);
  const AngleOfRepose ref = measure_slice_angle_of_repose(c.position_m, c.radius_m);

  // The same ridge along y, standing on a floor at z = 0.2 m.
  Cloud moved;
  for (const Vec3& p : c.position_m) moved.add({p.y, p.x, p.z + 0.2});
  SliceAoROptions o;
  o.long_axis = 1;
  o.base_height_m = 0.2;
  const AngleOfRepose a = measure_slice_angle_of_repose(moved.position_m, moved.radius_m, o);
  EXPECT_NEAR(a.mean_deg, ref.mean_deg, 1e-9);
  EXPECT_NEAR(a.crest_height_m, ref.crest_height_m, 1e-9);

  // A tower of grains stuck far away (a hopper's content) would become the
  // crest; a selection box leaves it out.
  Cloud tower = c;
  for (int k = 0; k < 80; ++k) tower.add({0.3, 2.5 * kD, (k + 0.5) * kD});
  bool tower_spoils = false;
  try {
    const AngleOfRepose bad = measure_slice_angle_of_repose(tower.position_m, tower.radius_m);
    tower_spoils = std::abs(bad.crest_height_m - ref.crest_height_m) > kD;
  } catch (const std::runtime_error&) {
    tower_spoils = true;
  }
  EXPECT_TRUE(tower_spoils);
  SliceAoROptions boxed;
  boxed.selection = SelectionBox{{-0.1, -1.0, -1.0}, {0.1, 1.0, 1.0}};
  const AngleOfRepose b = measure_slice_angle_of_repose(tower.position_m, tower.radius_m, boxed);
  EXPECT_NEAR(b.mean_deg, ref.mean_deg, 1e-9);
  EXPECT_EQ(b.particles_used, c.position_m.size());
}

TEST(SliceAngleOfRepose, RejectsInconsistentInput) {
  const Cloud c = ridge(30.0, 30.0, kSliceHeight, 1.0, 800);
  std::vector<double> short_radii(c.radius_m.begin(), c.radius_m.end() - 1);
  EXPECT_THROW(measure_slice_angle_of_repose(c.position_m, short_radii), std::invalid_argument);
  SliceAoROptions o;
  o.long_axis = 2;
  EXPECT_THROW(measure_slice_angle_of_repose(c.position_m, c.radius_m, o), std::invalid_argument);
  o = {};
  o.lower_fraction = 0.9;
  EXPECT_THROW(measure_slice_angle_of_repose(c.position_m, c.radius_m, o), std::invalid_argument);
  EXPECT_THROW(measure_slice_angle_of_repose({}, {}), std::runtime_error);
}

// -------------------------------------------------------------------- cone

TEST(ConicalAngleOfRepose, RecoversSlopes20To45DegWithin05Deg) {
  double worst_mean = 0.0, worst_sector = 0.0;
  for (double theta : kAngles)
    for (int seed = 1; seed <= kSeeds; ++seed) {
      const Cloud c = cone(theta, kConeHeight, 1.0, 900 + seed);
      const AngleOfRepose a = measure_conical_angle_of_repose(c.position_m, c.radius_m);
      EXPECT_NEAR(a.mean_deg, theta, 0.5) << "theta " << theta << " seed " << seed;
      ASSERT_EQ(a.sides.size(), 8u);
      EXPECT_EQ(a.valid_sides, 8);
      worst_mean = std::max(worst_mean, std::abs(a.mean_deg - theta));
      for (const AoRSide& s : a.sides)
        worst_sector = std::max(worst_sector, std::abs(s.angle_deg - theta));
      EXPECT_NEAR(a.crest_height_m, kConeHeight, 0.75 * kD);
      EXPECT_NEAR(a.axis_centre_m[0], 0.0, 0.5 * kD);
      EXPECT_NEAR(a.axis_centre_m[1], 0.0, 0.5 * kD);
      EXPECT_NEAR(a.base_half_width_m, (kConeHeight - kD) / tan_deg(theta), 2.0 * kD);
      EXPECT_GT(a.uncertainty_deg, 0.0);
    }
  std::printf("[ cone    ] worst |error|: mean %.3f deg, single sector %.3f deg\n", worst_mean,
              worst_sector);
}

TEST(ConicalAngleOfRepose, FindsAnOffCentreAxisAndAgreesWithTheGivenOne) {
  const double x0 = 0.0123, y0 = -0.0071;
  const Cloud c = cone(32.0, kConeHeight, 1.0, 1000, x0, y0);
  const AngleOfRepose found = measure_conical_angle_of_repose(c.position_m, c.radius_m);
  EXPECT_FALSE(found.axis_centre_given);
  EXPECT_NEAR(found.axis_centre_m[0], x0, 0.5 * kD);
  EXPECT_NEAR(found.axis_centre_m[1], y0, 0.5 * kD);
  ConicalAoROptions o;
  o.axis_centre_m = std::array<double, 2>{x0, y0};
  o.sectors = 6;
  const AngleOfRepose given = measure_conical_angle_of_repose(c.position_m, c.radius_m, o);
  EXPECT_TRUE(given.axis_centre_given);
  EXPECT_EQ(given.sides.size(), 6u);
  EXPECT_NEAR(found.mean_deg, 32.0, 0.5);
  EXPECT_NEAR(given.mean_deg, 32.0, 0.5);
}

TEST(ConicalAngleOfRepose, StrayGrainsInTheFitZoneMoveItLessThan03Deg) {
  double worst = 0.0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    Cloud c = cone(35.0, kConeHeight, 1.0, 1100 + seed);
    const AngleOfRepose clean = measure_conical_angle_of_repose(c.position_m, c.radius_m);
    Random rng(seed);
    const double t = tan_deg(35.0);
    for (int k = 0; k < 12; ++k) {
      const double frac = rng.uniform(0.3, 0.7);
      const double phi = rng.uniform(0.0, 2.0 * std::numbers::pi);
      const double rho = (1.0 - frac) * kConeHeight / t;
      c.add({rho * std::cos(phi), rho * std::sin(phi),
             frac * kConeHeight + rng.uniform(4.0, 6.0) * kD});
    }
    const AngleOfRepose dirty = measure_conical_angle_of_repose(c.position_m, c.radius_m);
    EXPECT_NEAR(dirty.mean_deg, clean.mean_deg, 0.3) << "seed " << seed;
    worst = std::max(worst, std::abs(dirty.mean_deg - clean.mean_deg));
  }
  std::printf("[ cone    ] stray grains moved the mean by at most %.3f deg\n", worst);
}

TEST(ConicalAngleOfRepose, FlatLayerAndTinyHeapThrowNamingSectorsAndCounts) {
  Random rng(1200);
  Cloud flat;
  for (int i = -25; i <= 25; ++i)
    for (int j = -25; j <= 25; ++j)
      add_column(flat, rng, i * kD, j * kD, (2.0 + rng.uniform(-0.5, 0.5)) * kD);
  const std::regex named(
      "too flat or too small.*sector_[0-7] \\([0-9.-]+ deg\\) has [0-9]+ bins? "
      "between 15 % and 85 % of the crest height");
  std::string msg =
      thrown_message([&] { measure_conical_angle_of_repose(flat.position_m, flat.radius_m); });
  EXPECT_TRUE(std::regex_search(msg, named)) << msg;

  const Cloud tiny = cone(30.0, 3.0 * kD, 1.0, 1201);
  msg = thrown_message([&] { measure_conical_angle_of_repose(tiny.position_m, tiny.radius_m); });
  EXPECT_TRUE(std::regex_search(msg, named)) << msg;
}

TEST(ConicalAngleOfRepose, SectorsAgainstAWallAreReportedNotDropped) {
  // Cut the cone by a wall at x = 0.35 R: the sectors facing it lose their
  // toe and most of their slope but the others still measure the angle.
  const Cloud full = cone(35.0, kConeHeight, 1.0, 1300);
  const double cut = 0.35 * kConeHeight / tan_deg(35.0);
  Cloud c;
  for (std::size_t i = 0; i < full.position_m.size(); ++i) {
    if (full.position_m[i].x < cut) c.add(full.position_m[i]);
  }
  ConicalAoROptions o;
  o.axis_centre_m = std::array<double, 2>{0.0, 0.0};
  const AngleOfRepose a = measure_conical_angle_of_repose(c.position_m, c.radius_m, o);
  EXPECT_EQ(a.sides.size(), 8u);
  EXPECT_LT(a.valid_sides, 8);
  EXPECT_GE(a.valid_sides, 4);
  EXPECT_NEAR(a.mean_deg, 35.0, 0.5);
  for (const AoRSide& s : a.sides) EXPECT_EQ(s.valid, s.invalid_reason.empty()) << s.name;
}

TEST(ConicalAngleOfRepose, UncertaintyGrowsWithRoughness) {
  double u_smooth = 0.0, u_rough = 0.0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const Cloud smooth = cone(35.0, kConeHeight, 0.25, 1400 + seed);
    const Cloud rough = cone(35.0, kConeHeight, 2.0, 1400 + seed);
    u_smooth += measure_conical_angle_of_repose(smooth.position_m, smooth.radius_m).uncertainty_deg;
    u_rough += measure_conical_angle_of_repose(rough.position_m, rough.radius_m).uncertainty_deg;
  }
  EXPECT_GT(u_smooth, 0.0);
  EXPECT_LT(u_smooth, u_rough);
}

// -------------------------------------------------------------------- json

TEST(AngleOfReposeJson, HasTheStableNames) {
  const Cloud c = ridge(30.0, 30.0, kSliceHeight, 1.0, 1500);
  const AngleOfRepose a = measure_slice_angle_of_repose(c.position_m, c.radius_m);
  const nlohmann::json j = to_json(a);
  EXPECT_DOUBLE_EQ(j.at("angle_of_repose_deg").get<double>(), a.mean_deg);
  EXPECT_DOUBLE_EQ(j.at("angle_of_repose_uncertainty_deg").get<double>(), a.uncertainty_deg);
  EXPECT_DOUBLE_EQ(j.at("crest_height_m").get<double>(), a.crest_height_m);
  ASSERT_EQ(j.at("sides").size(), 2u);
  for (const auto& s : j.at("sides")) {
    EXPECT_TRUE(s.contains("name"));
    EXPECT_TRUE(s.at("angle_deg").is_number());
    EXPECT_TRUE(s.at("std_error_deg").is_number());
    EXPECT_TRUE(s.at("points").is_number_integer());
  }
  EXPECT_EQ(j.at("profile").at("position_m").size(), a.profile_position_m.size());
  EXPECT_EQ(j.at("profile").at("height_m").size(), a.profile_height_m.size());
  EXPECT_TRUE(j.at("crest_position_m").is_number());
  EXPECT_FALSE(j.at("rules").empty());

  const Cloud k = cone(30.0, kConeHeight, 1.0, 1501);
  const nlohmann::json jc = to_json(measure_conical_angle_of_repose(k.position_m, k.radius_m));
  EXPECT_EQ(jc.at("crest_position_m").size(), 2u);
  EXPECT_EQ(jc.at("sides").size(), 8u);
  // Round trip through text: no NaN may leak into the file.
  EXPECT_EQ(nlohmann::json::parse(jc.dump()).at("sides").size(), 8u);
}

}  // namespace
}  // namespace demcal::dem
