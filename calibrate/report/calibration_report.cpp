#include "calibrate/report/calibration_report.hpp"

#include "calibrate/report/figures.hpp"
#include "calibrate/report/html_report.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace demcal::calibrate {
namespace {

namespace fs = std::filesystem;

std::string num(double v, int precision = 4) { return format_number(v, precision); }

std::string observables_of(const CalibrationResult& r) {
  std::string s;
  for (const auto& t : r.targets) s += (s.empty() ? "" : " + ") + t.observable;
  return s;
}

int target_index(const CalibrationResult& r, const std::string& observable) {
  for (std::size_t i = 0; i < r.targets.size(); ++i)
    if (r.targets[i].observable == observable) return static_cast<int>(i);
  return -1;
}

GridField grid_of(const LikelihoodRegion& region, const std::vector<double>& values) {
  GridField g;
  g.x = region.axes.at(0);
  g.y = region.axes.at(1);
  g.values = values;
  return g;
}

std::string theta_text(const CalibrationResult& r, const Eigen::VectorXd& theta) {
  std::string s = "(";
  for (Eigen::Index i = 0; i < theta.size(); ++i)
    s += (i ? ", " : "") + r.parameters[static_cast<std::size_t>(i)].name + " = " + num(theta(i), 3);
  return s + ")";
}

void minima_table(HtmlReport& page, const CalibrationResult& r, const std::string& label) {
  std::vector<std::string> header = {"minimum"};
  for (const auto& p : r.parameters) header.push_back(p.name);
  for (const auto& p : r.parameters) header.push_back("s.e. " + p.name);
  header.insert(header.end(), {"chi²", "at a bound", "Jacobian", "weakest direction", "starts"});
  std::vector<std::vector<std::string>> rows;
  for (std::size_t m = 0; m < r.minima.size(); ++m) {
    const auto& mi = r.minima[m];
    std::vector<std::string> row = {std::to_string(m + 1)};
    for (Eigen::Index i = 0; i < mi.theta.size(); ++i) row.push_back(num(mi.theta(i), 4));
    for (double se : mi.standard_errors) row.push_back(num(se, 2));
    row.push_back(num(mi.chi_squared, 4));
    row.push_back(mi.at_bound ? "yes" : "no");
    std::string sv;
    for (Eigen::Index i = 0; i < mi.singular_values.size(); ++i)
      sv += (i ? ", " : "") + num(mi.singular_values(i), 3);
    row.push_back((mi.rank_deficient ? "rank deficient; s.v. " : "full rank; s.v. ") + sv);
    std::string wd = "(";
    for (Eigen::Index i = 0; i < mi.weakest_direction.size(); ++i)
      wd += (i ? ", " : "") + num(mi.weakest_direction(i), 3);
    row.push_back(wd + ")");
    row.push_back(std::to_string(mi.starts));
    rows.push_back(row);
  }
  page.table(header, rows, label + ": distinct minima (Ceres, multi-start)");
  if (!r.minima.empty()) {
    const auto& best = r.minima.front();
    std::vector<std::vector<std::string>> res;
    for (std::size_t i = 0; i < r.targets.size(); ++i)
      res.push_back({r.targets[i].setup, r.targets[i].observable, num(r.targets[i].measured, 5),
                     num(r.targets[i].sigma_measured, 3), num(r.targets[i].sigma_dem, 3),
                     i < best.predicted.size() ? num(best.predicted[i], 5) : "—",
                     i < best.sigma_total.size() ? num(best.sigma_total[i], 3) : "—",
                     i < best.residuals.size() ? num(best.residuals[i], 3) : "—"});
    page.table({"setup", "observable", "measured", "sigma measured", "sigma DEM", "predicted at best", "sigma total",
                "standardized residual"},
               res,
               label + ": residuals at the best point; chi² = " + num(r.fit.chi_square, 4) + " on " +
                   std::to_string(r.fit.degrees_of_freedom) + " degrees of freedom" +
                   (std::isfinite(r.fit.p_value) ? ", p = " + num(r.fit.p_value, 3) : ""));
  }
}

}  // namespace

