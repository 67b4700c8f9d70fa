#include "calibrate/goodness_of_fit.hpp"

#include <gsl/gsl_cdf.h>

#include <stdexcept>

namespace demcal::calibrate {

GoodnessOfFit goodness_of_fit(const std::vector<double>& r, int fitted_parameters) {
  GoodnessOfFit g;
  g.degrees_of_freedom = static_cast<int>(r.size()) - fitted_parameters;
  if (g.degrees_of_freedom < 1)
    throw std::invalid_argument("goodness of fit: need more residuals than fitted parameters");
  for (double x : r) g.chi_square += x * x;
  g.chi_square_per_dof = g.chi_square / g.degrees_of_freedom;
  g.p_value = gsl_cdf_chisq_Q(g.chi_square, g.degrees_of_freedom);
  return g;
}

}  // namespace demcal::calibrate
