#pragma once
// A contact law assembled from parts by role, as in MercuryDPM: a normal part,
// an adhesion part, a tangential part and a rolling part, applied in that
// order. Each role is a closed set of interchangeable parts (a std::variant);
// adding physics means writing a new part in its own file and adding it to
// its role's list below — the force loop is generated for every combination,
// so no central switch is edited and no virtual call sits in the hot loop.

#include "dem/contact/hertz_normal.hpp"
#include "dem/contact/mindlin_tangential.hpp"
#include "dem/contact/no_adhesion.hpp"
#include "dem/contact/rolling_resistance.hpp"

#include <string>
#include <variant>
#include <vector>

namespace demcal::dem {

// The registry: one line per role. Names come from each part's kName.
using NormalPart = std::variant<HertzNormal>;
using AdhesionPart = std::variant<NoAdhesion>;
using TangentialPart = std::variant<MindlinTangential, NoTangential>;
using RollingPart = std::variant<ConstantDirectionalTorque, ElasticPlasticSpringDashpot, NoRolling>;

// What a config says about the contact law.
struct ContactLawSpec {
  std::string normal = "hertz";
  std::string adhesion = "none";
  std::string tangential = "mindlin";
  std::string rolling = "cdt";
  // Only for rolling = "cdt": oppose each grain's own angular velocity (EDEM's
  // original) instead of the relative rolling velocity.
  bool cdt_own_angular_velocity = false;
};

struct ContactLaw {
  NormalPart normal;
  AdhesionPart adhesion;
  TangentialPart tangential;
  RollingPart rolling;

  std::string describe() const;
};

// Builds the law; an unknown name throws std::invalid_argument listing the
// role and the names it knows.
ContactLaw make_contact_law(const ContactLawSpec& spec);

// Names each role knows, for help texts and error messages.
std::vector<std::string> known_part_names(const std::string& role);

// Applies the parts of one contact in role order. Instantiated per combination.
template <class N, class A, class T, class R>
struct ContactKernel {
  const N& normal;
  const A& adhesion;
  const T& tangential;
  const R& rolling;

  inline void operator()(const ContactKinematics& k, const PairCoefficients& c,
                         ContactHistory& h, ContactForce& f) const {
    normal.apply(k, c, h, f);
    adhesion.apply(k, c, h, f);
    tangential.apply(k, c, h, f);
    rolling.apply(k, c, h, f);
  }
};

// Calls fn(kernel) with the kernel type of this law's combination of parts.
template <class Fn>
decltype(auto) with_contact_kernel(const ContactLaw& law, Fn&& fn) {
  return std::visit(
      [&](const auto& n, const auto& a, const auto& t, const auto& r) -> decltype(auto) {
        using K = ContactKernel<std::decay_t<decltype(n)>, std::decay_t<decltype(a)>,
                                std::decay_t<decltype(t)>, std::decay_t<decltype(r)>>;
        return fn(K{n, a, t, r});
      },
      law.normal, law.adhesion, law.tangential, law.rolling);
}

}  // namespace demcal::dem
