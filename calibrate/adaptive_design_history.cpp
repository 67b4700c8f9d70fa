#include "calibrate/adaptive_design_history.hpp"

#include "calibrate/detail/number_text.hpp"

namespace demcal::calibrate {

const char* to_string(AdaptiveDesignStatus status) {
  switch (status) {
    case AdaptiveDesignStatus::running:
      return "running";
    case AdaptiveDesignStatus::converged:
      return "converged";
    case AdaptiveDesignStatus::budget_exhausted:
      return "budget_exhausted";
    case AdaptiveDesignStatus::out_of_range:
      return "out_of_range";
    case AdaptiveDesignStatus::no_candidates:
      return "no_candidates";
  }
  return "unknown";
}

std::string AdaptiveDesignHistory::to_text(const std::vector<std::string>& names) const {
  using detail::fmt;
  std::string s;
  for (const auto& b : batches) {
    s += "batch " + std::to_string(b.index) + ": " + std::to_string(b.runs.size()) + " runs";
    for (const auto& r : b.runs) {
      s += "\n  (";
      for (std::size_t j = 0; j < r.theta.size(); ++j)
        s += (j ? ", " : "") + (j < names.size() ? names[j] + " = " : "") + fmt(r.theta[j], 4);
      s += ") replicate " + std::to_string(r.replicate) + ", " + r.reason;
      if (r.acquisition == r.acquisition) s += ", acquisition " + fmt(r.acquisition, 3);
    }
    if (!b.complete) {
      s += "\n  not complete\n";
      continue;
    }
    s += "\n  after it: " + std::to_string(b.runs_total) + " runs, 95 % region area " +
         fmt(b.region_area, 4) + (b.region_resolved ? "" : " (not resolved)") + ", best point (";
    for (std::size_t j = 0; j < b.best_point.size(); ++j)
      s += (j ? ", " : "") + fmt(b.best_point[j], 4);
    s += "), chi^2 " + fmt(b.best_chi_squared, 3) + ", area change " + fmt(b.area_change, 2) +
         ", posterior-mean move " + fmt(b.point_move, 2) + " of the extent, surrogate variance " +
         fmt(b.surrogate_variance_ratio, 2) +
         " of the noise (another batch expected to shrink the area by " +
         fmt(b.expected_area_gain, 2) + "), scatter dof " +
         std::to_string(b.scatter_degrees_of_freedom) +
         (b.unconfirmed_parts > 0 ? ", " + std::to_string(b.unconfirmed_parts) +
                                        (b.unconfirmed_parts == 1 ? " part" : " parts") +
                                        " of the region without a design point"
                                  : "") +
         (b.stable ? ", stable" : "") + (b.chi_squared_too_large ? ", chi^2 too large" : "") + "\n";
  }
  return s + "status " + to_string(status) + ": " + statement + "\n";
}

nlohmann::json AdaptiveDesignHistory::to_json() const {
  using detail::number_json;
  nlohmann::json j;
  j["status"] = to_string(status);
  j["statement"] = statement;
  j["runs_done"] = runs_done;
  j["batches"] = nlohmann::json::array();
  for (const auto& b : batches) {
    nlohmann::json jb;
    jb["index"] = b.index;
    jb["complete"] = b.complete;
    jb["runs"] = nlohmann::json::array();
    for (const auto& r : b.runs)
      jb["runs"].push_back({{"slot", r.slot},
                            {"theta", r.theta},
                            {"replicate", r.replicate},
                            {"seed", r.seed},
                            {"reason", r.reason},
                            {"acquisition", number_json(r.acquisition)}});
    if (b.complete) {
      jb["runs_total"] = b.runs_total;
      jb["region_area"] = number_json(b.region_area);
      jb["region_resolved"] = b.region_resolved;
      jb["best_point"] = b.best_point;
      jb["posterior_mean"] = b.posterior_mean;
      jb["best_chi_squared"] = number_json(b.best_chi_squared);
      jb["area_change"] = number_json(b.area_change);
      jb["point_move"] = number_json(b.point_move);
      jb["surrogate_variance_ratio"] = number_json(b.surrogate_variance_ratio);
      jb["expected_area_gain"] = number_json(b.expected_area_gain);
      jb["scatter_degrees_of_freedom"] = b.scatter_degrees_of_freedom;
      jb["unconfirmed_parts"] = b.unconfirmed_parts;
      jb["stable"] = b.stable;
      jb["chi_squared_too_large"] = b.chi_squared_too_large;
    }
    j["batches"].push_back(jb);
  }
  return j;
}

}  // namespace demcal::calibrate
