#include "calibrate/region_components.hpp"

#include "calibrate/confidence_region.hpp"
#include "calibrate/detail/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace demcal::calibrate {

RegionComponents region_components(const std::vector<std::vector<double>>& axes,
                                   const std::vector<bool>& inside, const Eigen::VectorXd& best,
                                   const Eigen::MatrixXd& design_points) {
  const std::size_t p = axes.size();
  if (p == 0) throw std::invalid_argument("region_components: no axes");
  std::size_t n = 1;
  std::vector<std::size_t> stride(p);
  for (std::size_t a = 0; a < p; ++a) {
    if (axes[a].empty()) throw std::invalid_argument("region_components: an empty axis");
    stride[a] = n;
    n *= axes[a].size();
  }
  if (inside.size() != n)
    throw std::invalid_argument("region_components: inside has not one entry per node");
  if (best.size() != 0 && static_cast<std::size_t>(best.size()) != p)
    throw std::invalid_argument("region_components: the best point has not one value per axis");
  if (design_points.rows() > 0 && static_cast<std::size_t>(design_points.cols()) != p)
    throw std::invalid_argument("region_components: design points have not one column per axis");
  const std::vector<double> measure = grid_cell_measures(axes);
  const auto coordinate = [&](std::size_t node, std::size_t a) {
    return (node / stride[a]) % axes[a].size();
  };

  // Flood fill over face neighbours.
  std::vector<int> label(n, -1);
  std::vector<RegionComponent> parts;
  std::vector<std::size_t> stack;
  for (std::size_t start = 0; start < n; ++start) {
    if (!inside[start] || label[start] >= 0) continue;
    const int id = static_cast<int>(parts.size());
    RegionComponent c;
    c.lower.assign(p, std::numeric_limits<double>::infinity());
    c.upper.assign(p, -std::numeric_limits<double>::infinity());
    label[start] = id;
    stack.assign(1, start);
    while (!stack.empty()) {
      const std::size_t node = stack.back();
      stack.pop_back();
      ++c.nodes;
      c.area += measure[node];
      for (std::size_t a = 0; a < p; ++a) {
        const std::size_t i = coordinate(node, a);
        c.lower[a] = std::min(c.lower[a], axes[a][i]);
        c.upper[a] = std::max(c.upper[a], axes[a][i]);
        if (i > 0 && inside[node - stride[a]] && label[node - stride[a]] < 0) {
          label[node - stride[a]] = id;
          stack.push_back(node - stride[a]);
        }
        if (i + 1 < axes[a].size() && inside[node + stride[a]] && label[node + stride[a]] < 0) {
          label[node + stride[a]] = id;
          stack.push_back(node + stride[a]);
        }
      }
    }
    parts.push_back(c);
  }

  // The best point's node: nearest along each axis.
  if (best.size() != 0) {
    std::size_t node = 0;
    for (std::size_t a = 0; a < p; ++a) {
      const auto& ax = axes[a];
      std::size_t k = 0;
      for (std::size_t i = 1; i < ax.size(); ++i)
        if (std::abs(ax[i] - best(static_cast<Eigen::Index>(a))) <
            std::abs(ax[k] - best(static_cast<Eigen::Index>(a))))
          k = i;
      node += k * stride[a];
    }
    if (label[node] >= 0) parts[static_cast<std::size_t>(label[node])].holds_best = true;
  }
  // Design points in each part's bounding box, widened by half a grid cell.
  for (auto& c : parts) {
    for (Eigen::Index r = 0; r < design_points.rows(); ++r) {
      bool in = true;
      for (std::size_t a = 0; a < p && in; ++a) {
        const double half = axes[a].size() > 1
                                ? 0.5 * (axes[a].back() - axes[a].front()) / (axes[a].size() - 1)
                                : 0.0;
        const double v = design_points(r, static_cast<Eigen::Index>(a));
        in = v >= c.lower[a] - half && v <= c.upper[a] + half;
      }
      c.design_points += in;
    }
    c.between_design_points = !c.holds_best && c.design_points == 0 && design_points.rows() > 0;
  }

  // Order: the best point's part first, then by area.
  std::vector<std::size_t> order(parts.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (parts[a].holds_best != parts[b].holds_best) return parts[a].holds_best;
    return parts[a].area > parts[b].area;
  });
  std::vector<int> rank(parts.size());
  RegionComponents out;
  for (std::size_t k = 0; k < order.size(); ++k) {
    rank[order[k]] = static_cast<int>(k);
    out.parts.push_back(parts[order[k]]);
  }
  for (auto& l : label)
    if (l >= 0) l = rank[static_cast<std::size_t>(l)];
  out.label = std::move(label);
  return out;
}

std::string describe_components(const RegionComponents& c, const std::vector<std::string>& names) {
  using detail::fmt;
  if (c.parts.empty()) return "empty (no grid node inside)";
  if (c.parts.size() == 1) return "one connected part";
  std::ostringstream s;
  s << c.parts.size() << " separate parts";
  for (std::size_t k = 0; k < c.parts.size(); ++k) {
    const auto& part = c.parts[k];
    s << (k ? "; " : ": ") << "part " << k + 1 << " (";
    for (std::size_t a = 0; a < part.lower.size(); ++a) {
      s << (a ? ", " : "");
      if (a < names.size())
        s << names[a];
      else
        s << "x" << a;
      s << " " << fmt(part.lower[a]) << "–" << fmt(part.upper[a]);
    }
    s << ", area " << fmt(part.area, 2) << ")";
    if (part.holds_best) s << " holds the best point";
    if (part.between_design_points)
      s << " holds no design point: only the surrogate's uncertainty between design points admits "
           "it — add design "
           "points there to confirm or remove it";
  }
  return s.str();
}

}  // namespace demcal::calibrate
