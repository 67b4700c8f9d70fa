#pragma once
// Internal to calibrate/: how numbers appear in the sentences and JSON the
// statistics write (one rule for all of them, so a report never shows one
// value two ways).

#include <nlohmann/json.hpp>

#include <string>

namespace demcal::calibrate::detail {

// printf's "%.*g" with `digits` significant digits; "n/a" for NaN.
std::string fmt(double x, int digits = 3);

// The number, or null when it is not finite (JSON has no NaN or infinity).
nlohmann::json number_json(double x);

}  // namespace demcal::calibrate::detail
