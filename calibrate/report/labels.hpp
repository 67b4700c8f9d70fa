#pragma once
// What the reports and the console call each observable and parameter: a
// reader meets "angle of repose (°)", not "angle_of_repose_deg". The
// observables' labels are views of the one registry, io/observable_registry.hpp.
// Numbers are written as people write them (significant digits, round-off
// zeros as 0).

#include <string>

namespace demcal::calibrate {

// "angle_of_repose_deg" -> "angle of repose (°)"; an unknown name is returned as it is.
std::string observable_label(const std::string& observable);
// "angle_of_repose_deg" -> "angle of repose"
std::string observable_name(const std::string& observable);
// "angle_of_repose_deg" -> "AoR"; "discharge_time_s" -> "time"; else observable_name().
std::string observable_short(const std::string& observable);
// "°", " s", " kg/s", ...: appended directly to a number ("30.96°", "0.554 s"); "" when unknown.
std::string observable_unit_suffix(const std::string& observable);
// "mu_r" -> "rolling friction mu_r"; an unknown name as it is.
std::string parameter_label(const std::string& parameter);

// Every known observable identifier in `text` written as its label, quoted or not:
// "surrogate for 'angle_of_repose_deg'" -> "surrogate for angle of repose (°)".
std::string humanize_identifiers(std::string text);

// A sentence of the solver's for a reader: identifiers as labels, "chi^2" as "chi²",
// "+/-" as "±", round-off numbers (1.39e-27: an exponent of -10 or below) as 0.
std::string humanize_sentence(std::string text);

// `digits` significant digits ("%.*g"), no trailing zeros; |v| < zero_below -> "0";
// not finite -> "—".
std::string human_number(double v, int digits = 3, double zero_below = 1e-12);
// "30.96°", "0.554 s"
std::string observable_value(const std::string& observable, double v, int digits = 4);

}  // namespace demcal::calibrate
