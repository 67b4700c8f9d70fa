#include "calibrate/report/calibration_report.hpp"

#include "calibrate/report/figures.hpp"
#include "calibrate/report/html_report.hpp"
#include "calibrate/report/labels.hpp"
#include "calibrate/report/sobol_figure.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

namespace demcal::calibrate {
namespace {

namespace fs = std::filesystem;

std::string num(double v, int precision = 3) { return human_number(v, precision); }

// "AoR + time", from the observables' short names.
std::string observables_of(const CalibrationResult& r) {
  std::string s;
  for (const auto& t : r.targets) {
    const std::string o = observable_short(t.observable);
    if (s.find(o) == std::string::npos) s += (s.empty() ? "" : " + ") + o;
  }
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

RegionComponents components_of(const CalibrationResult& r, const Eigen::MatrixXd& design) {
  if (!r.region.available) return {};
  const Eigen::VectorXd best = r.minima.empty() ? Eigen::VectorXd() : r.minima.front().theta;
  const Eigen::MatrixXd d =
      design.cols() == static_cast<Eigen::Index>(r.parameters.size()) ? design : Eigen::MatrixXd();
  return region_components(r.region.axes, r.region.inside, best, d);
}

std::vector<std::string> parameter_names(const CalibrationResult& r) {
  std::vector<std::string> n;
  for (const auto& p : r.parameters) n.push_back(p.name);
  return n;
}

// "yes", "yes, loosely (its region spans 70 % of the range)", "no: reaches the upper bound (0.6)"
std::string identified_text(const CalibrationResult& r, std::size_t i) {
  if (!r.region.available || i >= r.region.extent.size())
    return i < r.identified.size() ? (r.identified[i] ? "yes" : "no") : "—";
  const auto& e = r.region.extent[i];
  const auto& b = r.parameters[i];
  const bool id = i < r.identified.size() ? r.identified[i] : e.identified();
  const double share = (e.upper - e.lower) / (b.upper - b.lower);
  if (id) {
    if (share > 0.5)
      return "yes, loosely: its 95 % region spans " + num(100 * share, 2) + " % of the range";
    return "yes";
  }
  if (e.touches_lower_bound && e.touches_upper_bound) return "no: its region reaches both bounds";
  if (e.touches_lower_bound) return "no: its region reaches the lower bound (" + num(b.lower) + ")";
  if (e.touches_upper_bound) return "no: its region reaches the upper bound (" + num(b.upper) + ")";
  return "no: it moves along a direction the data do not fix";
}

std::string minima_caption(const CalibrationResult& r, const std::string& label) {
  std::string c = label + ": distinct minima (Ceres, multi-start)";
  if (!r.minima.empty() && r.minima.front().rank_deficient)
    c += ". Rank deficient: these points lie along a valley of (nearly) equal fit; none of them is "
         "the answer — "
         "read the region instead";
  return c;
}

void minima_table(HtmlReport& page, const CalibrationResult& r, const std::string& label) {
  std::vector<std::string> header = {"minimum"};
  for (const auto& p : r.parameters) header.push_back(p.name);
  for (const auto& p : r.parameters) header.push_back("s.e. " + p.name + " (local)");
  header.insert(header.end(), {"chi²", "at a bound", "Jacobian", "weakest direction", "starts"});
  std::vector<std::vector<std::string>> rows;
  for (std::size_t m = 0; m < r.minima.size(); ++m) {
    const auto& mi = r.minima[m];
    std::vector<std::string> row = {std::to_string(m + 1)};
    for (Eigen::Index i = 0; i < mi.theta.size(); ++i) row.push_back(num(mi.theta(i), 4));
    for (double se : mi.standard_errors) row.push_back(num(se, 2));
    row.push_back(human_number(mi.chi_squared, 4, 1e-9));
    row.push_back(mi.at_bound ? "yes" : "no");
    std::string sv;
    for (Eigen::Index i = 0; i < mi.singular_values.size(); ++i)
      sv += (i ? ", " : "") + human_number(mi.singular_values(i), 3, 1e-9);
    row.push_back((mi.rank_deficient ? "rank deficient; s.v. " : "full rank; s.v. ") + sv);
    std::string wd = "(";
    for (Eigen::Index i = 0; i < mi.weakest_direction.size(); ++i)
      wd += (i ? ", " : "") + num(mi.weakest_direction(i), 3);
    row.push_back(wd + ")");
    row.push_back(std::to_string(mi.starts));
    rows.push_back(row);
  }
  page.table(header, rows, minima_caption(r, label));
  if (!r.minima.empty()) {
    const auto& best = r.minima.front();
    std::vector<std::vector<std::string>> res;
    for (std::size_t i = 0; i < r.targets.size(); ++i) {
      const auto& t = r.targets[i];
      res.push_back({t.setup, observable_label(t.observable), num(t.measured, 4),
                     num(t.sigma_measured, 3), num(t.sigma_dem, 3),
                     i < best.predicted.size() ? num(best.predicted[i], 4) : "—",
                     i < best.sigma_total.size() ? num(best.sigma_total[i], 3) : "—",
                     i < best.residuals.size() ? human_number(best.residuals[i], 3, 1e-9) : "—"});
    }
    page.table({"setup", "observable", "measured", "sigma measured", "sigma DEM",
                "predicted at best", "sigma total", "standardized residual"},
               res, label + ": residuals at the best point; " + fit_text(r));
  }
}

// A vertical marker line for a marginal plot.
LineSeries marker(const std::string& name, double x, double top, const std::string& style) {
  return {name, {x, x}, {0.0, top}, style};
}

}  // namespace

std::string fit_text(const CalibrationResult& r) {
  const int dof = r.fit.degrees_of_freedom;
  const std::string chi = "chi² = " + human_number(r.fit.chi_square, 3, 1e-9);
  if (dof < 1) {
    const std::size_t n = r.targets.size(), p = r.parameters.size();
    const std::string count = std::to_string(n) + " recording" + (n == 1 ? "" : "s") + " for " +
                              std::to_string(p) + " parameter" + (p == 1 ? "" : "s");
    // With no degrees of freedom a pair that matches exactly gives chi² = 0; a clearly
    // positive one means no pair in the box does.
    if (r.fit.chi_square > 4.0) {
      bool at_bound = !r.minima.empty() && r.minima.front().at_bound;
      return chi + " with " + count + ": no pair in the box matches the recordings" +
             (at_bound ? " (the best point lies on a bound: widen the box, or check the recordings "
                         "and the model)"
                       : " (check the recordings and the model)");
    }
    return chi + "; " + count +
           ": no degrees of freedom left, so the fit can match any data and tests nothing";
  }
  return chi + " on " + std::to_string(dof) + " degree" + (dof == 1 ? "" : "s") + " of freedom" +
         (std::isfinite(r.fit.p_value) ? ", p = " + num(r.fit.p_value, 2) : "");
}

std::vector<std::string> identification_statements(const CalibrationResult& r,
                                                   const std::string& label) {
  std::vector<std::string> out;
  if (!r.region.available) return out;
  for (std::size_t i = 0; i < r.region.extent.size(); ++i)
    out.push_back(label + ": " + r.region.extent[i].name + " identified? " + identified_text(r, i) +
                  " (95 % region " + num(r.region.extent[i].lower) + " to " +
                  num(r.region.extent[i].upper) + ")");
  return out;
}

Headline calibration_headline(const CalibrationResult* alone, const CalibrationResult& joint,
                              const CalibrationReportOptions& o) {
  Headline h;
  const std::string jl = observables_of(joint);
  const std::string al = alone ? observables_of(*alone) : "";
  h.header = {"parameter",
              "calibrated value (best fit, " + jl + ")",
              "95 % region (likelihood ratio)",
              "95 % posterior interval",
              "Gauss–Newton ±95 % (local)",
              "identified by " + jl + "?"};
  if (alone) h.header.push_back("identified by " + al + " alone?");
  for (std::size_t i = 0; i < joint.parameters.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    std::vector<std::string> row{joint.parameters[i].name};
    const Minimum* best = joint.minima.empty() ? nullptr : &joint.minima.front();
    row.push_back(best ? num(best->theta(k)) : "—");
    row.push_back(joint.region.available && i < joint.region.extent.size()
                      ? num(joint.region.extent[i].lower) + " – " +
                            num(joint.region.extent[i].upper)
                      : "—");
    row.push_back(joint.posterior.available && i < joint.posterior.marginals.size()
                      ? num(joint.posterior.marginals[i].lower) + " – " +
                            num(joint.posterior.marginals[i].upper)
                      : "—");
    row.push_back(best && i < best->standard_errors.size() &&
                          std::isfinite(best->standard_errors[i])
                      ? num(best->theta(k)) + " ± " + num(1.96 * best->standard_errors[i], 2)
                      : "not available (rank deficient)");
    row.push_back(identified_text(joint, i));
    if (alone) row.push_back(identified_text(*alone, i));
    h.rows.push_back(row);
  }
  h.sentences.push_back(
      "Which interval to believe: the likelihood-ratio region and the posterior interval (they "
      "account for the "
      "whole plane and the surrogates' uncertainty); the Gauss–Newton ± describes only the "
      "neighbourhood of the "
      "best point and is too narrow when the region is not an ellipse.");
  if (alone && alone->region.available && joint.region.available) {
    const auto cmp = compare_regions(*alone, joint);
    std::string added;
    for (const auto& t : joint.targets) {
      const std::string o = observable_short(t.observable);
      if (al.find(o) == std::string::npos && added.find(o) == std::string::npos)
        added += (added.empty() ? "" : " + ") + o;
    }
    std::string s = "Adding the " + added + " shrinks the 95 % region " + num(cmp.ratio) +
                    "-fold: area " + num(cmp.area_a) + " with " + al + " alone, " +
                    num(cmp.area_b) + " with " + jl + " (in " + joint.parameters[0].name;
    for (std::size_t i = 1; i < joint.parameters.size(); ++i) s += " × " + joint.parameters[i].name;
    s += " units)";
    if (std::isfinite(cmp.credible_ratio) && cmp.credible_ratio > 0)
      s += "; posterior 95 % credible areas " + num(cmp.credible_area_a) + " and " +
           num(cmp.credible_area_b) + " (ratio " + num(cmp.credible_ratio) + ")";
    h.sentences.push_back(s + ".");
  }
  const auto names = parameter_names(joint);
  const auto parts_sentence = [&](const CalibrationResult& r, const std::string& label) {
    if (!r.region.available) return;
    const auto c = components_of(r, o.design_points);
    std::string s = "The " + label + " 95 % region: " + describe_components(c, names) + ".";
    h.sentences.push_back(s);
  };
  parts_sentence(joint, jl);
  if (alone) parts_sentence(*alone, al + " alone");
  for (const auto& ref : o.references) {
    if (!std::isfinite(ref.delta_chi_square_joint)) continue;
    std::string t = ref.label + ": " + (ref.inside_joint ? "inside" : "OUTSIDE") + " the " + jl +
                    " 95 % region (chi² − chi²_min = " + num(ref.delta_chi_square_joint) + ")";
    if (std::isfinite(ref.delta_chi_square_alone))
      t += ", " + std::string(ref.inside_alone ? "inside" : "OUTSIDE") + " the " + al +
           "-alone region (" + num(ref.delta_chi_square_alone) + ")";
    h.sentences.push_back(t + ".");
  }
  h.sentences.push_back("Fit (" + jl + "): " + fit_text(joint) + ".");
  return h;
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

  const std::string jl = observables_of(joint);
  const std::string al = alone ? observables_of(*alone) : "";
  const std::string jcal = "calibrated on " + jl;
  const std::string acal = alone ? "calibrated on " + al + " alone" : "";

  // The headline box.
  const Headline head = calibration_headline(alone, joint, o);
  page.raw_html("<div class=\"headline\">");
  page.table(head.header, head.rows, "In short: the calibrated values and how sure they are");
  {
    std::string html = "<ul>";
    for (const auto& t : head.sentences) html += "<li>" + html_escape(t) + "</li>";
    page.raw_html(html + "</ul></div>");
  }
  summary["headline"] = {
      {"header", head.header}, {"rows", head.rows}, {"sentences", head.sentences}};

  const auto jc = components_of(joint, o.design_points);
  const auto ac = alone ? components_of(*alone, o.design_points) : RegionComponents{};
  const auto parts_json = [](const RegionComponents& c) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& p : c.parts)
      a.push_back({{"nodes", p.nodes},
                   {"area", p.area},
                   {"lower", p.lower},
                   {"upper", p.upper},
                   {"holds_best", p.holds_best},
                   {"design_points", p.design_points},
                   {"between_design_points", p.between_design_points}});
    return a;
  };
  summary["region_parts"] = {{"joint", parts_json(jc)}};
  if (alone) summary["region_parts"]["alone"] = parts_json(ac);

