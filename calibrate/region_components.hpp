#pragma once
// The connected parts of a region on a grid: a 95 % region that falls apart into
// islands must be reported as such, not as "one minimum". Two nodes are
// connected when they are inside and neighbours along one axis (4-connectivity
// in 2-D, 6 in 3-D). A part that holds no design point and not the best point
// exists only between design points, where the surrogate's variance (added to
// sigma_total) rather than a DEM run allows it: it is flagged, with the advice
// to put design points there.

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace demcal::calibrate {

struct RegionComponent {
  std::size_t nodes = 0;
  double area = 0.0;                 // parameter units, as LikelihoodRegion::area
  std::vector<double> lower, upper;  // per parameter: extent of the part's nodes
  bool holds_best = false;           // the node nearest the best point is in it
  std::size_t design_points = 0;     // design points inside its bounding box (+ half a cell)
  // Not the best point's part and no design point in it: the surrogate's variance
  // between design points, not a DEM run, allows it.
  bool between_design_points = false;
};

struct RegionComponents {
  std::vector<RegionComponent> parts;  // the best point's part first, then by area, largest first
  std::vector<int> label;              // per node (region layout): index into parts, -1 outside
};

// `axes` and `inside` in LikelihoodRegion's layout (first axis fastest). `best`: the best
// point (may be empty: no part holds it). `design_points`: rows of inputs (may have 0 rows).
// Throws std::invalid_argument when sizes disagree.
RegionComponents region_components(const std::vector<std::vector<double>>& axes,
                                   const std::vector<bool>& inside,
                                   const Eigen::VectorXd& best = Eigen::VectorXd(),
                                   const Eigen::MatrixXd& design_points = Eigen::MatrixXd());

// "one connected part" / "3 separate parts: ... ; part 2 (mu_r 0.09-0.18, mu_s 0.76-0.87)
// holds no design point ..." (names: the parameters').
std::string describe_components(const RegionComponents& c, const std::vector<std::string>& names);

}  // namespace demcal::calibrate
