#include "dem/domain.hpp"

#include <stdexcept>
#include <string>

namespace demcal::dem {

void Domain::validate() const {
  if (!is_finite(lower_m) || !is_finite(upper_m))
    throw std::invalid_argument("domain: lower_m and upper_m must be finite");
  for (int k = 0; k < 3; ++k)
    if (!(upper_m[k] > lower_m[k]))
      throw std::invalid_argument("domain: upper_m[" + std::to_string(k) +
                                  "] must exceed lower_m[" + std::to_string(k) + "]");
}

}  // namespace demcal::dem
