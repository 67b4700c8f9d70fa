#include "surrogate/design.hpp"

#include "surrogate/latin_hypercube_design.hpp"
#include "surrogate/sobol_design.hpp"

#include <stdexcept>

namespace demcal::surrogate {

const std::vector<std::string>& design_kind_names() {
  static const std::vector<std::string> names = {"full_factorial", "latin_hypercube", "sobol",
                                                 "list"};
  return names;
}

std::string design_kind_name(DesignKind kind) {
  switch (kind) {
    case DesignKind::kFullFactorial:
      return "full_factorial";
    case DesignKind::kLatinHypercube:
      return "latin_hypercube";
    case DesignKind::kSobol:
      return "sobol";
    case DesignKind::kList:
      return "list";
  }
  return "unknown";
}

std::optional<DesignKind> design_kind_from_name(std::string_view name) {
  for (DesignKind k : {DesignKind::kFullFactorial, DesignKind::kLatinHypercube, DesignKind::kSobol,
                        DesignKind::kList})
    if (design_kind_name(k) == name) return k;
  return std::nullopt;
}

Design generate_design(const DesignSpec& spec) {
  Design d;
  d.spec = spec;
  switch (spec.kind) {
    case DesignKind::kFullFactorial:
      d.points = full_factorial_design(spec.parameters);
      break;
    case DesignKind::kLatinHypercube: {
      LatinHypercubeOptions o;
      o.points = spec.points;
      o.seed = spec.seed;
      d.points = latin_hypercube_design(spec.parameters, o);
      break;
    }
    case DesignKind::kSobol:
      d.points = sobol_design(spec.parameters, spec.points, spec.skip);
      break;
    case DesignKind::kList:
      if (spec.values.empty()) throw std::invalid_argument("list design: no points");
      for (std::size_t i = 0; i < spec.values.size(); ++i) {
        if (spec.values[i].size() != spec.parameters.size())
          throw std::invalid_argument("list design: point " + std::to_string(i) + " has " +
                                      std::to_string(spec.values[i].size()) + " values; expected " +
                                      std::to_string(spec.parameters.size()));
        for (std::size_t k = 0; k < spec.parameters.size(); ++k) {
          const auto& p = spec.parameters[k];
          const double v = spec.values[i][k];
          if (!(v >= p.lower && v <= p.upper))
            throw std::invalid_argument("list design: point " + std::to_string(i) + ": " + p.name + " = " +
                                        std::to_string(v) + " is outside [" + std::to_string(p.lower) + ", " +
                                        std::to_string(p.upper) + "]");
        }
      }
      d.points = spec.values;
      break;
  }
  return d;
}

}  // namespace demcal::surrogate
