#pragma once
// Sobol design: the first points of GSL's Sobol low-discrepancy sequence
// (gsl_qrng_sobol, Bratley & Fox, up to 40 dimensions), scaled from the unit
// cube to each parameter's range. GSL's sequence leaves out the all-zero
// point, so the first point is the centre (0.5, ..., 0.5). A sequence is best
// balanced over 2^k points; `skip` drops that many points first (to continue a
// sequence or to start further along it).

#include "surrogate/full_factorial_design.hpp"

#include <cstddef>
#include <vector>

namespace demcal::surrogate {

inline constexpr std::size_t kSobolMaxDimensions = 40;

// Rows are points, columns follow `ranges`. Throws std::invalid_argument when
// points is 0, a range is empty, or there are more than kSobolMaxDimensions parameters.
std::vector<std::vector<double>> sobol_design(const std::vector<ParameterRange>& ranges,
                                              std::size_t points, std::size_t skip = 0);

}  // namespace demcal::surrogate
