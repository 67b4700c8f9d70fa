#include "dem/particle_order.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace demcal::dem {

const char* particle_order_name(ParticleOrder order) {
  return order == ParticleOrder::kSpatial ? "spatial" : "insertion";
}

const std::vector<std::string>& particle_order_names() {
  static const std::vector<std::string> names = {"insertion", "spatial"};
  return names;
}

ParticleOrder parse_particle_order(const std::string& name) {
  if (name == "insertion") return ParticleOrder::kInsertion;
  if (name == "spatial") return ParticleOrder::kSpatial;
  throw std::invalid_argument("unknown particle order '" + name +
                              "'; expected \"insertion\" or \"spatial\"");
}

std::vector<std::uint32_t> spatial_order(const std::vector<Vec3>& pos, const Domain& domain,
                                         double cell_m) {
  const std::size_t n = pos.size();
  if (!(cell_m > 0.0) || !std::isfinite(cell_m))
    throw std::invalid_argument("spatial_order: the cell size must be finite and > 0");
  const Vec3 length = domain.length_m();
  std::array<int, 3> nc{};
  std::size_t total = 1;
  for (int k = 0; k < 3; ++k) {
    nc[k] = std::clamp(static_cast<int>(std::floor(length[k] / cell_m)), 1, 1 << 10);
    total *= static_cast<std::size_t>(nc[k]);
  }
  // Memory follows the particles, not the volume (a sparse box).
  while (total > 8 * n + 4096) {
    for (int k = 0; k < 3; ++k) nc[k] = std::max(1, nc[k] / 2);
    total = static_cast<std::size_t>(nc[0]) * nc[1] * nc[2];
  }
  // Slowest axis first: most cells; ties by axis index.
  std::array<int, 3> axis = {0, 1, 2};
  std::stable_sort(axis.begin(), axis.end(), [&](int a, int b) { return nc[a] > nc[b]; });
  std::array<double, 3> inv_cell{};
  for (int k = 0; k < 3; ++k) inv_cell[k] = nc[k] / length[k];

  std::vector<std::uint32_t> cell(n);
  std::vector<std::uint32_t> start(total + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t c = 0;
    for (int a : axis) {
      const double u = (pos[i][a] - domain.lower_m[a]) * inv_cell[a];
      // NaN positions (an unstable run, reported after the step) go to cell 0.
      const int ck = std::isfinite(u) ? static_cast<int>(std::clamp(std::floor(u), 0.0,
                                                                    static_cast<double>(nc[a] - 1)))
                                      : 0;
      c = c * static_cast<std::size_t>(nc[a]) + static_cast<std::size_t>(ck);
    }
    cell[i] = static_cast<std::uint32_t>(c);
    ++start[c + 1];
  }
  for (std::size_t c = 0; c < total; ++c) start[c + 1] += start[c];
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[start[cell[i]]++] = static_cast<std::uint32_t>(i);
  return order;
}

}  // namespace demcal::dem
