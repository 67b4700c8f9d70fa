#pragma once
// Goodness of fit of standardized residuals r_i = (measured - predicted) / sigma:
// the chi-square statistic against its degrees of freedom.

#include <vector>

namespace demcal::calibrate {

struct GoodnessOfFit {
  double chi_square = 0.0;
  int degrees_of_freedom = 0;
  double chi_square_per_dof = 0.0;
  double p_value = 1.0;  // probability of a chi-square at least this large if the model is right
};

// dof = number of residuals - fitted parameters; throws std::invalid_argument when < 1.
GoodnessOfFit goodness_of_fit(const std::vector<double>& standardized_residuals,
                              int fitted_parameters);

}  // namespace demcal::calibrate
