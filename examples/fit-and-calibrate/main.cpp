// Fits a surrogate of each output of your own table and calibrates its inputs
// against measured values, through an installed demcal (find_package(demcal)).
//
// The table (table.csv here, or the file given): a header, then one row per run,
// with the inputs a and b, a replicate index, and the outputs height_m and
// spread_m. Rows with equal inputs are replicates: their scatter is the
// simulator's own, which the calibration adds to the measurement's.
//
// Exits 0 when the best fit lies within 0.05 of where the measurements were
// made (a = 0.4, b = 0.5), 1 otherwise, so that CI notices a broken pipeline.
#include "calibrate/calibration.hpp"
#include "surrogate/surrogate_fit.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace sg = demcal::surrogate;
namespace cal = demcal::calibrate;

struct Row {
  double a, b, height_m, spread_m;
};

std::vector<Row> read_table(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read " + file);
  std::string line;
  std::getline(in, line);  // header
  std::vector<Row> rows;
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    std::istringstream s(line);
    Row r{};
    char c1 = 0, c2 = 0, c3 = 0, c4 = 0;
    int replicate = 0;
    if (!(s >> r.a >> c1 >> r.b >> c2 >> replicate >> c3 >> r.height_m >> c4 >> r.spread_m) ||
        c1 != ',' || c2 != ',' || c3 != ',' || c4 != ',')
      throw std::runtime_error(file + ":" + std::to_string(n) +
                               ": expected a,b,replicate,height_m,spread_m");
    rows.push_back(r);
  }
  return rows;
}

sg::ReplicatedData data_for(const std::vector<Row>& rows, double Row::*output, const char* name) {
  sg::ReplicatedData d;
  d.input_names = {"a", "b"};
  d.lower = {0.1, 0.2};
  d.upper = {0.7, 0.8};
  d.output_name = name;
  d.x.resize(static_cast<Eigen::Index>(rows.size()), 2);
  d.y.resize(static_cast<Eigen::Index>(rows.size()));
  std::map<std::pair<double, double>, int> points;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    d.x(k, 0) = rows[i].a;
    d.x(k, 1) = rows[i].b;
    d.y(k) = rows[i].*output;
    const auto key = std::make_pair(rows[i].a, rows[i].b);
    const auto it = points.emplace(key, static_cast<int>(points.size())).first;
    d.group.push_back(it->second);
  }
  return d;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string file = argc > 1 ? argv[1] : "table.csv";
    const std::vector<Row> rows = read_table(file);
    sg::SurrogateSpec spec;
    spec.model = "polynomial";  // degree chosen by leave-one-out
    const sg::FittedSurrogate height = sg::fit_surrogate(data_for(rows, &Row::height_m, "height_m"), spec);
    const sg::FittedSurrogate spread = sg::fit_surrogate(data_for(rows, &Row::spread_m, "spread_m"), spec);
    std::cout << "height_m: " << height.model->description() << "\n"
              << "spread_m: " << spread.model->description() << "\n";

    // What was measured (at a = 0.4, b = 0.5), with its standard uncertainty.
    std::vector<cal::Target> targets(2);
    targets[0] = {"bench", "height_m", 0.370, 0.003, height.scatter.sd, height.model, true};
    targets[1] = {"bench", "spread_m", 0.078, 0.003, spread.scatter.sd, spread.model, true};
    cal::CalibrationOptions options;
    options.mcmc_samples = 0;  // minima and likelihood-ratio region only: fast
    options.grid_points_per_axis = 41;
    const cal::CalibrationResult result =
        cal::calibrate({{"a", 0.1, 0.7}, {"b", 0.2, 0.8}}, targets, options);
    const cal::Minimum& best = result.minima.at(0);
    std::printf("best fit: a = %.4f, b = %.4f, chi2 = %.3g\n", best.theta(0), best.theta(1),
                best.chi_squared);
    for (const std::string& note : result.notes) std::cout << "note: " << note << "\n";
    const bool close = std::abs(best.theta(0) - 0.4) < 0.05 && std::abs(best.theta(1) - 0.5) < 0.05;
    std::cout << (close ? "recovered the measured point\n" : "did NOT recover the measured point\n");
    return close ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "fit_and_calibrate: " << e.what() << "\n";
    return 2;
  }
}
