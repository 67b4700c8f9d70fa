#pragma once
// A design of experiments by kind: what the campaign runner (demcal doe) asks
// for, independent of how the points are made. The kinds:
//   full_factorial   every combination of `levels` evenly spaced values per
//                    parameter, bounds included; the last parameter varies
//                    fastest (surrogate/full_factorial_design.hpp)
//   latin_hypercube  `points` maximin Latin hypercube points for `seed`
//                    (surrogate/latin_hypercube_design.hpp)
//   sobol            the first `points` of GSL's Sobol sequence after `skip`
//                    (surrogate/sobol_design.hpp)
//   list             the points given, in order (`values`): a refinement chosen
//                    by hand or by a program, e.g. the diagnosis's runs at a fit

#include "surrogate/full_factorial_design.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace demcal::surrogate {

enum class DesignKind { kFullFactorial, kLatinHypercube, kSobol, kList };

// "full_factorial", "latin_hypercube", "sobol", "list".
std::string design_kind_name(DesignKind kind);
std::optional<DesignKind> design_kind_from_name(std::string_view name);
const std::vector<std::string>& design_kind_names();

struct DesignSpec {
  DesignKind kind = DesignKind::kFullFactorial;
  std::vector<ParameterRange> parameters;  // levels used by full_factorial only
  std::size_t points = 0;                  // latin_hypercube and sobol
  std::uint64_t seed = 1;                  // latin_hypercube
  std::size_t skip = 0;                    // sobol
  std::vector<std::vector<double>> values;  // list: rows are points, inside the bounds
};

struct Design {
  DesignSpec spec;
  std::vector<std::vector<double>> points;  // rows are points, columns spec.parameters
};

// Throws std::invalid_argument (naming the parameter where one is at fault)
// when the spec is not one the kind can make.
Design generate_design(const DesignSpec& spec);

}  // namespace demcal::surrogate
