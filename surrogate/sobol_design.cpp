#include "surrogate/sobol_design.hpp"

#include "surrogate/latin_hypercube_design.hpp"

#include <gsl/gsl_qrng.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace demcal::surrogate {

std::vector<std::vector<double>> sobol_design(const std::vector<ParameterRange>& ranges,
                                              std::size_t points, std::size_t skip) {
  check_ranges(ranges, "sobol");
  if (points == 0) throw std::invalid_argument("sobol: points must be >= 1");
  // Checked here: GSL's own check calls its error handler, which aborts.
  if (ranges.size() > kSobolMaxDimensions)
    throw std::invalid_argument("sobol: GSL's Sobol sequence has at most " +
                                std::to_string(kSobolMaxDimensions) + " dimensions, got " +
                                std::to_string(ranges.size()));
  struct Deleter {
    void operator()(gsl_qrng* q) const { gsl_qrng_free(q); }
  };
  const auto dims = static_cast<unsigned int>(ranges.size());
  std::unique_ptr<gsl_qrng, Deleter> q(gsl_qrng_alloc(gsl_qrng_sobol, dims));
  if (!q) throw std::runtime_error("sobol: cannot allocate GSL's Sobol generator");
  std::vector<double> v(ranges.size());
  for (std::size_t i = 0; i < skip; ++i) gsl_qrng_get(q.get(), v.data());
  std::vector<std::vector<double>> unit(points);
  for (auto& row : unit) {
    gsl_qrng_get(q.get(), v.data());
    row = v;
  }
  return scale_to_ranges(unit, ranges);
}

}  // namespace demcal::surrogate
