// The surrogate models: a section per model (its reader and its declaration),
// then the registry that lists them.

#include "config/models/surrogate_models.hpp"

#include <cstdint>
#include <limits>

namespace demcal::config {

namespace {

using reader::Table;

// ---------------------------------------------------------------- gaussian_process

void read_gaussian_process(Table& t, surrogate::SurrogateSpec& s) {
  s.kernel = surrogate::covariance_kernel_from_string(
      t.choice_or("kernel", {"matern52", "squared_exponential"}, "matern52"));
  s.mean = surrogate::mean_function_from_string(
      t.choice_or("mean", {"constant", "linear"}, "constant"));
  s.nugget = t.choice_or("nugget", {"replicates", "estimated", "none"}, "replicates");
  s.starts = static_cast<int>(t.integer_or("starts", 8, 1, 100));
  s.seed = static_cast<std::uint64_t>(
      t.integer_or("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
}

ModelInfo gaussian_process_info() {
  return {"gaussian_process",
          "a Gaussian process per observable (surrogate/gaussian_process.hpp)",
          {{"kernel", "", "\"matern52\"", "\"matern52\" | \"squared_exponential\"",
            "the covariance kernel"},
           {"mean", "", "\"constant\"", "\"constant\" | \"linear\"", "the mean function"},
           {"nugget", "", "\"replicates\"", "\"replicates\" | \"estimated\" | \"none\"",
            "the noise: per point from replicates, one estimated, or none (interpolating)"},
           {"starts", "", "8", "an integer in [1, 100]", "maximum-likelihood starts"},
           {"seed", "", "1", "an integer >= 0", "the starts' seed"}}};
}

// ---------------------------------------------------------------- polynomial

void read_polynomial(Table& t, surrogate::SurrogateSpec& s) {
  s.degree = static_cast<int>(t.integer_or("degree", 0, 0, 4));
}

ModelInfo polynomial_info() {
  return {"polynomial",
          "a polynomial response surface per observable (surrogate/polynomial_surface.hpp)",
          {{"degree", "", "0 (chosen by leave-one-out)", "an integer in [0, 4]",
            "the total degree"}}};
}

}  // namespace

const SurrogateRegistry& surrogate_models() {
  // Registration order is the order messages list the models in.
  static const SurrogateRegistry registry = [] {
    SurrogateRegistry r({"surrogate", "", "[surrogate] model = \"<name>\""});
    r.add(gaussian_process_info(), &read_gaussian_process);
    r.add(polynomial_info(), &read_polynomial);
    return r;
  }();
  return registry;
}

}  // namespace demcal::config
