#pragma once
// Saving and loading fitted surrogates as JSON, so that a calibration can reuse a surface
// fitted once from expensive DEM runs. Every number the model uses is stored (coefficients,
// hyperparameters, scaling, training data) and doubles are written in shortest round-trip
// form, so a loaded model predicts bit-for-bit what the saved one did (within one build;
// the GP refactorizes its covariance on load).
//
// Files carry "format": "demcal.surrogate", "version": 1 and "kind"; fields marked
// informational (term names, standard errors, hyperparameters in input units) are written
// for readers and ignored on load.

#include "surrogate/gaussian_process.hpp"
#include "surrogate/polynomial_surface.hpp"
#include "surrogate/surrogate_model.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>

namespace demcal::surrogate {

nlohmann::json to_json(const PolynomialSurface& model);
nlohmann::json to_json(const GaussianProcess& model);
// Dispatches on kind(); throws std::invalid_argument for a model kind it does not know.
nlohmann::json to_json(const SurrogateModel& model);

// Throw std::invalid_argument naming the missing or malformed key, or the wrong kind.
PolynomialSurface polynomial_surface_from_json(const nlohmann::json& j);
GaussianProcess gaussian_process_from_json(const nlohmann::json& j);
std::unique_ptr<SurrogateModel> surrogate_from_json(const nlohmann::json& j);

// Throw std::runtime_error naming the path when it cannot be written or read, and
// std::invalid_argument naming the path and key when the content is not a surrogate.
void save_surrogate(const SurrogateModel& model, const std::filesystem::path& path);
std::unique_ptr<SurrogateModel> load_surrogate(const std::filesystem::path& path);

}  // namespace demcal::surrogate
