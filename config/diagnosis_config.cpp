#include "config/diagnosis_config.hpp"

#include "config/physics_candidates.hpp"

namespace demcal::config {

std::optional<DiagnosisConfig> read_diagnosis(reader::Table& root,
                                              const std::vector<std::string>& setups) {
  if (!root.has("diagnosis")) return std::nullopt;
  reader::Table t = root.table("diagnosis");
  DiagnosisConfig c;
  c.line = t.line();
  const std::vector<std::string> names = physics_candidate_names();
  c.candidates = t.strings_or("candidates", names, names);
  if (c.candidates.empty())
    t.fail("candidates", "expected at least one of " + reader::quoted_list(names));
  c.alpha = t.number_or("alpha", 0.01, reader::between(0, true, 0.5, true));
  c.hold_out = t.strings_or("hold_out", setups, {});
  if (c.hold_out.size() >= setups.size() && !setups.empty())
    t.fail("hold_out", "holds out every setup; at least one must be fitted");
  c.probe_replicates = static_cast<int>(t.integer_or("probe_replicates", 2, 1, 100));
  c.leading = static_cast<int>(t.integer_or("leading", 2, 1, 10));
  c.extended_points = static_cast<int>(t.integer_or("extended_points", 16, 4, 10000));
  c.design_extensions = static_cast<int>(t.integer_or("design_extensions", 2, 0, 10));
  c.probe_grid = static_cast<int>(t.integer_or("probe_grid", 200, 2, 100000));
  // One evidence margin decides both whether a candidate beats the base model and whether it
  // beats the generic discrepancy; the Bayes-factor key it replaced set only the first.
  if (t.contains("bayes_factor_threshold"))
    t.fail("bayes_factor_threshold",
           "was replaced by required_log_bayes_factor (a natural-log Bayes factor that a "
           "candidate must reach over both the base model and the generic discrepancy; 3 = a "
           "factor of 20, ln(10) = 2.3 the old default of 10)");
  c.required_log_bayes_factor =
      t.number_or("required_log_bayes_factor", 3.0, reader::between(0, false, 50, false));
  for (const auto& name : names) {
    if (!t.has(name)) continue;
    reader::Table r = t.table(name);
    CandidateRange range;
    if (r.has("lower")) range.lower = r.number("lower", reader::any_number());
    if (r.has("upper")) range.upper = r.number("upper", reader::any_number());
    if (r.has("probe")) range.probe = r.number("probe", reader::any_number());
    if (range.lower && range.upper && !(*range.upper > *range.lower))
      r.fail("upper", "expected a number > lower (" + reader::format_number(*range.lower) + ")");
    r.finish();
    c.ranges[name] = range;
  }
  t.finish();
  return c;
}

}  // namespace demcal::config
