#include "dem/insertion/inserter.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

namespace demcal::dem {
namespace {

class FillInserter final : public Inserter {
 public:
  FillInserter(std::unique_ptr<Region> region, std::unique_ptr<SizeDistribution> sizes,
               const FillOptions& o)
      : region_(std::move(region)), sizes_(std::move(sizes)), o_(o) {
    if (o.amount.count == 0 && o.amount.mass_kg <= 0.0)
      throw std::invalid_argument("fill: give count or mass_kg (how much to insert)");
    if (o.method != "random" && o.method != "lattice")
      throw std::invalid_argument("fill: method must be \"random\" or \"lattice\", not \"" +
                                  o.method + "\"");
  }

  bool due(double t) const override { return !done_ && t >= o_.time_s; }

  void insert(InsertionContext& ctx) override {
    if (o_.method == "lattice")
      fill_lattice(ctx);
    else
      fill_random(ctx);
    done_ = true;
    if (!reached()) {
      std::ostringstream msg;
      msg << "fill: the region (" << region_->describe() << ") cannot hold the requested amount ("
          << describe_amount() << "); placed " << inserted_ << " particles, " << mass_
          << " kg. Enlarge the region or use method = \"lattice\"";
      throw std::runtime_error(msg.str());
    }
  }

  bool finished() const override { return done_; }
  std::size_t inserted() const override { return inserted_; }
  int material() const override { return o_.material; }
  double inserted_mass_kg() const override { return mass_; }
  const SizeDistribution& sizes() const override { return *sizes_; }
  const Region& region() const override { return *region_; }
  std::string describe() const override {
    return "fill (" + o_.method + ") " + region_->describe() + " with " + describe_amount() + ", " +
           sizes_->describe();
  }

 private:
  bool reached() const {
    if (o_.amount.count > 0 && inserted_ >= o_.amount.count) return true;
    if (o_.amount.mass_kg > 0.0 && mass_ >= o_.amount.mass_kg) return true;
    return false;
  }
  std::string describe_amount() const {
    std::ostringstream s;
    if (o_.amount.count > 0) s << o_.amount.count << " particles";
    if (o_.amount.count > 0 && o_.amount.mass_kg > 0.0) s << " or ";
    if (o_.amount.mass_kg > 0.0) s << o_.amount.mass_kg << " kg";
    return s.str();
  }
  void place(InsertionContext& ctx, const Vec3& c, double r) {
    ctx.add(c, r, o_.material, Vec3{});
    ++inserted_;
    mass_ += o_.density_kg_m3 * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  }

  void fill_random(InsertionContext& ctx) {
    while (!reached()) {
      const double r = 0.5 * sizes_->sample_diameter_m(ctx.rng());
      bool placed = false;
      for (int a = 0; a < o_.attempts_per_particle && !placed; ++a) {
        const Vec3 c = region_->sample(ctx.rng(), r);
        if (ctx.is_free(c, r)) {
          place(ctx, c, r);
          placed = true;
        }
      }
      if (!placed) return;  // region full at this looseness
    }
  }

  // Lattice sites from the bottom up, so a partial fill is a settled-looking layer stack.
  void fill_lattice(InsertionContext& ctx) {
    const double d_max = sizes_->max_diameter_m();
    const double spacing = d_max * (1.0 + o_.lattice_gap);
    const double jitter = 0.5 * (spacing - d_max);
    for_each_lattice_site(*region_, d_max, o_.lattice_gap, ctx.domain(), [&](const Vec3& site) {
      if (reached()) return false;
      const double r = 0.5 * sizes_->sample_diameter_m(ctx.rng());
      const double slack = std::max(0.0, 0.5 * (spacing - 2.0 * r) - 1e-12);
      const double j = std::min(jitter + 0.5 * (d_max - 2.0 * r), slack);
      const Vec3 c =
          site + Vec3{ctx.rng().uniform(-j, j), ctx.rng().uniform(-j, j), ctx.rng().uniform(-j, j)};
      // The region may be round (a cylinder): keep only sites inside it.
      if (region_->contains(c, r) && ctx.is_free(c, r)) place(ctx, c, r);
      return true;
    });
  }

  std::unique_ptr<Region> region_;
  std::unique_ptr<SizeDistribution> sizes_;
  FillOptions o_;
  bool done_ = false;
  std::size_t inserted_ = 0;
  double mass_ = 0.0;
};

}  // namespace

// 10^7 sites along one axis: 10 km of 1 mm grains.
constexpr double kMaxLatticeSitesPerAxis = 1e7;

void for_each_lattice_site(const Region& region, double max_diameter_m, double lattice_gap,
                           const Domain& domain, const std::function<bool(const Vec3&)>& visit) {
  const double spacing = max_diameter_m * (1.0 + lattice_gap);
  const Vec3 lo = region.lower_m(), hi = region.upper_m();
  const Vec3 len = domain.length_m();
  std::array<int, 3> n{};
  for (int k = 0; k < 3; ++k) {
    // Along a periodic axis the lattice must tile the period, or the seam overlaps.
    // The 1e-6 keeps a length of exactly n spacings (4 sites in a 5 d slab at
    // 1.25 d) from losing a site to rounding.
    const double extent = hi[k] - lo[k];
    double sites = std::floor(extent / spacing + 1e-6);
    if (domain.periodic[k] && std::abs(extent - len[k]) < 1e-12 * len[k])
      sites = std::floor(len[k] / spacing + 1e-6);
    // A count past any real fill (a length or size off by orders of magnitude)
    // is refused before it is turned into an int it may not fit.
    if (!(sites <= kMaxLatticeSitesPerAxis)) {
      std::ostringstream m;
      m << "the fill region is " << extent << " m across, " << sites << " lattice spacings of "
        << spacing << " m (grains of " << max_diameter_m << " m), more than "
        << kMaxLatticeSitesPerAxis
        << " along one axis: check the apparatus' lengths and the grain size";
      throw std::invalid_argument(m.str());
    }
    n[k] = static_cast<int>(sites);
  }
  // Bottom up, so a partial fill is a settled-looking stack of layers.
  for (int iz = 0; iz < n[2]; ++iz)
    for (int iy = 0; iy < n[1]; ++iy)
      for (int ix = 0; ix < n[0]; ++ix) {
        const Vec3 c{lo.x + (ix + 0.5) * ((hi.x - lo.x) / n[0]),
                     lo.y + (iy + 0.5) * ((hi.y - lo.y) / n[1]), lo.z + (iz + 0.5) * spacing};
        // Half a spacing of margin: a jittered particle at the site stays inside.
        // Less a rounding allowance: a region exactly n spacings wide puts its
        // outer sites exactly half a spacing from its faces.
        if (region.contains(c, 0.5 * spacing * (1.0 - 2e-6)) && !visit(c)) return;
      }
}

std::vector<Vec3> lattice_sites(const Region& region, double max_diameter_m, double lattice_gap,
                                const Domain& domain, std::size_t max_sites) {
  std::vector<Vec3> sites;
  if (max_sites == 0) return sites;
  for_each_lattice_site(region, max_diameter_m, lattice_gap, domain, [&](const Vec3& c) {
    sites.push_back(c);
    return sites.size() < max_sites;
  });
  return sites;
}

std::unique_ptr<Inserter> make_fill_inserter(std::unique_ptr<Region> region,
                                             std::unique_ptr<SizeDistribution> sizes,
                                             const FillOptions& options) {
  return std::make_unique<FillInserter>(std::move(region), std::move(sizes), options);
}

}  // namespace demcal::dem
