#include "study/derived_study.hpp"

#include "config/design_config.hpp"

#include <sstream>

namespace demcal::study {

std::vector<DerivedParameter> base_design_parameters(const config::DesignConfig& design) {
  std::vector<DerivedParameter> out;
  const auto& params = design.spec.parameters;
  for (std::size_t i = 0; i < params.size(); ++i)
    out.push_back({params[i].name, params[i].lower, params[i].upper,
                   i < design.tied_paths.size() ? design.tied_paths[i]
                                                : std::vector<std::string>{}});
  return out;
}

std::string derived_study_text(const DerivedStudyFile& file) {
  using config::shortest_decimal;
  using config::toml_key_text;
  std::ostringstream s;
  for (const std::string& line : file.header) s << "# " << line << "\n";
  s << toml::toml_formatter(file.study) << "\n\n[design]\n";
  const DerivedDesignTable& d = file.design;
  s << "kind = \"" << d.kind << "\"\n";
  if (d.points) s << "points = " << *d.points << "\n";
  s << "replicates = " << d.replicates << "\n";
  if (d.seed) s << "seed = " << *d.seed << "\n";
  if (!d.values.empty()) {
    s << "values = [";
    for (std::size_t r = 0; r < d.values.size(); ++r) {
      s << (r == 0 ? "[" : ", [");
      for (std::size_t k = 0; k < d.values[r].size(); ++k)
        s << (k == 0 ? "" : ", ") << shortest_decimal(d.values[r][k]);
      s << "]";
    }
    s << "]\n";
  }
  s << "parameters = { ";
  for (std::size_t i = 0; i < d.parameters.size(); ++i) {
    const DerivedParameter& p = d.parameters[i];
    s << (i == 0 ? "" : ", ") << toml_key_text(p.key)
      << " = { lower = " << shortest_decimal(p.lower) << ", upper = " << shortest_decimal(p.upper);
    if (!p.also_sets.empty()) {
      s << ", also_sets = [";
      for (std::size_t k = 0; k < p.also_sets.size(); ++k)
        s << (k == 0 ? "" : ", ") << '"' << p.also_sets[k] << '"';
      s << "]";
    }
    s << " }";
  }
  s << " }\n";
  return s.str();
}

}  // namespace demcal::study
