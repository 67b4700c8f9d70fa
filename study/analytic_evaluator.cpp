#include "study/analytic_evaluator.hpp"

#include "config/toml_reader.hpp"

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <utility>

namespace demcal::study {
namespace {

// A number of the resolved study, `fallback` when the key is absent.
double number_at(const config::StudyConfig& study, const std::string& key, double fallback) {
  const toml::node_view<const toml::node> node = study.resolved.at_path(key);
  if (!node) return fallback;
  if (const std::optional<double> v = node.value<double>()) return *v;
  throw config::ConfigError(study.file + ": " + key +
                            ": the analytic evaluator expected a number");
}

// FNV-1a: a portable hash of the apparatus' name, so that setups draw apart.
std::uint64_t name_hash(const std::string& s) {
  std::uint64_t h = 1469598103934665603ULL;
  for (const unsigned char c : s) h = (h ^ c) * 1099511628211ULL;
  return h;
}

// Standard normal draws, the same on every platform (std::normal_distribution's
// algorithm is the library's choice): mt19937_64 words, 53-bit uniforms, Box-Muller.
constexpr double kTwoPi = 6.283185307179586476925286766559;

class PortableNormal {
 public:
  explicit PortableNormal(std::uint64_t seed) : words_(seed) {}
  double operator()() {
    const double u1 = (static_cast<double>(words_() >> 11) + 1.0) * 0x1.0p-53;  // (0, 1]
    const double u2 = static_cast<double>(words_() >> 11) * 0x1.0p-53;          // [0, 1)
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
  }

 private:
  std::mt19937_64 words_;
};

struct Inputs {
  double mu_r = 0.0, mu_s = 0.0, mu_w = 0.0, gamma = 0.0, drag = 0.0, spread = 0.0;
  double density_kg_m3 = 0.0;
  double wall_weight = 0.0;  // w: 1 / thickness_diameters between walls, else 0
  bool sandglass = false;
};

class AnalyticRun final : public PreparedRun {
 public:
  AnalyticRun(Inputs in, AnalyticEvaluatorOptions options, std::uint64_t seed,
              const dem::Simulation& simulation, const dem::StepObserver& observe)
      : in_(in), options_(options), seed_(seed), simulation_(simulation), observe_(observe) {}

  dem::ApparatusResult run() override {
    // The observer may cancel the run, as it may a DEM run.
    observe_(simulation_, "analytic");
    PortableNormal normal(seed_);
    const double w = in_.wall_weight;
    dem::ApparatusResult r;
    r.observables["angle_of_repose_deg"] =
        15.0 + 25.0 * std::tanh(2.5 * in_.mu_r) + 12.0 * in_.mu_s + 20.0 * w * in_.mu_w +
        4000.0 * in_.gamma * (1.0 + 6.0 * w) - 0.5 * in_.drag + options_.aor_noise_deg * normal();
    const double packing = 0.62 - 0.06 * in_.mu_s - 0.04 * std::tanh(3.0 * in_.mu_r) - 0.05 * w -
                           60.0 * in_.gamma + 0.03 * in_.spread;
    r.observables["bulk_density_kg_m3"] =
        in_.density_kg_m3 * packing * (1.0 + options_.bulk_density_relative_noise * normal());
    if (in_.sandglass)
      r.observables["discharge_time_s"] =
          2.0 * (1.0 + 0.8 * in_.mu_s + 0.5 * in_.mu_r + 200.0 * in_.gamma + 0.2 * in_.drag) *
          (1.0 + options_.discharge_relative_noise * normal());
    r.details["evaluator"] = "analytic";
    return r;
  }

  void describe(nlohmann::json& record) const override {
    record["evaluator"] = {{"kind", "analytic"},
                           {"header", "study/analytic_evaluator.hpp"},
                           {"aor_noise_deg", options_.aor_noise_deg},
                           {"bulk_density_relative_noise", options_.bulk_density_relative_noise},
                           {"discharge_relative_noise", options_.discharge_relative_noise}};
  }

 private:
  Inputs in_;
  AnalyticEvaluatorOptions options_;
  std::uint64_t seed_;
  const dem::Simulation& simulation_;  // the apparatus' (never stepped)
  const dem::StepObserver& observe_;
};

}  // namespace

AnalyticEvaluator::AnalyticEvaluator(AnalyticEvaluatorOptions options)
    : options_(std::move(options)) {}

std::unique_ptr<PreparedRun> AnalyticEvaluator::prepare(const RunRequest& r) const {
  const config::StudyConfig& s = r.study;
  Inputs in;
  in.mu_r = number_at(s, "interaction.particle_particle.rolling_friction", 0.0);
  in.mu_s = number_at(s, "interaction.particle_particle.sliding_friction", 0.0);
  in.mu_w = number_at(s, "interaction.particle_wall.sliding_friction", 0.0);
  in.gamma = number_at(s, "interaction.particle_particle.surface_energy_j_m2", 0.0);
  in.drag = number_at(s, "air.drag_scale", 0.0);
  in.spread = number_at(s, "material.size.relative_half_width", 0.0);
  in.density_kg_m3 = number_at(s, "material.density_kg_m3", 0.0);
  const std::string table = "apparatus." + r.apparatus.name;
  const toml::node_view<const toml::node> boundary = s.resolved.at_path(table + ".boundary");
  if (boundary.value<std::string>().value_or("") == "walls") {
    const double thickness = number_at(s, table + ".thickness_diameters", 1.0);
    if (!(thickness > 0.0))
      throw config::ConfigError(s.file + ": " + table +
                                ".thickness_diameters: the analytic evaluator expected a number > 0");
    in.wall_weight = 1.0 / thickness;
  }
  in.sandglass = r.apparatus.kind == "sandglass";
  return std::make_unique<AnalyticRun>(in, options_, r.seed ^ name_hash(r.apparatus.name),
                                       r.apparatus.apparatus->simulation(), r.observe);
}

}  // namespace demcal::study
