// The contact-law registry and the per-pair coefficients.
#include "dem/contact/contact_law.hpp"
#include "dem/contact/pair_coefficients.hpp"
#include "dem/material.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace demcal::dem {
namespace {

TEST(ContactLaw, BuildsEveryRegisteredCombinationByName) {
  for (const auto& t : known_part_names("tangential"))
    for (const auto& r : known_part_names("rolling")) {
      ContactLawSpec spec;
      spec.tangential = t;
      spec.rolling = r;
      const ContactLaw law = make_contact_law(spec);
      EXPECT_NE(law.describe().find("rolling=" + r), std::string::npos);
    }
}

TEST(ContactLaw, UnknownPartNamesTheRoleAndTheKnownNames) {
  ContactLawSpec spec;
  spec.rolling = "type_c";
  try {
    make_contact_law(spec);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("contact.rolling"), std::string::npos) << what;
    EXPECT_NE(what.find("\"cdt\""), std::string::npos) << what;
    EXPECT_NE(what.find("\"epsd\""), std::string::npos) << what;
  }
  spec.rolling = "epsd";
  spec.cdt_own_angular_velocity = true;
  EXPECT_THROW(make_contact_law(spec), std::invalid_argument);
}

TEST(PairCoefficients, EffectiveModuliFollowHertzAndMindlin) {
  Material a{"a", 2650.0, 7e10, 0.0, 0.25};
  Material b{"b", 7800.0, 0.0, 8e10, 0.3};
  InteractionParameters p;
  const auto c = resolve_pair(a, b, p, RestitutionModel::kExact);
  const double ea = 7e10, eb = 2.0 * 8e10 * 1.3;
  EXPECT_NEAR(c.youngs_modulus_eff_pa, 1.0 / ((1 - 0.0625) / ea + (1 - 0.09) / eb), 1.0);
  const double ga = 7e10 / 2.5, gb = 8e10;
  EXPECT_NEAR(c.shear_modulus_eff_pa, 1.0 / ((2 - 0.25) / ga + (2 - 0.3) / gb), 1.0);
}

TEST(Material, RefusesUnphysicalValuesNamingTheField) {
  Material m{"quartz", 2650.0, 1e7, 0.0, 0.3};
  EXPECT_NO_THROW(m.validate());
  auto expect_field = [](Material bad, const std::string& field) {
    try {
      bad.validate();
      FAIL() << "expected an error for " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  Material bad = m;
  bad.density_kg_m3 = -1;
  expect_field(bad, "density_kg_m3");
  bad = m;
  bad.poisson_ratio = 0.5;
  expect_field(bad, "poisson_ratio");
  bad = m;
  bad.youngs_modulus_pa = 0;
  expect_field(bad, "youngs_modulus_pa");
  bad = m;
  bad.shear_modulus_pa = 1e9;  // inconsistent with E and nu
  expect_field(bad, "shear_modulus_pa");
}

TEST(Material, RayleighTimeOfTheBenchmarkGrain) {
  // d = 1 mm, E = 1e7 Pa, nu = 0.3, rho = 2650: G = 3.846e6 Pa, T_R = 4.45e-5 s.
  Material m{"grain", 2650.0, 1e7, 0.0, 0.3};
  EXPECT_NEAR(rayleigh_time_s(m, 0.5e-3), 4.453e-5, 0.005e-5);
}

}  // namespace
}  // namespace demcal::dem
