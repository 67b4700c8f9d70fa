#pragma once
// Full factorial design: every combination of evenly spaced levels of each
// bounded parameter (the seed paper's grid over mu_r and mu_s).

#include <string>
#include <vector>

namespace demcal::surrogate {

struct ParameterRange {
  std::string name;
  double lower = 0.0;
  double upper = 1.0;
  int levels = 2;  // >= 2: both bounds are included
};

// Rows are design points, columns follow `ranges`; the last parameter varies fastest.
// Throws std::invalid_argument naming the parameter when a range is empty or levels < 2.
std::vector<std::vector<double>> full_factorial_design(const std::vector<ParameterRange>& ranges);

}  // namespace demcal::surrogate
