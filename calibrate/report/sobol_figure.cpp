#include "calibrate/report/sobol_figure.hpp"

#include "calibrate/report/labels.hpp"
#include "surrogate/sobol_indices.hpp"

namespace demcal::calibrate {

RenderedFigure sobol_figure(const std::filesystem::path& directory, const std::string& name,
                            const surrogate::SurrogateModel& model,
                            const std::vector<std::string>& parameter_names,
                            const std::vector<double>& lower, const std::vector<double>& upper,
                            const std::string& title, std::size_t base_samples,
                            nlohmann::json& numbers) {
  surrogate::SobolOptions so;
  so.base_samples = base_samples;
  so.bootstrap_resamples = 100;
  const auto si = surrogate::sobol_indices(model, lower, upper, so);
  std::vector<double> e1, et;
  for (std::size_t i = 0; i < parameter_names.size(); ++i) {
    e1.push_back(si.first_order_upper.empty()
                     ? 0.0
                     : 0.5 * (si.first_order_upper[i] - si.first_order_lower[i]));
    et.push_back(si.total_upper.empty() ? 0.0 : 0.5 * (si.total_upper[i] - si.total_lower[i]));
  }
  numbers = {{"lower", lower},
             {"upper", upper},
             {"first_order", si.first_order},
             {"total", si.total},
             {"variance", si.variance}};
  return bar_figure(directory, name, parameter_names,
                    {{"first order", si.first_order, e1}, {"total", si.total, et}}, title,
                    "share of the variance");
}

std::string box_text(const std::vector<std::string>& names, const std::vector<double>& lower,
                     const std::vector<double>& upper) {
  std::string s;
  for (std::size_t i = 0; i < names.size() && i < lower.size() && i < upper.size(); ++i)
    s += (i ? ", " : "") + names[i] + " " + human_number(lower[i]) + "–" + human_number(upper[i]);
  return s;
}

}  // namespace demcal::calibrate
