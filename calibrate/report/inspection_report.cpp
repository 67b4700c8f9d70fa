#include "calibrate/report/inspection_report.hpp"

#include "calibrate/report/figures.hpp"
#include "calibrate/report/html_report.hpp"
#include "calibrate/report/labels.hpp"
#include "calibrate/report/sobol_figure.hpp"
#include "surrogate/gaussian_process.hpp"
#include "surrogate/polynomial_surface.hpp"
#include "surrogate/sobol_indices.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace demcal::calibrate {
namespace {

namespace fs = std::filesystem;

std::string num(double v, int precision = 4) { return format_number(v, precision); }

std::string label_of(const std::string& observable) { return observable_label(observable); }

// The design points of one surrogate's map, one marker per number of runs that gave a
// value there (the legend says how many), crosses where none did.
struct DesignMarks {
  std::vector<PointSet> with_value;  // most runs first
  PointSet none{"design point where no run gave a value", {}, {}, "points pt 2 ps 1.3 lc rgb '#000000' lw 2"};
  std::vector<PointSet> sets() const {
    std::vector<PointSet> out = with_value;
    if (!none.x.empty()) out.push_back(none);
    return out;
  }
};

DesignMarks design_marks(const InspectedSurrogate& s) {
  std::vector<std::pair<std::pair<double, double>, int>> points;  // (x, y) -> runs with a value
  for (Eigen::Index i = 0; i < s.design_x.rows(); ++i) {
    const std::pair<double, double> xy{s.design_x(i, 0), s.design_x(i, 1)};
    const bool value = s.design_y.size() != s.design_x.rows() || std::isfinite(s.design_y(i));
    auto it = std::find_if(points.begin(), points.end(), [&](const auto& p) { return p.first == xy; });
    if (it == points.end()) points.push_back({xy, value ? 1 : 0});
    else it->second += value;
  }
  std::vector<int> counts;
  for (const auto& [xy, n] : points)
    if (n > 0 && std::find(counts.begin(), counts.end(), n) == counts.end()) counts.push_back(n);
  std::sort(counts.rbegin(), counts.rend());
  static const int marker[] = {6, 12, 8, 4, 10};
  DesignMarks m;
  for (std::size_t k = 0; k < counts.size(); ++k)
    m.with_value.push_back({"design point, " + std::to_string(counts[k]) + (counts[k] == 1 ? " run" : " runs") +
                                " with a value",
                            {}, {},
                            "points pt " + std::to_string(marker[std::min<std::size_t>(k, 4)]) +
                                " ps 1.2 lc rgb '#ff3030' lw 1.5"});
  for (const auto& [xy, n] : points) {
    PointSet& set = n == 0 ? m.none
                           : m.with_value[static_cast<std::size_t>(std::find(counts.begin(), counts.end(), n) -
                                                                    counts.begin())];
    set.x.push_back(xy.first);
    set.y.push_back(xy.second);
  }
  return m;
}

std::string stem_of(const InspectedSurrogate& s) { return s.setup + "_" + s.fit.output_name; }

void coefficient_section(HtmlReport& page, nlohmann::json& out, const InspectedSurrogate& s) {
  const auto* poly = dynamic_cast<const surrogate::PolynomialSurface*>(s.fit.model.get());
  const auto* gp = dynamic_cast<const surrogate::GaussianProcess*>(s.fit.model.get());
  if (poly) {
    const auto names = poly->term_names();
    const Eigen::VectorXd c = poly->coefficients();
    const Eigen::VectorXd se = poly->standard_errors();
    Eigen::VectorXd cu, seu;
    bool unscaled = true;
    try {
      cu = poly->unscaled_coefficients();
      seu = poly->unscaled_standard_errors();
    } catch (const std::logic_error&) {
      unscaled = false;
    }
    std::vector<std::vector<std::string>> rows;
    nlohmann::json terms = nlohmann::json::array();
    for (std::size_t i = 0; i < names.size(); ++i) {
      const auto k = static_cast<Eigen::Index>(i);
      const double t = se(k) > 0 ? c(k) / se(k) : std::nan("");
      rows.push_back({names[i], num(c(k)), num(se(k), 2), num(t, 3),
                      unscaled ? num(cu(k)) : "—", unscaled ? num(seu(k), 2) : "—"});
      terms.push_back({{"term", names[i]}, {"coefficient_scaled", c(k)}, {"standard_error_scaled", se(k)},
                       {"coefficient", unscaled ? nlohmann::json(cu(k)) : nlohmann::json()},
                       {"standard_error", unscaled ? nlohmann::json(seu(k)) : nlohmann::json()}});
    }
    page.table({"term", "coefficient (inputs scaled to [-1, 1])", "std. error", "t", "coefficient (physical units)",
                "std. error"},
               rows,
               "Polynomial coefficients of " + label_of(s.fit.output_name) + ", R² = " + num(poly->r_squared(), 4) +
                   ", adjusted R² = " + num(poly->adjusted_r_squared(), 4) + ", residual sigma = " +
                   num(poly->residual_sigma(), 3));
    out["coefficients"] = terms;
    out["r_squared"] = poly->r_squared();
    out["adjusted_r_squared"] = poly->adjusted_r_squared();
  } else if (gp) {
    const auto h = gp->hyperparameters();
    std::vector<std::vector<std::string>> rows;
    for (std::size_t i = 0; i < h.length_scales.size(); ++i)
      rows.push_back({"length scale of " + gp->input_names()[i], num(h.length_scales[i])});
    rows.push_back({"signal variance", num(h.signal_variance)});
    rows.push_back({"nugget", s.fit.spec.nugget == "estimated"    ? num(h.nugget_variance)
                              : s.fit.spec.nugget == "replicates" ? "from replicates (per point: pooled replicate "
                                                                    "variance / runs at the point)"
                                                                  : s.fit.spec.nugget});
    rows.push_back({"log marginal likelihood", num(gp->log_marginal_likelihood(), 6)});
    const Eigen::VectorXd beta = gp->mean_coefficients();
    for (Eigen::Index i = 0; i < beta.size(); ++i) rows.push_back({"mean coefficient " + std::to_string(i), num(beta(i))});
    page.table({"hyperparameter", "value"}, rows,
               "Gaussian process of " + label_of(s.fit.output_name) + " (" + surrogate_description(s.fit) + ")");
    out["hyperparameters"] = {{"length_scales", h.length_scales},
                              {"signal_variance", h.signal_variance},
                              {"nugget_variance", h.nugget_variance},
                              {"log_marginal_likelihood", gp->log_marginal_likelihood()}};
  }
}

}  // namespace

