#pragma once
// A contact law assembled from parts by role, as in MercuryDPM: a normal part,
// an adhesion part, a tangential part and a rolling part, applied in that
// order. Each role is a closed set of interchangeable parts (a std::variant);
// adding physics means writing a new part in its own file and adding it to
// its role's list below — the force loop is generated for every combination,
// so no central switch is edited and no virtual call sits in the hot loop.
//
// A part with numbers of its own declares them (keys, units, ranges, defaults,
// coarse-graining exponent) in `static constexpr std::array<PartParameter, N>
// kParameters` (dem/contact/part_parameter.hpp); readers, schema and coarse
// graining take them from registered_part_parameters().
//
// A part's apply() is marked [[gnu::always_inline]]: the loop must not call it.
// It is written without branches (selects, `c ? a : b`, taken before any
// division they guard; no early return, no flag read): the engine applies the
// law to batches of contacts in a loop the compiler vectorises
// (dem/contact_batch.hpp), and one branch in one part keeps the whole law
// scalar. A part with branches is still correct, only slower.
//
// A part may hold a contact beyond touching (adhesion): it then defines
//   bool holds(const PairCoefficients&, double radius_eff_m, double overlap_m) const
//     -- whether a contact that touched is still on at this negative overlap,
//   double max_separation_m(const PairCoefficients&, double radius_eff_m) const
//     -- the largest gap at which it can hold one (the Verlet skin must exceed it).
// The engine asks only while a pair that touched has parted, and only in the
// loops instantiated for a combination with such a part; the loops of every
// other combination are the ones of a law without it.

#include "dem/contact/constant_spring_rolling.hpp"
#include "dem/contact/hertz_normal.hpp"
#include "dem/contact/jkr_adhesion.hpp"
#include "dem/contact/liquid_bridge.hpp"
#include "dem/contact/mindlin_tangential.hpp"
#include "dem/contact/no_adhesion.hpp"
#include "dem/contact/part_parameter.hpp"
#include "dem/contact/rolling_resistance.hpp"

#include <algorithm>
#include <concepts>
#include <string>
#include <variant>
#include <vector>

namespace demcal::dem {

// The registry: one line per role. Names come from each part's kName.
using NormalPart = std::variant<HertzNormal>;
using AdhesionPart = std::variant<NoAdhesion, JkrAdhesion, LiquidBridge>;
using TangentialPart = std::variant<MindlinTangential, NoTangential>;
// ConstantDirectionalTorqueOwnOmega shares the name "cdt" (it is chosen by
// contact.cdt_own_angular_velocity); a name is found by its first part.
using RollingPart =
    std::variant<ConstantDirectionalTorque, ElasticPlasticSpringDashpot, ConstantSpringDashpot,
                 NoRolling, ConstantDirectionalTorqueOwnOmega>;

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

// The roles, in the order the parts apply: normal, adhesion, tangential, rolling.
const std::vector<std::string>& contact_roles();

// Every parameter the registered parts declare, role by role, part by part,
// in declaration order. Throws std::logic_error when two parts claim one slot
// or one key, or a slot lies outside PartValues.
const std::vector<RegisteredPartParameter>& registered_part_parameters();

// "[0, 90)", ">= 0": a declared range as messages and the schema show it.
std::string part_parameter_range_text(const PartParameter& p);

// A part that holds contacts beyond touching (see the top of this file).
template <class Part>
concept HoldsBeyondTouching = requires(const Part& p, const PairCoefficients& c, double x) {
  { p.holds(c, x, x) } -> std::same_as<bool>;
  { p.max_separation_m(c, x) } -> std::same_as<double>;
};

// Applies the parts of one contact in role order. Instantiated per combination.
template <class N, class A, class T, class R>
struct ContactKernel {
  const N& normal;
  const A& adhesion;
  const T& tangential;
  const R& rolling;

  static constexpr bool kHoldsBeyondTouching = HoldsBeyondTouching<N> || HoldsBeyondTouching<A> ||
                                               HoldsBeyondTouching<T> || HoldsBeyondTouching<R>;

  // A contact that touched stays on while any part holds it.
  bool holds(const PairCoefficients& c, double radius_eff_m, double overlap_m) const {
    return holds_by(normal, c, radius_eff_m, overlap_m) ||
           holds_by(adhesion, c, radius_eff_m, overlap_m) ||
           holds_by(tangential, c, radius_eff_m, overlap_m) ||
           holds_by(rolling, c, radius_eff_m, overlap_m);
  }
  double max_separation_m(const PairCoefficients& c, double radius_eff_m) const {
    return std::max(
        {separation_by(normal, c, radius_eff_m), separation_by(adhesion, c, radius_eff_m),
         separation_by(tangential, c, radius_eff_m), separation_by(rolling, c, radius_eff_m)});
  }

  // Forced inline, like each part's apply(): with a dozen combinations
  // instantiated, GCC's growth limits otherwise leave parts as calls in the
  // contact loop (measured: +0.8 % instructions, a call per part per contact).
  [[gnu::always_inline]] inline void operator()(const ContactKinematics& k,
                                                const PairCoefficients& c, ContactHistory& h,
                                                ContactForce& f) const {
    normal.apply(k, c, h, f);
    adhesion.apply(k, c, h, f);
    tangential.apply(k, c, h, f);
    rolling.apply(k, c, h, f);
  }

 private:
  template <class P>
  static bool holds_by(const P& part, const PairCoefficients& c, double r, double overlap) {
    if constexpr (HoldsBeyondTouching<P>) {
      return part.holds(c, r, overlap);
    } else {
      return false;
    }
  }
  template <class P>
  static double separation_by(const P& part, const PairCoefficients& c, double r) {
    if constexpr (HoldsBeyondTouching<P>) {
      return part.max_separation_m(c, r);
    } else {
      return 0.0;
    }
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