std::vector<std::string> identification_statements(const CalibrationResult& r, const std::string& label) {
  std::vector<std::string> out;
  if (!r.region.available) return out;
  for (std::size_t i = 0; i < r.region.extent.size(); ++i) {
    const auto& e = r.region.extent[i];
    std::ostringstream s;
    s << label << ": " << e.name << (e.identified() ? " is identified" : " is NOT identified") << " — its "
      << num(100 * r.region.confidence, 3) << " % region spans " << num(e.lower, 3) << " to " << num(e.upper, 3);
    if (e.identified())
      s << ", clear of both bounds (" << num(r.parameters[i].lower, 3) << ", " << num(r.parameters[i].upper, 3) << ")";
    else
      s << " and reaches the " << (e.touches_lower_bound && e.touches_upper_bound ? "lower and upper bounds"
                                   : e.touches_lower_bound                        ? "lower bound"
                                                                                  : "upper bound");
    out.push_back(s.str());
  }
  return out;
}

CalibrationReportFiles write_calibration_report(const fs::path& dir, const CalibrationResult* alone,
                                                const CalibrationResult& joint,
                                                const CalibrationReportOptions& o) {
  fs::create_directories(dir);
  CalibrationReportFiles files{dir / "index.html", dir / "calibration.json"};
  HtmlReport page("Calibration — " + o.study_name);
  nlohmann::json summary;
  summary["study"] = o.study_name;
  summary["joint"] = joint.to_json(false, false);
  if (alone) summary["alone"] = alone->to_json(false, false);

  const std::string jl = "calibrated on " + observables_of(joint);
  const std::string al = alone ? "calibrated on " + observables_of(*alone) : "";
  {
    std::ostringstream s;
    s << "Best point " << jl << ": " << (joint.minima.empty() ? "none" : theta_text(joint, joint.minima[0].theta))
      << ", chi² = " << num(joint.fit.chi_square, 4) << ".";
    page.paragraph(s.str());
  }
  if (joint.parameters.size() == 2 && joint.region.available) {
    const auto& R = joint.region;
    std::vector<ContourLine> lines;
    const int k_aor = target_index(joint, "angle_of_repose_deg");
    for (std::size_t k = 0; k < joint.targets.size(); ++k) {
      const auto& t = joint.targets[k];
      ContourLine l{"measured " + t.observable + " = " + num(t.measured, 4), grid_of(R, R.predicted_mean.at(k)),
                    t.measured, static_cast<int>(k) == k_aor ? "#1f77b4" : "#ff7f0e", 2, 1.5};
      lines.push_back(l);
    }
    if (alone && alone->region.available)
      lines.push_back({"95 % region, " + al, grid_of(alone->region, alone->region.chi_squared),
                       alone->region.threshold, "#1f77b4", 1, 2.5});
    lines.push_back({"95 % region, " + jl, grid_of(R, R.chi_squared), R.threshold, "#d62728", 1, 3.0});
    std::vector<PointSet> pts;
    if (alone) {
      PointSet a{"minima, " + al, {}, {}, "points pt 8 ps 1.3 lc rgb '#1f77b4' lw 2"};
      for (const auto& m : alone->minima) {
        a.x.push_back(m.theta(0));
        a.y.push_back(m.theta(1));
      }
      pts.push_back(a);
    }
    PointSet b{"best, " + jl, {}, {}, "points pt 7 ps 1.4 lc rgb '#d62728'"};
    if (!joint.minima.empty()) {
      b.x.push_back(joint.minima[0].theta(0));
      b.y.push_back(joint.minima[0].theta(1));
    }
    pts.push_back(b);
    for (const auto& ref : o.references)
      if (ref.theta.size() == 2) pts.push_back({ref.label, {ref.theta[0]}, {ref.theta[1]}, "points pt 3 ps 2 lc rgb '#000000' lw 2"});
    // Colour: the joint chi² above its minimum, capped so the valley shows.
    std::vector<double> dchi;
    for (double c : R.chi_squared) dchi.push_back(std::min(c - R.chi_squared_min, 4.0 * (R.threshold - R.chi_squared_min)));
    MapFigureOptions mo{"Which (" + joint.parameters[0].name + ", " + joint.parameters[1].name + ") reproduce the recordings?",
                        joint.parameters[0].name, joint.parameters[1].name, "chi² - chi²_min (" + observables_of(joint) + ")",
                        0, "viridis", 760, 640};
    const auto fig = map_figure(dir, "key_figure", grid_of(R, dchi), lines, pts, mo);
    std::ostringstream cap;
    cap << "Dashed: where the surrogates predict the measured values (iso-lines). Solid: the "
        << num(100 * R.confidence, 3) << " % likelihood-ratio regions {chi² − chi²_min ≤ "
        << num(R.threshold - R.chi_squared_min, 4) << "}.";
    page.figure(fig.svg, cap.str(), fig.data_files);
    std::vector<std::string> text;
    text.push_back("Region " + jl + ": area " + num(R.area, 3) + " (in " + joint.parameters[0].name + " × " +
                   joint.parameters[1].name + " units).");
    summary["comparison"] = nlohmann::json::object();
    if (alone && alone->region.available) {
      text.push_back("Region " + al + ": area " + num(alone->region.area, 3) + ".");
      const auto cmp = compare_regions(*alone, joint);
      text.push_back("Ratio of the areas (" + observables_of(*alone) + " alone / " + observables_of(joint) +
                     "): " + num(cmp.ratio, 3) + ". Posterior 95 % credible areas: " + num(cmp.credible_area_a, 3) +
                     " and " + num(cmp.credible_area_b, 3) + ".");
      summary["comparison"] = cmp.to_json();
      for (const auto& s : identification_statements(*alone, al)) text.push_back(s + ".");
    }
    for (const auto& s : identification_statements(joint, jl)) text.push_back(s + ".");
    std::string html = "<ul>";
    for (const auto& t : text) html += "<li>" + html_escape(t) + "</li>";
    html += "</ul>";
    page.raw_html(html);
    summary["statements"] = text;
  }
  summary["references"] = nlohmann::json::array();
  for (const auto& ref : o.references) {
    const auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
    summary["references"].push_back({{"label", ref.label},
                                     {"theta", ref.theta},
                                     {"delta_chi_square_joint", number(ref.delta_chi_square_joint)},
                                     {"inside_joint", ref.inside_joint},
                                     {"delta_chi_square_alone", number(ref.delta_chi_square_alone)},
                                     {"inside_alone", ref.inside_alone}});
    if (!std::isfinite(ref.delta_chi_square_joint)) continue;
    std::string t = ref.label + ": chi² − chi²_min = " + num(ref.delta_chi_square_joint, 3) + " (" + jl + ", " +
                    (ref.inside_joint ? "inside" : "outside") + " its 95 % region)";
    if (std::isfinite(ref.delta_chi_square_alone))
      t += ", " + num(ref.delta_chi_square_alone, 3) + " (" + al + ", " + (ref.inside_alone ? "inside" : "outside") +
           ")";
    page.paragraph(t + ".");
  }
  for (const auto& r : o.remarks) page.paragraph(r);
  for (const auto& n : joint.notes) page.paragraph(jl + ": " + n);
  if (alone)
    for (const auto& n : alone->notes) page.paragraph(al + ": " + n);

  page.heading("Minima, chi-square and residuals");
  minima_table(page, joint, jl);
  if (alone) minima_table(page, *alone, al);

  if (joint.posterior.available) {
    page.heading("Posterior (adaptive Metropolis, surrogate variance included)");
    for (std::size_t i = 0; i < joint.parameters.size(); ++i) {
      std::vector<LineSeries> series;
      const auto add = [&](const CalibrationResult& r, const std::string& name, const std::string& colour) {
        if (!r.posterior.available) return;
        const auto& m = r.posterior.marginals.at(i);
        LineSeries s{name, {}, {}, "steps lw 2 lc rgb '" + colour + "'"};
        for (std::size_t b = 0; b < m.histogram_density.size(); ++b) {
          s.x.push_back(m.histogram_edges[b]);
          s.y.push_back(m.histogram_density[b]);
        }
        series.push_back(s);
      };
      if (alone) add(*alone, al, "#1f77b4");
      add(joint, jl, "#d62728");
      const auto fig = line_figure(dir, "marginal_" + joint.parameters[i].name, series,
                                   "Marginal posterior of " + joint.parameters[i].name, joint.parameters[i].name,
                                   "density");
      page.figure(fig.svg, "Marginal posterior density of " + joint.parameters[i].name + " (histogram of the samples).",
                  fig.data_files);
    }
    std::vector<std::vector<std::string>> rows;
    const auto add_rows = [&](const CalibrationResult& r, const std::string& label) {
      if (!r.posterior.available) return;
      for (const auto& m : r.posterior.marginals)
        rows.push_back({label, m.name, num(m.mean, 4), num(m.sd, 3), num(m.lower, 4), num(m.median, 4),
                        num(m.upper, 4), num(m.effective_sample_size, 4), num(m.r_hat, 4)});
    };
    add_rows(joint, jl);
    if (alone) add_rows(*alone, al);
    page.table({"calibration", "parameter", "mean", "sd", "2.5 %", "median", "97.5 %", "effective samples", "R-hat"},
               rows, "Calibrated values with 95 % credible intervals");
  }
  page.write(files.html);
  write_text_atomically(files.json, summary.dump(1) + "\n");
  return files;
}

}  // namespace demcal::calibrate