  if (joint.parameters.size() == 2 && joint.region.available) {
    page.heading("Which (" + joint.parameters[0].name + ", " + joint.parameters[1].name +
                 ") reproduce the recordings?");
    const auto& R = joint.region;
    const std::string xl = parameter_label(joint.parameters[0].name),
                      yl = parameter_label(joint.parameters[1].name);
    std::vector<ContourLine> iso;
    const int k_aor = target_index(joint, "angle_of_repose_deg");
    for (std::size_t k = 0; k < joint.targets.size(); ++k) {
      const auto& t = joint.targets[k];
      iso.push_back({observable_short(t.observable) + " = " +
                         observable_value(t.observable, t.measured) + " (measured" +
                         (t.setup.empty() ? "" : ", " + t.setup) + ")",
                     grid_of(R, R.predicted_mean.at(k)), t.measured,
                     static_cast<int>(k) == k_aor ? "#08519c" : "#e6550d", 2, 2.0});
    }
    PointSet design{"design points", {}, {}, "points pt 7 ps 0.45 lc rgb '#555555'"};
    for (Eigen::Index r = 0; r < o.design_points.rows(); ++r)
      if (o.design_points.cols() == 2) {
        design.x.push_back(o.design_points(r, 0));
        design.y.push_back(o.design_points(r, 1));
      }
    std::vector<PointSet> refs;
    for (const auto& ref : o.references)
      if (ref.theta.size() == 2)
        refs.push_back({ref.label,
                        {ref.theta[0]},
                        {ref.theta[1]},
                        "points pt 3 ps 2.2 lc rgb '#000000' lw 2"});
    PointSet best{"best point, " + jl, {}, {}, "points pt 7 ps 1.6 lc rgb '#a50f15'"};
    if (!joint.minima.empty()) {
      best.x.push_back(joint.minima[0].theta(0));
      best.y.push_back(joint.minima[0].theta(1));
    }
    const auto island_labels = [&](const RegionComponents& c, const LikelihoodRegion& reg) {
      std::vector<MapLabel> labels;
      for (std::size_t k = 0; k < c.parts.size(); ++k)
        if (c.parts[k].between_design_points)
          labels.push_back({0.5 * (c.parts[k].lower[0] + c.parts[k].upper[0]),
                            0.5 * (c.parts[k].lower[1] + c.parts[k].upper[1]),
                            "part " + std::to_string(k + 1) + ": no design point"});
      (void)reg;
      return labels;
    };

    // Panel 1: AoR alone.
    if (alone && alone->region.available) {
      const auto& A = alone->region;
      std::vector<double> fill;
      for (bool b : A.inside) fill.push_back(b ? 1.0 : 0.0);
      std::vector<ContourLine> lines;
      lines.push_back({"95 % region, " + al + " alone (filled)", grid_of(A, A.chi_squared),
                       A.threshold, "#3182bd", 1, 2.0});
      for (std::size_t k = 0; k < alone->targets.size(); ++k) {
        const auto& t = alone->targets[k];
        lines.push_back({observable_short(t.observable) + " = " +
                             observable_value(t.observable, t.measured) + " (measured)",
                         grid_of(A, A.predicted_mean.at(k)), t.measured, "#08519c", 2, 2.0});
      }
      std::vector<PointSet> pts{design};
      // A rank-deficient problem has no meaningful minimum: no marker for it.
      if (!alone->minima.empty() && !alone->minima.front().rank_deficient)
        pts.push_back({"best point, " + al + " alone",
                       {alone->minima[0].theta(0)},
                       {alone->minima[0].theta(1)},
                       "points pt 6 ps 1.6 lc rgb '#08519c' lw 2"});
      for (const auto& r : refs) pts.push_back(r);
      MapFigureOptions mo{
          al + " alone", xl,  yl,    "inside", 0, "defined (0 '#ffffff', 1 '#9ecae1')",
          520,           470, false, 0,        1, island_labels(ac, A)};
      const auto fig = map_figure(dir, "key_figure_alone", grid_of(A, fill), lines, pts, mo);
      page.figure(fig.svg,
                  "Filled: the 95 % region calibrated on " + al +
                      " alone — every pair in it reproduces the recording "
                      "within its uncertainty. " +
                      (alone->minima.empty() || alone->minima.front().rank_deficient
                           ? "No best point is marked: with one recording for two parameters the "
                             "minimum is a valley, not a point."
                           : ""),
                  fig.data_files);
    }
    // Panel 2: AoR + time.
    {
      std::vector<double> fill;
      for (std::size_t n = 0; n < R.inside.size(); ++n) {
        const bool in_a = alone && alone->region.available && n < alone->region.inside.size() &&
                          alone->region.inside[n];
        fill.push_back(R.inside[n] ? 2.0 : in_a ? 1.0 : 0.0);
      }
      std::vector<ContourLine> lines;
      lines.push_back({"95 % region, " + jl + " (filled red)", grid_of(R, R.chi_squared),
                       R.threshold, "#a50f15", 1, 2.5});
      if (alone && alone->region.available)
        lines.push_back({"95 % region, " + al + " alone (light blue)",
                         grid_of(alone->region, alone->region.chi_squared), alone->region.threshold,
                         "#3182bd", 1, 1.2});
      for (const auto& l : iso) lines.push_back(l);
      std::vector<PointSet> pts{design, best};
      for (const auto& r : refs) pts.push_back(r);
      MapFigureOptions mo{
          jl,  xl,  yl,    "region", 0, "defined (0 '#ffffff', 1 '#deebf7', 2 '#fc9272')",
          520, 470, false, 0,        2, island_labels(jc, R)};
      const auto fig = map_figure(dir, "key_figure", grid_of(R, fill), lines, pts, mo);
      std::ostringstream cap;
      cap << "Filled red: the 95 % region calibrated on " << jl << " {chi² − chi²_min ≤ "
          << num(R.threshold - R.chi_squared_min) << "}; light blue: the part of the " << al
          << "-alone region it rules out. Dashed: where the surrogates predict each measured "
             "value. The region: "
          << describe_components(jc, parameter_names(joint)) << ".";
      // A measured value the surrogate reaches nowhere in the box has no iso-line.
      for (std::size_t k = 0; k < joint.targets.size(); ++k) {
        const auto& mean = R.predicted_mean.at(k);
        const auto [lo, hi] = std::minmax_element(mean.begin(), mean.end());
        const auto& t = joint.targets[k];
        if (lo != mean.end() && (t.measured < *lo || t.measured > *hi))
          cap << " No " << observable_short(t.observable) << " iso-line: the measured "
              << observable_value(t.observable, t.measured)
              << " lies outside what the surrogate predicts anywhere in "
              << "the box (" << observable_value(t.observable, *lo) << " to "
              << observable_value(t.observable, *hi) << ").";
      }
      page.figure(fig.svg, cap.str(), fig.data_files);
    }
    // Panel 3: the posterior.
    if (joint.posterior.available && !R.log_posterior.empty()) {
      double top = -std::numeric_limits<double>::infinity();
      for (double v : R.log_posterior) top = std::max(top, v);
      std::vector<double> dens;
      for (double v : R.log_posterior) dens.push_back(std::isfinite(v) ? std::exp(v - top) : 0.0);
      std::vector<ContourLine> lines;
      const auto& cr = joint.posterior.credible_region;
      if (cr.available)
        lines.push_back({"95 % credible region", grid_of(R, R.log_posterior),
                         cr.log_posterior_level, "#ff7f0e", 1, 2.0});
      std::vector<PointSet> pts{best};
      for (const auto& r : refs) {
        auto w = r;
        w.style = "points pt 3 ps 2.2 lc rgb '#ff3333' lw 2";
        pts.push_back(w);
      }
      MapFigureOptions mo{"posterior, " + jl,
                          xl,
                          yl,
                          "posterior density / its maximum",
                          0,
                          "viridis",
                          520,
                          470,
                          true,
                          0,
                          1,
                          {}};
      const auto fig = map_figure(dir, "posterior_map", grid_of(R, dens), lines, pts, mo);
      page.figure(fig.svg,
                  "The posterior (adaptive Metropolis, surrogate variance included) over the same "
                  "plane, relative to "
                  "its maximum; orange: its 95 % highest-density region.",
                  fig.data_files);
    }
    std::vector<std::string> text;
    for (const auto& s : identification_statements(joint, jcal)) text.push_back(s + ".");
    if (alone)
      for (const auto& s : identification_statements(*alone, acal)) text.push_back(s + ".");
    std::string html = "<ul>";
    for (const auto& t : text) html += "<li>" + html_escape(t) + "</li>";
    page.raw_html(html + "</ul>");
    summary["statements"] = text;
    summary["comparison"] = nlohmann::json::object();
    if (alone && alone->region.available)
      summary["comparison"] = compare_regions(*alone, joint).to_json();
  }
  // The surrogates where it matters: over the joint 95 % region.
  if (joint.region.available && o.models.size() == joint.targets.size() &&
      joint.region.nodes_inside > 0) {
    const auto& R = joint.region;
    const std::size_t p = joint.parameters.size();
    page.heading("The surrogates over the " + jl + " 95 % region");
    Eigen::MatrixXd nodes(static_cast<Eigen::Index>(R.nodes_inside), static_cast<Eigen::Index>(p));
    std::vector<double> lo(p), hi(p);
    for (std::size_t a = 0; a < p; ++a) lo[a] = R.extent[a].lower, hi[a] = R.extent[a].upper;
    {
      Eigen::Index row = 0;
      std::size_t stride = 1;
      std::vector<std::size_t> strides(p);
      for (std::size_t a = 0; a < p; ++a) strides[a] = stride, stride *= R.axes[a].size();
      for (std::size_t n = 0; n < R.inside.size(); ++n)
        if (R.inside[n]) {
          for (std::size_t a = 0; a < p; ++a)
            nodes(row, static_cast<Eigen::Index>(a)) =
                R.axes[a][(n / strides[a]) % R.axes[a].size()];
          ++row;
        }
    }
    std::vector<std::vector<std::string>> rows;
    std::vector<std::pair<RenderedFigure, std::string>> figures;
    nlohmann::json js = nlohmann::json::array();
    for (std::size_t k = 0; k < joint.targets.size(); ++k) {
      const auto& t = joint.targets[k];
      if (!o.models[k]) continue;
      const auto pred = o.models[k]->predict(nodes);
      double mean_sd = 0, max_sd = 0;
      for (Eigen::Index i = 0; i < pred.variance.size(); ++i) {
        const double sd = std::sqrt(std::max(0.0, pred.variance(i)));
        mean_sd += sd / static_cast<double>(pred.variance.size());
        max_sd = std::max(max_sd, sd);
      }
      const double noise =
          std::sqrt(t.sigma_measured * t.sigma_measured + t.sigma_dem * t.sigma_dem);
      rows.push_back(
          {t.setup, observable_label(t.observable), num(mean_sd), num(max_sd), num(noise),
           max_sd > noise ? "the surrogate: more design points in the region would narrow it"
                          : "the recording and the DEM's scatter"});
      bool degenerate = false;
      for (std::size_t a = 0; a < p; ++a) degenerate = degenerate || !(hi[a] > lo[a]);
      nlohmann::json sj;
      if (!degenerate) {
        const auto fig = sobol_figure(
            dir, "region_sobol_" + t.setup + "_" + t.observable, *o.models[k],
            parameter_names(joint), lo, hi,
            observable_label(t.observable) + ": Sobol indices over the 95 % region's box", 8192,
            sj);
        figures.push_back({fig, "Which parameter moves " + observable_label(t.observable) +
                                    " within the box of the " + jl + " 95 % region (" +
                                    box_text(parameter_names(joint), lo, hi) +
                                    "), not over the whole design box (the inspection report)."});
      }
      js.push_back({{"setup", t.setup},
                    {"observable", t.observable},
                    {"surrogate_sd_mean", mean_sd},
                    {"surrogate_sd_max", max_sd},
                    {"measurement_and_dem_sd", noise},
                    {"sobol_region_box", sj}});
    }
    page.table({"setup", "observable", "surrogate sd, mean over the region", "largest",
                "recording and DEM scatter (sd)", "what limits the region"},
               rows, "The surrogates' own uncertainty inside the " + jl + " 95 % region");
    for (const auto& [fig, caption] : figures) page.figure(fig.svg, caption, fig.data_files);
    summary["region_surrogates"] = js;
  }
  summary["references"] = nlohmann::json::array();
  for (const auto& ref : o.references) {
    const auto number = [](double v) {
      return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
    };
    summary["references"].push_back({{"label", ref.label},
                                     {"theta", ref.theta},
                                     {"delta_chi_square_joint", number(ref.delta_chi_square_joint)},
                                     {"inside_joint", ref.inside_joint},
                                     {"delta_chi_square_alone", number(ref.delta_chi_square_alone)},
                                     {"inside_alone", ref.inside_alone}});
    if (!std::isfinite(ref.delta_chi_square_joint)) continue;
    std::string t = ref.label + ": chi² − chi²_min = " + num(ref.delta_chi_square_joint, 3) + " (" +
                    jcal + ", " + (ref.inside_joint ? "inside" : "outside") + " its 95 % region)";
    if (std::isfinite(ref.delta_chi_square_alone))
      t += ", " + num(ref.delta_chi_square_alone, 3) + " (" + acal + ", " +
           (ref.inside_alone ? "inside" : "outside") + ")";
    page.paragraph(t + ".");
  }
  for (const auto& r : o.remarks) page.paragraph(r);

