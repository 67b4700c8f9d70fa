#include "config/surrogate_config.hpp"

#include "config/models/surrogate_models.hpp"
#include "config/observables.hpp"

#include <algorithm>

namespace demcal::config {

std::optional<SurrogateConfig> read_surrogate(reader::Table& root) {
  if (!root.has("surrogate")) return std::nullopt;
  reader::Table t = root.table("surrogate");
  SurrogateConfig c;
  auto& s = c.spec;
  const SurrogateRegistry& models = surrogate_models();
  s.model = t.choice_or("model", models.names(), "gaussian_process");
  // Left out: every stable observable with data. Written empty, as candidates = [] of
  // [diagnosis], it asks for no surrogate at all, which no later stage can use.
  const bool observables_given = t.contains("observables");
  c.observables = t.strings_or("observables", observable_names(), {});
  if (observables_given && c.observables.empty())
    t.fail("observables",
           "expected at least one of " + reader::quoted_list(observable_names()) +
               " (leave the key out for every observable the design table measures)");
  // Another model's keys would silently do nothing: refused at the key.
  const SurrogateRegistry::Entry& chosen = models.at(s.model);
  const auto mine = [&](const std::string& key) {
    return std::any_of(chosen.info.keys.begin(), chosen.info.keys.end(),
                       [&](const ModelKey& k) { return k.key == key; });
  };
  for (const auto& other : models.entries())
    for (const ModelKey& k : other.info.keys)
      if (&other != &chosen && !mine(k.key) && t.contains(k.key))
        t.fail(k.key, "applies only to model = \"" + other.info.name + "\"");
  chosen.model(t, s);
  t.finish();
  return c;
}

}  // namespace demcal::config
