#include "surrogate/full_factorial_design.hpp"

#include <cmath>
#include <stdexcept>

namespace demcal::surrogate {

std::vector<std::vector<double>> full_factorial_design(const std::vector<ParameterRange>& ranges) {
  if (ranges.empty()) throw std::invalid_argument("full factorial design: no parameters");
  std::size_t total = 1;
  for (const auto& r : ranges) {
    if (!(r.upper > r.lower) || !std::isfinite(r.lower) || !std::isfinite(r.upper))
      throw std::invalid_argument("parameter '" + r.name + "': upper must exceed lower");
    if (r.levels < 2) throw std::invalid_argument("parameter '" + r.name + "': levels must be >= 2");
    total *= static_cast<std::size_t>(r.levels);
  }
  std::vector<std::vector<double>> points;
  points.reserve(total);
  for (std::size_t k = 0; k < total; ++k) {
    std::vector<double> p(ranges.size());
    std::size_t rest = k;
    for (std::size_t d = ranges.size(); d-- > 0;) {
      const auto& r = ranges[d];
      const std::size_t level = rest % static_cast<std::size_t>(r.levels);
      rest /= static_cast<std::size_t>(r.levels);
      // Exact end points: lower + (upper - lower) * 1 may round off upper.
      p[d] = level + 1 == static_cast<std::size_t>(r.levels)
                 ? r.upper
                 : r.lower + (r.upper - r.lower) * static_cast<double>(level) / (r.levels - 1);
    }
    points.push_back(std::move(p));
  }
  return points;
}

}  // namespace demcal::surrogate
