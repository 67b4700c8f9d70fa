#include "surrogate/design.hpp"

#include "surrogate/latin_hypercube_design.hpp"
#include "surrogate/sobol_design.hpp"

#include <stdexcept>

namespace demcal::surrogate {

const std::vector<std::string>& design_kind_names() {
  static const std::vector<std::string> names = {"full_factorial", "latin_hypercube", "sobol"};
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
  }
  return "unknown";
}

std::optional<DesignKind> design_kind_from_name(std::string_view name) {
  for (DesignKind k : {DesignKind::kFullFactorial, DesignKind::kLatinHypercube, DesignKind::kSobol})
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
  }
  return d;
}

}  // namespace demcal::surrogate