std::string surrogate_description(const surrogate::FittedSurrogate& f) {
  std::string d = f.model->description();
  const auto k = d.find("nugget fixed");
  if (k != std::string::npos && f.spec.nugget == "replicates") d.replace(k, 12, "nugget from replicates");
  return d;
}

InspectionReportFiles write_inspection_report(const fs::path& dir, const std::vector<InspectedSurrogate>& surrogates,
                                              const InspectionReportOptions& o) {
  const std::size_t p = o.parameter_names.size();
  if (o.lower.size() != p || o.upper.size() != p)
    throw std::invalid_argument("inspection report: bounds do not match the parameters");
  fs::create_directories(dir);
  InspectionReportFiles files;
  files.html = dir / "index.html";
  files.json = dir / "inspection.json";
  HtmlReport page("Surrogate inspection — " + o.study_name);
  nlohmann::json summary;
  summary["study"] = o.study_name;
  summary["parameters"] = o.parameter_names;
  summary["lower"] = o.lower;
  summary["upper"] = o.upper;

  page.paragraph(
      "Each surrogate below stands in for the DEM in the calibration. Leave-one-out (LOO) "
      "predicts every design point from a model fitted without it; a surrogate is trustworthy "
      "where its LOO error is no larger than the DEM's own run-to-run scatter, measured from the "
      "replicates (a scatter measured from few replicates is allowed its 95 % upper confidence "
      "bound: it may have come out low).");
  std::vector<std::vector<std::string>> rows;
  for (const auto& s : surrogates) {
    const auto& f = s.fit;
    rows.push_back({s.setup, label_of(f.output_name), surrogate_description(f), std::to_string(f.runs),
                    std::to_string(f.scatter.points), num(f.scatter.sd, 3), num(f.validation.rmse, 3),
                    num(f.validation.q_squared, 4), num(f.validation.max_abs_standardized_residual, 3),
                    f.scatter_check.within_scatter ? "yes" : "NO"});
    if (!f.scatter_check.within_scatter) {
      page.warning(humanize_identifiers(f.scatter_check.message));
      files.warnings.push_back(humanize_identifiers(f.scatter_check.message));
    }
  }
  page.table({"setup", "observable", "model", "runs", "points", "DEM scatter (sd)", "LOO RMSE", "Q²",
              "max |std. residual|", "within scatter"},
             rows, "Summary");

  for (const auto& s : surrogates) {
    const auto& f = s.fit;
    const std::string stem = stem_of(s);
    const std::string label = label_of(f.output_name);
    nlohmann::json entry = f.to_json();
    entry.erase("model");
    entry["setup"] = s.setup;
    page.heading(s.setup + ": " + label);
    page.paragraph(humanize_identifiers(f.scatter_check.message));

    if (p == 2) {
      const int n = std::max(11, o.map_points_per_axis);
      GridField mean, sd;
      for (int i = 0; i < n; ++i) {
        mean.x.push_back(o.lower[0] + (o.upper[0] - o.lower[0]) * i / (n - 1));
        mean.y.push_back(o.lower[1] + (o.upper[1] - o.lower[1]) * i / (n - 1));
      }
      Eigen::MatrixXd pts(n * n, 2);
      for (int iy = 0; iy < n; ++iy)
        for (int ix = 0; ix < n; ++ix) pts.row(iy * n + ix) << mean.x[ix], mean.y[iy];
      const auto pred = f.model->predict(pts);
      sd.x = mean.x;
      sd.y = mean.y;
      for (Eigen::Index i = 0; i < pred.mean.size(); ++i) {
        mean.values.push_back(pred.mean(i));
        sd.values.push_back(std::sqrt(std::max(0.0, pred.variance(i))));
      }
      const DesignMarks marks = design_marks(s);
      const std::string xl = parameter_label(o.parameter_names[0]), yl = parameter_label(o.parameter_names[1]);
      const auto map = map_figure(dir, stem + "_map", mean, {}, marks.sets(),
                                  {label + ", surrogate mean", xl, yl, label, 10, "viridis", 520, 470, true, 0, 0, {}});
      std::string cap = "Surrogate mean of " + label + " over the design box; the markers say how many runs gave a "
                        "value at each design point";
      if (!marks.none.x.empty())
        cap += ", crosses: " + std::to_string(marks.none.x.size()) + " design point" +
               (marks.none.x.size() == 1 ? "" : "s") + " where no run gave a value (the surrogate extrapolates "
               "there: do not read the map near them)";
      page.figure(map.svg, cap + ".", map.data_files);
      const auto sdmap = map_figure(dir, stem + "_sd", sd, {}, marks.sets(),
                                    {label + ", surrogate sd", xl, yl, "sd of the mean (" + label + ")", 10, "viridis", 520, 470,
                                     true, 0, 0, {}});
      page.figure(sdmap.svg,
                  "The surrogate's own standard deviation: small at the design points, larger between and "
                  "beyond them. Calibration adds it to the measurement noise.",
                  sdmap.data_files);
    } else {
      page.paragraph("Maps are drawn for two parameters; this study has " + std::to_string(p) + ".");
    }

    std::vector<double> obs, mu, sdv, std_res;
    for (Eigen::Index i = 0; i < f.loo.observed.size(); ++i) {
      obs.push_back(f.loo.observed(i));
      mu.push_back(f.loo.mean(i));
      sdv.push_back(std::sqrt(std::max(0.0, f.loo.variance(i))));
      std_res.push_back(i < f.validation.standardized_residuals.size() ? f.validation.standardized_residuals(i)
                                                                        : std::nan(""));
    }
    const auto parity = parity_figure(dir, stem + "_parity", obs, mu, sdv, label + ": leave-one-out", label);
    page.figure(parity.svg,
                "Leave-one-out parity: each design point predicted by the surrogate fitted without it (bars: "
                "±2 sd of the prediction). Q² = " + num(f.validation.q_squared, 4) + ", RMSE = " +
                    num(f.validation.rmse, 3) + ".",
                parity.data_files);
    const auto resid = residual_figure(dir, stem + "_residuals", mu, std_res, label + ": standardized residuals",
                                       "leave-one-out prediction, " + label);
    page.figure(resid.svg,
                "Standardized LOO residuals (observed − predicted) / sd: about 95 % should lie within ±2 when the "
                "surrogate's variance is honest.",
                resid.data_files);
    if (!f.degrees_tried.empty()) {
      std::vector<std::vector<std::string>> drows;
      for (std::size_t i = 0; i < f.degrees_tried.size(); ++i)
        drows.push_back({std::to_string(f.degrees_tried[i]), num(f.degree_cv_rmse[i], 4)});
      page.table({"total degree", "LOO RMSE"}, drows, "Degree chosen by leave-one-out cross-validation");
    }
    coefficient_section(page, entry, s);
    if (s.companion_polynomial) {
      InspectedSurrogate poly{s.setup, *s.companion_polynomial, s.design_x, s.design_y, std::nullopt};
      nlohmann::json pe;
      page.paragraph("For comparison, the regression equation the seed paper would fit: a polynomial of total degree " +
                     std::to_string(dynamic_cast<const surrogate::PolynomialSurface&>(*poly.fit.model).degree()) +
                     " chosen by leave-one-out (LOO RMSE " + num(poly.fit.validation.rmse, 3) + ", Q² " +
                     num(poly.fit.validation.q_squared, 4) + "). It is shown, not used by the calibration.");
      coefficient_section(page, pe, poly);
      entry["companion_polynomial"] = pe;
      entry["companion_polynomial"]["loo_rmse"] = poly.fit.validation.rmse;
    }

    nlohmann::json box_numbers;
    const auto bars = sobol_figure(dir, stem + "_sobol", *f.model, o.parameter_names, o.lower, o.upper,
                                   label + ": Sobol indices, whole box", o.sobol_base_samples, box_numbers);
    page.figure(bars.svg,
                "Sobol indices of the surrogate over the design box (uniform inputs): the share of the variance of " +
                    label + " due to each parameter alone (first order) and with its interactions (total); bars: "
                            "95 % bootstrap half-width.",
                bars.data_files);
    entry["sobol"] = box_numbers;
    // Over the part of the box the runs measured: a strip where no run gave a value (piles
    // that spread flat) is extrapolation, and its variance would dominate the indices.
    if (p >= 1 && s.design_y.size() == s.design_x.rows()) {
      std::vector<double> lo(p, std::numeric_limits<double>::infinity()), hi(p, -std::numeric_limits<double>::infinity());
      // A design point counts when at least half of its runs gave a value.
      for (Eigen::Index i = 0; i < s.design_x.rows(); ++i) {
        int runs = 0, values = 0;
        for (Eigen::Index k = 0; k < s.design_x.rows(); ++k)
          if (s.design_x.row(k) == s.design_x.row(i)) {
            ++runs;
            values += std::isfinite(s.design_y(k));
          }
        if (2 * values < runs) continue;
        for (std::size_t j = 0; j < p; ++j) {
          lo[j] = std::min(lo[j], s.design_x(i, static_cast<Eigen::Index>(j)));
          hi[j] = std::max(hi[j], s.design_x(i, static_cast<Eigen::Index>(j)));
        }
      }
      bool smaller = false, valid = true;
      for (std::size_t j = 0; j < p; ++j) {
        valid = valid && hi[j] > lo[j];
        smaller = smaller || lo[j] > o.lower[j] + 1e-12 || hi[j] < o.upper[j] - 1e-12;
      }
      if (valid && smaller) {
        nlohmann::json sub;
        const auto b2 = sobol_figure(dir, stem + "_sobol_measured", *f.model, o.parameter_names, lo, hi,
                                     label + ": Sobol indices where runs gave a value", o.sobol_base_samples, sub);
        page.figure(b2.svg,
                    "The same over the part of the box where most runs gave a value (" + box_text(o.parameter_names, lo, hi) +
                        "): outside it the surrogate extrapolates, and that strip's variance would dominate the "
                        "indices above. The calibration report gives them over the 95 % region too.",
                    b2.data_files);
        entry["sobol_measured_box"] = sub;
      }
    }
    summary["surrogates"].push_back(entry);
  }
  page.write(files.html);
  write_text_atomically(files.json, summary.dump(1) + "\n");
  return files;
}

}  // namespace demcal::calibrate
