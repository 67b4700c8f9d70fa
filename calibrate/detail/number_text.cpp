#include "calibrate/detail/number_text.hpp"

#include <cmath>
#include <cstdio>

namespace demcal::calibrate::detail {

std::string fmt(double x, int digits) {
  if (std::isnan(x)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

nlohmann::json number_json(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); }

}  // namespace demcal::calibrate::detail
