#include "config/diagnosis_config.hpp"

#include "config/physics_candidates.hpp"

namespace demcal::config {

std::optional<DiagnosisConfig> read_diagnosis(
    reader::Table& root, const std::vector<std::string>& setups,
    const std::vector<surrogate::ParameterRange>& design) {
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
  c.candidate_refinements = static_cast<int>(t.integer_or("candidate_refinements", 0, 0, 5));
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
  if (t.has("plausible")) {
    reader::Table r = t.table("plausible");
    std::vector<std::string> known;
    for (const auto& p : design) known.push_back(p.name);
    if (design.empty())
      t.fail("plausible", "the study has no [design]: there are no design parameters to bound");
    for (const auto& p : design) {
      if (!r.has(p.name)) continue;
      const std::vector<double> v = r.numbers_or_empty(p.name);
      if (v.size() != 2)
        r.fail(p.name, "expected [lower, upper], two numbers, got " + std::to_string(v.size()));
      if (!(v[1] > v[0]))
        r.fail(p.name, "expected upper > lower, got [" + reader::format_number(v[0]) + ", " +
                           reader::format_number(v[1]) + "]");
      // The design's own box must be plausible: a range narrower than the box would say the
      // design already runs values the material cannot have.
      if (v[0] > p.lower || v[1] < p.upper)
        r.fail(p.name, "[" + reader::format_number(v[0]) + ", " + reader::format_number(v[1]) +
                           "] does not enclose the design's range of " + p.name + " [" +
                           reader::format_number(p.lower) + ", " + reader::format_number(p.upper) +
                           "]; expected a plausible range that holds the design's box");
      c.plausible[p.name] = {v[0], v[1]};
    }
    r.finish();
  }
  t.finish();
  return c;
}

}  // namespace demcal::config