  // The solver's own notes, once per calibration, as lists.
  const auto notes = [&](const CalibrationResult& r, const std::string& label,
                         const RegionComponents& c) {
    if (r.notes.empty()) return;
    std::string html = "<h3>" + html_escape(label) + "</h3><ul>";
    for (auto n : r.notes) {
      if (n.rfind("One minimum", 0) == 0 && c.parts.size() > 1)
        n += " The 95 % region nevertheless has " + std::to_string(c.parts.size()) +
             " separate parts (see the headline): one minimum of the solver, not one island.";
      html += "<li>" + html_escape(humanize_sentence(n)) + "</li>";
    }
    page.raw_html(html + "</ul>");
  };
  page.heading("What the solver noted");
  notes(joint, jcal, jc);
  if (alone) notes(*alone, acal, ac);

  page.heading("Minima, chi-square and residuals");
  minima_table(page, joint, jcal);
  if (alone) minima_table(page, *alone, acal);

  if (joint.posterior.available) {
    page.heading("Posterior (adaptive Metropolis, surrogate variance included)");
    const Minimum* bestm = joint.minima.empty() ? nullptr : &joint.minima.front();
    for (std::size_t i = 0; i < joint.parameters.size(); ++i) {
      std::vector<LineSeries> series;
      double top = 0;
      const auto add = [&](const CalibrationResult& r, const std::string& name,
                           const std::string& colour) {
        if (!r.posterior.available) return;
        const auto& m = r.posterior.marginals.at(i);
        LineSeries s{name, {}, {}, "steps lw 2 lc rgb '" + colour + "'"};
        for (std::size_t b = 0; b < m.histogram_density.size(); ++b) {
          s.x.push_back(m.histogram_edges[b]);
          s.y.push_back(m.histogram_density[b]);
          top = std::max(top, m.histogram_density[b]);
        }
        series.push_back(s);
      };
      if (alone) add(*alone, acal, "#3182bd");
      add(joint, jcal, "#a50f15");
      if (bestm)
        series.push_back(marker(
            "best point, " + jl + " (" + num(bestm->theta(static_cast<Eigen::Index>(i))) + ")",
            bestm->theta(static_cast<Eigen::Index>(i)), top * 1.05,
            "lines lw 2.5 dt 4 lc rgb '#e6550d'"));
      for (const auto& ref : o.references)
        if (i < ref.theta.size())
          series.push_back(
              marker(ref.label, ref.theta[i], top * 1.05, "lines lw 2 dt 2 lc rgb '#000000'"));
      const auto fig = line_figure(dir, "marginal_" + joint.parameters[i].name, series,
                                   "Marginal posterior of " + joint.parameters[i].name,
                                   parameter_label(joint.parameters[i].name), "density");
      page.figure(fig.svg,
                  "Marginal posterior density of " + joint.parameters[i].name +
                      " (histogram of the samples).",
                  fig.data_files);
    }
    // Trace plots: each chain's samples in order; a chain that wanders off or sticks
    // shows here before it shows in R-hat.
    const auto& P = joint.posterior;
    if (P.chains > 0 && P.samples_per_chain > 0 &&
        P.samples.rows() >= P.chains * P.samples_per_chain) {
      static const char* colours[] = {"#1b9e77", "#d95f02", "#7570b3", "#e7298a"};
      const int stride = std::max(1, P.samples_per_chain / 1000);
      for (std::size_t i = 0; i < joint.parameters.size(); ++i) {
        std::vector<LineSeries> series;
        for (int c = 0; c < P.chains; ++c) {
          LineSeries s{"chain " + std::to_string(c + 1),
                       {},
                       {},
                       std::string("lines lw 1 lc rgb '") + colours[c % 4] + "'"};
          for (int k = 0; k < P.samples_per_chain; k += stride) {
            s.x.push_back(k);
            s.y.push_back(P.samples(c * P.samples_per_chain + k, static_cast<Eigen::Index>(i)));
          }
          series.push_back(s);
        }
        const auto fig =
            line_figure(dir, "trace_" + joint.parameters[i].name, series,
                        "MCMC trace of " + joint.parameters[i].name + ", " + jl,
                        "sample (after burn-in)", parameter_label(joint.parameters[i].name));
        page.figure(fig.svg,
                    "Trace of each chain (" +
                        (stride == 1 ? std::string("every sample")
                                     : "every " + std::to_string(stride) + "th sample") +
                        " shown): well-mixed chains overlap and look like noise around one level.",
                    fig.data_files);
      }
    }
    std::vector<std::vector<std::string>> rows;
    const auto add_rows = [&](const CalibrationResult& r, const std::string& label) {
      if (!r.posterior.available) return;
      for (const auto& m : r.posterior.marginals)
        rows.push_back({label, m.name, num(m.mean, 4), num(m.sd, 3), num(m.lower, 4),
                        num(m.median, 4), num(m.upper, 4), num(m.effective_sample_size, 4),
                        num(m.r_hat, 4)});
    };
    add_rows(joint, jcal);
    if (alone) add_rows(*alone, acal);
    page.table({"calibration", "parameter", "mean", "sd", "2.5 %", "median", "97.5 %",
                "effective samples", "R-hat"},
               rows, "Calibrated values with 95 % credible intervals");
  }
  page.write(files.html);
  write_text_atomically(files.json, summary.dump(1) + "\n");
  return files;
}

}  // namespace demcal::calibrate
