#include "dem/insertion/inserter.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace demcal::dem {
namespace {

class PourInserter final : public Inserter {
 public:
  PourInserter(std::unique_ptr<Region> region, std::unique_ptr<SizeDistribution> sizes,
               const PourOptions& o)
      : region_(std::move(region)), sizes_(std::move(sizes)), o_(o) {
    if (o.amount.count == 0 && o.amount.mass_kg <= 0.0)
      throw std::invalid_argument("pour: give count or mass_kg (how much to pour)");
    if (o.rate_particles_per_s < 0.0) throw std::invalid_argument("pour: rate must be >= 0");
    if (o.rate_particles_per_s == 0.0 && !(o.batch_volume_fraction > 0.0 && o.batch_volume_fraction < 0.6))
      throw std::invalid_argument("pour: batch_volume_fraction must lie in (0, 0.6)");
    next_s_ = o.start_s;
    if (o.rate_particles_per_s == 0.0) {
      // Time for a particle to fall through the region's height: the next batch
      // then finds the region empty.
      const double h = region_->upper_m().z - region_->lower_m().z;
      const double g = std::max(1e-12, std::abs(o.gravity_m_s2.z));
      const double v0 = std::abs(std::min(0.0, o.velocity_m_s.z));
      interval_s_ = (-v0 + std::sqrt(v0 * v0 + 2.0 * g * h)) / g;
      const double mean_volume = std::numbers::pi / 6.0 * sizes_->mean_diameter_cubed_m3();
      batch_ = std::max<std::size_t>(
          1, static_cast<std::size_t>(o.batch_volume_fraction * region_->volume_m3() / mean_volume));
    }
  }

  bool due(double t) const override { return !finished() && t >= next_s_; }

  void insert(InsertionContext& ctx) override {
    std::size_t wanted;
    if (o_.rate_particles_per_s > 0.0) {
      const double elapsed = ctx.time_s() - o_.start_s;
      const auto target = static_cast<std::size_t>(std::floor(elapsed * o_.rate_particles_per_s)) + 1;
      wanted = target > inserted_ ? target - inserted_ : 0;
      next_s_ = o_.start_s + static_cast<double>(inserted_ + wanted) / o_.rate_particles_per_s;
    } else {
      wanted = batch_;
      next_s_ = ctx.time_s() + interval_s_;
    }
    std::size_t placed_now = 0;
    for (std::size_t k = 0; k < wanted && !finished(); ++k) {
      const double r = 0.5 * sizes_->sample_diameter_m(ctx.rng());
      bool placed = false;
      for (int a = 0; a < o_.attempts_per_particle && !placed; ++a) {
        const Vec3 c = region_->sample(ctx.rng(), r);
        if (!ctx.is_free(c, r)) continue;
        ctx.add(c, r, o_.material, o_.velocity_m_s);
        ++inserted_;
        ++placed_now;
        mass_ += o_.density_kg_m3 * 4.0 / 3.0 * std::numbers::pi * r * r * r;
        placed = true;
      }
    }
    // A region that stays blocked (the heap has grown into it) would stall the pour for ever.
    if (placed_now == 0 && wanted > 0) {
      if (++blocked_events_ > 1000) {
        std::ostringstream msg;
        msg << "pour: the insertion region (" << region_->describe()
            << ") has stayed blocked; poured " << inserted_ << " particles so far";
        throw std::runtime_error(msg.str());
      }
    } else {
      blocked_events_ = 0;
    }
  }

  bool finished() const override {
    if (o_.amount.count > 0 && inserted_ >= o_.amount.count) return true;
    if (o_.amount.mass_kg > 0.0 && mass_ >= o_.amount.mass_kg) return true;
    return false;
  }
  std::size_t inserted() const override { return inserted_; }
  int material() const override { return o_.material; }
  double inserted_mass_kg() const override { return mass_; }
  const SizeDistribution& sizes() const override { return *sizes_; }
  const Region& region() const override { return *region_; }
  std::string describe() const override {
    std::ostringstream s;
    s << "pour into " << region_->describe() << ", " << sizes_->describe();
    return s.str();
  }

 private:
  std::unique_ptr<Region> region_;
  std::unique_ptr<SizeDistribution> sizes_;
  PourOptions o_;
  double next_s_ = 0.0;
  double interval_s_ = 0.0;
  std::size_t batch_ = 0;
  std::size_t inserted_ = 0;
  double mass_ = 0.0;
  int blocked_events_ = 0;
};

}  // namespace

std::unique_ptr<Inserter> make_pour_inserter(std::unique_ptr<Region> region,
                                             std::unique_ptr<SizeDistribution> sizes,
                                             const PourOptions& options) {
  return std::make_unique<PourInserter>(std::move(region), std::move(sizes), options);
}

}  // namespace demcal::dem
