// The two spring rolling parts at the level of one contact and one step:
// "epsd"'s spring follows the normal part's stiffness (the overlap), "sds"'s is
// the constant factor 2 E* R* sqrt(x) (mu_r R*)^2, equal to epsd's at
// delta = x R*; both have the limit mu_r R* F_n and the same dashpot, but
// their sliders differ: epsd's bounds the spring alone (Ai et al., model C),
// sds's bounds spring + dashpot together as LAMMPS's does.
#include "dem/contact/constant_spring_rolling.hpp"
#include "dem/contact/contact_law.hpp"
#include "dem/contact/rolling_resistance.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace demcal::dem {
namespace {

constexpr double kRadius = 0.5e-3;  // two equal grains: R* = R / 2
constexpr double kReff = 0.5 * kRadius;
constexpr double kEstar = 5.0e6;
constexpr double kDt = 1e-6;

PairCoefficients pair(double mu_r, double damping_ratio, double reference_overlap) {
  PairCoefficients c;
  c.youngs_modulus_eff_pa = kEstar;
  c.rolling_friction = mu_r;
  c.rolling_stiffness_factor = 2.25;
  c.rolling_damping_ratio = damping_ratio;
  c.part_values = default_part_values();
  c.part_values[constant_spring_rolling::kReferenceOverlapSlot] = reference_overlap;
  return c;
}

ContactKinematics rolling_about_y(double omega_rad_s) {
  const double mass = 2650.0 * 4.0 / 3.0 * std::numbers::pi * kRadius * kRadius * kRadius;
  const double inertia = 0.4 * mass * kRadius * kRadius;
  ContactKinematics k;
  k.normal = {0, 0, 1};
  k.radius_eff_m = kReff;
  k.mass_eff_kg = 0.5 * mass;
  k.lever_i_m = k.lever_j_m = kRadius;
  k.inv_mass_i_kg = k.inv_mass_j_kg = 1.0 / mass;
  k.inv_inertia_i_kg_m2 = k.inv_inertia_j_kg_m2 = 1.0 / inertia;
  k.omega_i_rad_s = {0, omega_rad_s, 0};
  k.dt_s = kDt;
  return k;
}

// One step from a fresh contact at this overlap (Hertz's tangent stiffness
// and load); returns the torque on i.
template <class Part>
Vec3 first_step_torque(const Part& part, const PairCoefficients& c, double overlap_m,
                       double omega_rad_s, ContactHistory* history = nullptr) {
  const double a = std::sqrt(kReff * overlap_m);
  ContactForce f;
  f.normal_stiffness_n_m = 2.0 * kEstar * a;
  f.normal_force_n = 4.0 / 3.0 * kEstar * a * overlap_m;
  f.friction_load_n = f.normal_force_n;
  ContactHistory fresh;
  ContactHistory& h = history != nullptr ? *history : fresh;
  part.apply(rolling_about_y(omega_rad_s), c, h, f);
  return f.torque_i_nm;
}

TEST(RollingSprings, TheConstantSpringIgnoresTheOverlapAndEqualsEpsdAtTheReference) {
  const double mu_r = 0.2, omega = 1e-3, x = 0.005;
  const auto c = pair(mu_r, 0.0, x);  // undamped: the torque is the spring's
  const double arm = mu_r * kReff;
  const double k_sds = 2.25 * 2.0 * kEstar * kReff * std::sqrt(x) * arm * arm;
  EXPECT_DOUBLE_EQ(ConstantSpringDashpot::stiffness_nm_rad(c, kReff), k_sds);
  for (const double q : {0.001, x, 0.02}) {
    const Vec3 t = first_step_torque(ConstantSpringDashpot{}, c, q * kReff, omega);
    // -k dt w, opposing the rolling about y.
    EXPECT_NEAR(t.y, -k_sds * kDt * omega, 1e-12 * k_sds * kDt * omega) << "overlap " << q;
    const Vec3 e = first_step_torque(ElasticPlasticSpringDashpot{}, c, q * kReff, omega);
    const double k_epsd = 2.25 * 2.0 * kEstar * std::sqrt(kReff * q * kReff) * arm * arm;
    EXPECT_NEAR(e.y, -k_epsd * kDt * omega, 1e-12 * k_epsd * kDt * omega) << "overlap " << q;
    if (q == x) {
      EXPECT_NEAR(t.y, e.y, 1e-12 * std::abs(e.y));
    }
  }
}

TEST(RollingSprings, TheReferenceOverlapSetsTheStiffnessAsItsSquareRoot) {
  const auto soft = pair(0.3, 0.0, 0.001), stiff = pair(0.3, 0.0, 0.004);
  EXPECT_NEAR(ConstantSpringDashpot::stiffness_nm_rad(stiff, kReff) /
                  ConstantSpringDashpot::stiffness_nm_rad(soft, kReff),
              2.0, 1e-12);
}

TEST(RollingSprings, BothSlideAtTheLimitingTorque) {
  const double mu_r = 0.1, overlap = 0.003 * kReff;
  const auto c = pair(mu_r, 0.3, 0.005);
  const double load = 4.0 / 3.0 * kEstar * std::sqrt(kReff) * std::pow(overlap, 1.5);
  const double limit = mu_r * kReff * load;
  for (const bool constant : {true, false}) {
    ContactHistory h;
    // A rotation far beyond the elastic range in one step.
    const Vec3 t = constant ? first_step_torque(ConstantSpringDashpot{}, c, overlap, 1e4, &h)
                            : first_step_torque(ElasticPlasticSpringDashpot{}, c, overlap, 1e4, &h);
    EXPECT_NEAR(t.y, -limit, 1e-12 * limit) << (constant ? "sds" : "epsd");
  }
}

// At the limit epsd keeps its spring on the limit and idles the dashpot;
// sds keeps the dashpot on and stores the spring so that spring + dashpot is
// the limit (LAMMPS: xi = -(F_crit f^ + gamma_roll v_roll) / k_roll). The next
// step's spring is then the stored one, turned with the contact.
TEST(RollingSprings, AtTheLimitEpsdIdlesTheDashpotAndSdsStoresTheSpringLammpsWay) {
  const double mu_r = 0.1, overlap = 0.003 * kReff, omega = 1e4;
  const auto c = pair(mu_r, 0.3, 0.005);
  const double load = 4.0 / 3.0 * kEstar * std::sqrt(kReff) * std::pow(overlap, 1.5);
  const double limit = mu_r * kReff * load;
  const auto k = rolling_about_y(omega);
  const double dashpot =
      rolling_dashpot_n_m_s(k, c, ConstantSpringDashpot::stiffness_nm_rad(c, kReff));
  ASSERT_GT(dashpot, 0.0);

  ContactHistory epsd;
  first_step_torque(ElasticPlasticSpringDashpot{}, c, overlap, omega, &epsd);
  EXPECT_NEAR(epsd.rolling_torque_nm.y, -limit, 1e-12 * limit);

  ContactHistory sds;
  first_step_torque(ConstantSpringDashpot{}, c, overlap, omega, &sds);
  // torque = spring - dashpot w = -limit, so spring = -limit + dashpot w.
  const double stored = -limit + dashpot * omega;
  EXPECT_NEAR(sds.rolling_torque_nm.y, stored, 1e-12 * std::abs(stored) + 1e-12 * limit);
  EXPECT_NEAR(sds.rolling_torque_nm.x, 0.0, 1e-30);
  EXPECT_NEAR(sds.rolling_torque_nm.z, 0.0, 1e-30);
}

// Below the spring's limit: epsd's dashpot adds to the spring without bound,
// sds bounds the sum. A fresh contact spun up fast (an impact) shows it: the
// spring is still small, the dashpot alone exceeds mu_r R* F_n.
TEST(RollingSprings, InAnImpactOnlySdsBoundsSpringPlusDashpot) {
  // At the reference overlap the two parts have the same spring, dashpot and limit.
  const double mu_r = 0.1, overlap = 0.005 * kReff, zeta = 0.3;
  const auto c = pair(mu_r, zeta, 0.005);
  const double load = 4.0 / 3.0 * kEstar * std::sqrt(kReff) * std::pow(overlap, 1.5);
  const double limit = mu_r * kReff * load;
  const double k_r = ConstantSpringDashpot::stiffness_nm_rad(c, kReff);
  const double dashpot = rolling_dashpot_n_m_s(rolling_about_y(1.0), c, k_r);
  // The spin at which the dashpot alone is twice the limit, while one step of
  // spring (k_r dt w) stays far below it.
  const double omega = 2.0 * limit / dashpot;
  ASSERT_LT(k_r * kDt * omega, 0.1 * limit);
  const double spring = -k_r * kDt * omega;

  const Vec3 e = first_step_torque(ElasticPlasticSpringDashpot{}, c, overlap, omega);
  EXPECT_NEAR(e.y, spring - dashpot * omega, 1e-9 * dashpot * omega)
      << "epsd: spring + dashpot, unbounded below the spring's limit";
  EXPECT_GT(std::abs(e.y), 2.0 * limit);
  const Vec3 t = first_step_torque(ConstantSpringDashpot{}, c, overlap, omega);
  EXPECT_NEAR(t.y, -limit, 1e-12 * limit) << "sds: the sum bounded at mu_r R* F_n";
  // Without a dashpot the two sliders are the same.
  const auto undamped = pair(mu_r, 0.0, 0.005);
  EXPECT_NEAR(first_step_torque(ConstantSpringDashpot{}, undamped, overlap, omega).y, spring,
              1e-12 * std::abs(spring));
  EXPECT_NEAR(first_step_torque(ElasticPlasticSpringDashpot{}, undamped, overlap, omega).y, spring,
              1e-12 * std::abs(spring));
}

TEST(RollingSprings, TheDashpotIsTheStatedFractionOfCritical) {
  const double mu_r = 0.2, omega = 1e-3, zeta = 0.3;
  const auto damped = pair(mu_r, zeta, 0.005), undamped = pair(mu_r, 0.0, 0.005);
  const double overlap = 0.005 * kReff;
  const double dashpot = first_step_torque(ConstantSpringDashpot{}, damped, overlap, omega).y -
                         first_step_torque(ConstantSpringDashpot{}, undamped, overlap, omega).y;
  // Reduced inertia about the contact point: (I + m R^2)/2 for two equal grains.
  const auto k = rolling_about_y(omega);
  const double about_contact = 1.0 / k.inv_inertia_i_kg_m2 + kRadius * kRadius / k.inv_mass_i_kg;
  const double reduced = 0.5 * about_contact;
  const double k_r = ConstantSpringDashpot::stiffness_nm_rad(damped, kReff);
  const double expected = -zeta * 2.0 * std::sqrt(k_r * reduced) * omega;
  EXPECT_NEAR(dashpot, expected, 1e-9 * std::abs(expected));
}

TEST(RollingSprings, TheConstantSpringIsRegisteredWithItsParameter) {
  ContactLawSpec spec;
  spec.rolling = "sds";
  EXPECT_NE(make_contact_law(spec).describe().find("rolling=sds"), std::string::npos);
  bool declared = false;
  for (const auto& r : registered_part_parameters())
    if (r.part == "sds" && r.role == "rolling") {
      declared = true;
      EXPECT_EQ(std::string(r.parameter.key), "rolling_reference_overlap_fraction");
      EXPECT_EQ(r.parameter.default_value, 0.005);
      EXPECT_FALSE(r.parameter.accepts(0.0));
      EXPECT_TRUE(r.parameter.accepts(0.1));
      EXPECT_FALSE(r.parameter.accepts(0.2));
    }
  EXPECT_TRUE(declared);
}

}  // namespace
}  // namespace demcal::dem
