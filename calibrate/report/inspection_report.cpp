#include "calibrate/report/inspection_report.hpp"

#include "calibrate/report/figures.hpp"
#include "calibrate/report/html_report.hpp"
#include "surrogate/gaussian_process.hpp"
#include "surrogate/polynomial_surface.hpp"
#include "surrogate/sobol_indices.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace demcal::calibrate {
namespace {

namespace fs = std::filesystem;

std::string num(double v, int precision = 4) { return format_number(v, precision); }

// "angle_of_repose_deg" -> "AoR (deg)": figure labels a reader recognises.
std::string label_of(const std::string& observable) {
  if (observable == "angle_of_repose_deg") return "angle of repose (deg)";
  if (observable == "discharge_time_s") return "discharge time (s)";
  if (observable == "mass_flow_rate_kg_s") return "mass flow rate (kg/s)";
  if (observable == "bulk_density_kg_m3") return "bulk density (kg/m3)";
  return observable;
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
    rows.push_back({"nugget", s.fit.spec.nugget == "estimated" ? num(h.nugget_variance)
                                                                : s.fit.spec.nugget + " (per point)"});
    rows.push_back({"log marginal likelihood", num(gp->log_marginal_likelihood(), 6)});
    const Eigen::VectorXd beta = gp->mean_coefficients();
    for (Eigen::Index i = 0; i < beta.size(); ++i) rows.push_back({"mean coefficient " + std::to_string(i), num(beta(i))});
    page.table({"hyperparameter", "value"}, rows,
               "Gaussian process of " + label_of(s.fit.output_name) + " (" + gp->description() + ")");
    out["hyperparameters"] = {{"length_scales", h.length_scales},
                              {"signal_variance", h.signal_variance},
                              {"nugget_variance", h.nugget_variance},
                              {"log_marginal_likelihood", gp->log_marginal_likelihood()}};
  }
}

}  // namespace

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
      "Each surrogate below stands in for the DEM in the calibration. Leave-one-out (LOO) predicts every "
      "design point from a model fitted without it; a surrogate is trustworthy where its LOO error is no "
      "larger than the DEM's own run-to-run scatter, measured from the replicates.");
  std::vector<std::vector<std::string>> rows;
  for (const auto& s : surrogates) {
    const auto& f = s.fit;
    rows.push_back({s.setup, label_of(f.output_name), f.model->description(), std::to_string(f.runs),
                    std::to_string(f.scatter.points), num(f.scatter.sd, 3), num(f.validation.rmse, 3),
                    num(f.validation.q_squared, 4), num(f.validation.max_abs_standardized_residual, 3),
                    f.scatter_check.within_scatter ? "yes" : "NO"});
    if (!f.scatter_check.within_scatter) {
      page.warning(f.scatter_check.message);
      files.warnings.push_back(f.scatter_check.message);
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
    page.paragraph(f.scatter_check.message);

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
      PointSet design{"design points", {}, {}};
      for (Eigen::Index i = 0; i < s.design_x.rows(); ++i) {
        design.x.push_back(s.design_x(i, 0));
        design.y.push_back(s.design_x(i, 1));
      }
      design.style = "points pt 6 ps 1.0 lc rgb '#ff3030' lw 1.5";
      const auto map = map_figure(dir, stem + "_map", mean, {}, {design},
                                  {label + ", surrogate mean", o.parameter_names[0], o.parameter_names[1], label});
      page.figure(map.svg, "Surrogate mean of " + label + " over the design box; circles: design points.",
                  map.data_files);
      const auto sdmap = map_figure(dir, stem + "_sd", sd, {}, {design},
                                    {label + ", surrogate sd", o.parameter_names[0], o.parameter_names[1],
                                     "sd of the mean"});
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
    const auto parity = parity_figure(dir, stem + "_parity", obs, mu, sdv, label + ": leave-one-out", "");
    page.figure(parity.svg,
                "Leave-one-out parity: each design point predicted by the surrogate fitted without it (bars: "
                "±2 sd of the prediction). Q² = " + num(f.validation.q_squared, 4) + ", RMSE = " +
                    num(f.validation.rmse, 3) + ".",
                parity.data_files);
    const auto resid = residual_figure(dir, stem + "_residuals", mu, std_res, label + ": standardized residuals",
                                       "leave-one-out prediction");
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
      InspectedSurrogate poly{s.setup, *s.companion_polynomial, s.design_x, std::nullopt};
      nlohmann::json pe;
      page.paragraph("For comparison, the regression equation the seed paper would fit: a polynomial of total degree " +
                     std::to_string(dynamic_cast<const surrogate::PolynomialSurface&>(*poly.fit.model).degree()) +
                     " chosen by leave-one-out (LOO RMSE " + num(poly.fit.validation.rmse, 3) + ", Q² " +
                     num(poly.fit.validation.q_squared, 4) + "). It is shown, not used by the calibration.");
      coefficient_section(page, pe, poly);
      entry["companion_polynomial"] = pe;
      entry["companion_polynomial"]["loo_rmse"] = poly.fit.validation.rmse;
    }

    surrogate::SobolOptions so;
    so.base_samples = o.sobol_base_samples;
    so.bootstrap_resamples = 100;
    const auto si = surrogate::sobol_indices(*f.model, o.lower, o.upper, so);
    std::vector<double> e1, et;
    for (std::size_t i = 0; i < p; ++i) {
      e1.push_back(si.first_order_upper.empty() ? 0.0 : 0.5 * (si.first_order_upper[i] - si.first_order_lower[i]));
      et.push_back(si.total_upper.empty() ? 0.0 : 0.5 * (si.total_upper[i] - si.total_lower[i]));
    }
    const auto bars = bar_figure(dir, stem + "_sobol", o.parameter_names,
                                 {{"first order", si.first_order, e1}, {"total", si.total, et}},
                                 label + ": Sobol indices", "share of the variance over the box");
    page.figure(bars.svg,
                "Sobol indices of the surrogate over the design box (uniform inputs): the share of the variance of " +
                    label + " due to each parameter alone (first order) and with its interactions (total); bars: "
                            "95 % bootstrap half-width.",
                bars.data_files);
    entry["sobol"] = {{"first_order", si.first_order}, {"total", si.total}, {"variance", si.variance}};
    summary["surrogates"].push_back(entry);
  }
  page.write(files.html);
  write_text_atomically(files.json, summary.dump(1) + "\n");
  return files;
}

}  // namespace demcal::calibrate
