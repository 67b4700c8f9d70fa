#pragma once
// Sobol indices of a surrogate over a box, as a bar figure with its CSV: used over the
// whole design box, over the part the runs measured (inspection report) and over the
// 95 % region's box (calibration report) — where the indices matter.

#include "calibrate/report/figures.hpp"
#include "surrogate/surrogate_model.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace demcal::calibrate {

// `numbers` receives {"lower", "upper", "first_order", "total", "variance"}.
RenderedFigure sobol_figure(const std::filesystem::path& directory, const std::string& name,
                            const surrogate::SurrogateModel& model,
                            const std::vector<std::string>& parameter_names,
                            const std::vector<double>& lower, const std::vector<double>& upper,
                            const std::string& title, std::size_t base_samples,
                            nlohmann::json& numbers);

// "mu_r 0.05–0.6, mu_s 0.375–0.9"
std::string box_text(const std::vector<std::string>& names, const std::vector<double>& lower,
                     const std::vector<double>& upper);

}  // namespace demcal::calibrate
