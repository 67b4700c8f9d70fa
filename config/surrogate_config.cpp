#include "config/surrogate_config.hpp"

#include "config/observables.hpp"

namespace demcal::config {

std::optional<SurrogateConfig> read_surrogate(reader::Table& root) {
  if (!root.has("surrogate")) return std::nullopt;
  reader::Table t = root.table("surrogate");
  SurrogateConfig c;
  auto& s = c.spec;
  s.model = t.choice_or("model", {"gaussian_process", "polynomial"}, "gaussian_process");
  c.observables = t.strings_or("observables", observable_names(), {});
  const bool gp = s.model == "gaussian_process";
  const char* gp_only[] = {"kernel", "mean", "nugget", "starts", "seed"};
  if (gp) {
    if (t.contains("degree")) t.fail("degree", "applies only to model = \"polynomial\"");
    s.kernel = surrogate::covariance_kernel_from_string(
        t.choice_or("kernel", {"matern52", "squared_exponential"}, "matern52"));
    s.mean = surrogate::mean_function_from_string(
        t.choice_or("mean", {"constant", "linear"}, "constant"));
    s.nugget = t.choice_or("nugget", {"replicates", "estimated", "none"}, "replicates");
    s.starts = static_cast<int>(t.integer_or("starts", 8, 1, 100));
    s.seed = static_cast<std::uint64_t>(
        t.integer_or("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  } else {
    for (const char* k : gp_only)
      if (t.contains(k)) t.fail(k, "applies only to model = \"gaussian_process\"");
    s.degree = static_cast<int>(t.integer_or("degree", 0, 0, 4));
  }
  t.finish();
  return c;
}

}  // namespace demcal::config
