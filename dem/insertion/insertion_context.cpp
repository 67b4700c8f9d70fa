#include "dem/insertion/insertion_context.hpp"

#include <cmath>

namespace demcal::dem {

InsertionContext::InsertionContext(double time_s, const Domain& domain,
                                   const Particles& particles,
                                   const std::vector<const Wall*>& walls, Random& rng,
                                   const Vec3& lower_m, const Vec3& upper_m, double max_radius_m,
                                   AddFn add)
    : time_s_(time_s), domain_(domain), walls_(walls), rng_(rng), add_(std::move(add)) {
  double r_max = max_radius_m;
  for (double r : particles.radius_m) r_max = std::max(r_max, r);
  cell_m_ = 2.0 * r_max;
  const Vec3 len = domain.length_m();
  for (int k = 0; k < 3; ++k)
    wrap_[k] = domain.periodic[k] ? std::max(1, static_cast<int>(std::floor(len[k] / cell_m_))) : 0;
  if (cell_m_ <= 0.0) cell_m_ = 1.0;
  const Vec3 lo = lower_m - Vec3{cell_m_, cell_m_, cell_m_};
  const Vec3 hi = upper_m + Vec3{cell_m_, cell_m_, cell_m_};
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Vec3& p = particles.position_m[i];
    bool near = true;
    for (int k = 0; k < 3; ++k)
      if (!domain.periodic[k] && (p[k] < lo[k] || p[k] > hi[k])) near = false;
    if (near) grid_[key(p)].push_back({p, particles.radius_m[i]});
  }
}

std::array<int, 3> InsertionContext::coords(const Vec3& p) const {
  std::array<int, 3> c{};
  for (int k = 0; k < 3; ++k) {
    if (wrap_[k] > 0) {
      const double cell = domain_.length_m()[k] / wrap_[k];
      int ck = static_cast<int>(std::floor((p[k] - domain_.lower_m[k]) / cell));
      c[k] = ((ck % wrap_[k]) + wrap_[k]) % wrap_[k];
    } else {
      c[k] = static_cast<int>(std::floor(p[k] / cell_m_));
    }
  }
  return c;
}

std::int64_t InsertionContext::key(const Vec3& p) const {
  const auto c = coords(p);
  constexpr std::int64_t kSpan = 1 << 20;
  return ((c[0] + kSpan / 2) * kSpan + (c[1] + kSpan / 2)) * kSpan + (c[2] + kSpan / 2);
}

bool InsertionContext::is_free(const Vec3& centre, double radius) const {
  for (const Wall* w : walls_) {
    WallContactPoint cp;
    if (w->nearest_point(centre, radius, time_s_, cp) && cp.distance_m < radius) return false;
  }
  const auto c = coords(centre);
  const Vec3 len = domain_.length_m();
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        std::array<int, 3> n = {c[0] + dx, c[1] + dy, c[2] + dz};
        for (int k = 0; k < 3; ++k)
          if (wrap_[k] > 0) n[k] = ((n[k] % wrap_[k]) + wrap_[k]) % wrap_[k];
        constexpr std::int64_t kSpan = 1 << 20;
        const std::int64_t key =
            ((n[0] + kSpan / 2) * kSpan + (n[1] + kSpan / 2)) * kSpan + (n[2] + kSpan / 2);
        const auto it = grid_.find(key);
        if (it == grid_.end()) continue;
        for (const Entry& e : it->second) {
          Vec3 d = centre - e.centre;
          for (int k = 0; k < 3; ++k)
            if (domain_.periodic[k]) d[k] -= len[k] * std::round(d[k] / len[k]);
          const double reach = radius + e.radius;
          if (norm2(d) < reach * reach) return false;
        }
      }
  return true;
}

void InsertionContext::add(const Vec3& centre, double radius, int material, const Vec3& velocity) {
  add_(centre, radius, material, velocity);
  grid_[key(centre)].push_back({centre, radius});
}

}  // namespace demcal::dem
