#include "dem/insertion/region.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace demcal::dem {
namespace {

class BoxRegion final : public Region {
 public:
  BoxRegion(const Vec3& lo, const Vec3& hi) : lo_(lo), hi_(hi) {
    for (int k = 0; k < 3; ++k)
      if (!(hi[k] > lo[k]))
        throw std::invalid_argument("box region: upper_m must exceed lower_m on every axis");
  }
  Vec3 sample(Random& rng, double margin) const override {
    Vec3 p;
    for (int k = 0; k < 3; ++k) {
      const double a = lo_[k] + margin, b = hi_[k] - margin;
      p[k] = a < b ? rng.uniform(a, b) : 0.5 * (lo_[k] + hi_[k]);
    }
    return p;
  }
  bool contains(const Vec3& p, double margin) const override {
    for (int k = 0; k < 3; ++k)
      if (p[k] - margin < lo_[k] || p[k] + margin > hi_[k]) return false;
    return true;
  }
  double volume_m3() const override {
    const Vec3 l = hi_ - lo_;
    return l.x * l.y * l.z;
  }
  Vec3 lower_m() const override { return lo_; }
  Vec3 upper_m() const override { return hi_; }
  std::string describe() const override {
    std::ostringstream s;
    s << "box [" << lo_.x << ", " << lo_.y << ", " << lo_.z << "] - [" << hi_.x << ", " << hi_.y
      << ", " << hi_.z << "] m";
    return s.str();
  }

 private:
  Vec3 lo_, hi_;
};

class CylinderRegion final : public Region {
 public:
  CylinderRegion(const Vec3& base, double radius, double height)
      : base_(base), radius_(radius), height_(height) {
    if (!(radius > 0.0)) throw std::invalid_argument("cylinder region: radius_m must be > 0");
    if (!(height > 0.0)) throw std::invalid_argument("cylinder region: height_m must be > 0");
  }
  Vec3 sample(Random& rng, double margin) const override {
    const double r_max = std::max(0.0, radius_ - margin);
    // sqrt of a uniform variate: uniform density over the disk's area.
    const double r = r_max * std::sqrt(rng.uniform());
    const double phi = 2.0 * std::numbers::pi * rng.uniform();
    const double z0 = margin, z1 = height_ - margin;
    const double z = z0 < z1 ? rng.uniform(z0, z1) : 0.5 * height_;
    return base_ + Vec3{r * std::cos(phi), r * std::sin(phi), z};
  }
  bool contains(const Vec3& p, double margin) const override {
    const Vec3 d = p - base_;
    if (d.z - margin < 0.0 || d.z + margin > height_) return false;
    return std::sqrt(d.x * d.x + d.y * d.y) + margin <= radius_;
  }
  double volume_m3() const override { return std::numbers::pi * radius_ * radius_ * height_; }
  Vec3 lower_m() const override { return base_ - Vec3{radius_, radius_, 0.0}; }
  Vec3 upper_m() const override { return base_ + Vec3{radius_, radius_, height_}; }
  std::string describe() const override {
    std::ostringstream s;
    s << "cylinder radius " << radius_ << " m, height " << height_ << " m";
    return s.str();
  }

 private:
  Vec3 base_;
  double radius_, height_;
};

}  // namespace

std::unique_ptr<Region> make_box_region(const Vec3& lower_m, const Vec3& upper_m) {
  return std::make_unique<BoxRegion>(lower_m, upper_m);
}
std::unique_ptr<Region> make_cylinder_region(const Vec3& base_centre_m, double radius_m,
                                             double height_m) {
  return std::make_unique<CylinderRegion>(base_centre_m, radius_m, height_m);
}

}  // namespace demcal::dem
