#include "dem/apparatus/conical_pile.hpp"

#include "dem/insertion/inserter.hpp"
#include "dem/measure/angle_of_repose.hpp"
#include "dem/wall/bounded_plane_wall.hpp"
#include "dem/wall/cone_wall.hpp"
#include "dem/wall/cylinder_wall.hpp"
#include "dem/wall/orifice_plate_wall.hpp"
#include "dem/wall/plane_wall.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace demcal::dem {
namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

void ConicalPileOptions::validate() const {
  protocol::require_positive("conical_pile", funnel_top_diameter_m, "funnel_top_diameter_m");
  protocol::require_positive("conical_pile", funnel_outlet_diameter_m, "funnel_outlet_diameter_m");
  protocol::require_positive("conical_pile", feed_height_m, "feed_height_m");
  protocol::require_positive("conical_pile", drop_height_m, "drop_height_m");
  protocol::require_positive("conical_pile", base_diameter_m, "base_diameter_m");
  protocol::require_positive("conical_pile", fill_mass_kg, "fill_mass_kg");
  if (funnel_outlet_diameter_m >= funnel_top_diameter_m)
    throw std::invalid_argument(
        "conical_pile: funnel_outlet_diameter_m must be below funnel_top_diameter_m");
  if (!(funnel_half_angle_deg > 0.0 && funnel_half_angle_deg < 80.0))
    throw std::invalid_argument("conical_pile: funnel_half_angle_deg must lie in (0, 80)");
}

ConicalPile::ConicalPile(const ConicalPileOptions& options, const GranularMaterial& material,
                         const RunProtocol& protocol)
    : o_(options), protocol_(protocol) {
  o_.validate();
  if (!material.sizes)
    throw std::invalid_argument("conical_pile: the material has no size distribution");
  auto sizes = scaled_sizes(material.sizes, o_.reduction.coarse_graining_factor);
  diameter_m_ = mean_diameter_m(*sizes);
  const double d_max = sizes->max_diameter_m();
  const bool slice = o_.reduction.slice;
  depth_m_ = slice ? o_.reduction.slice_thickness_diameters * diameter_m_ : 0.0;
  const double rt = 0.5 * o_.funnel_top_diameter_m, ro = 0.5 * o_.funnel_outlet_diameter_m;
  const double rb = 0.5 * o_.base_diameter_m;
  if (o_.funnel_outlet_diameter_m < 4.0 * diameter_m_)
    throw std::invalid_argument(
        "conical_pile: funnel_outlet_diameter_m must be at least 4 particle diameters");
  const double funnel_h = (rt - ro) / std::tan(o_.funnel_half_angle_deg * kPi / 180.0);
  base_height_m_ = std::max(0.3 * rb, 10.0 * d_max);
  outlet_height_m_ = base_height_m_ + o_.drop_height_m;
  const double top = outlet_height_m_ + funnel_h + o_.feed_height_m;
  const double fill_mass =
      slice ? o_.fill_mass_kg * depth_m_ / o_.funnel_top_diameter_m : o_.fill_mass_kg;

  const double margin = d_max;
  const double fill_h = o_.feed_height_m - 2.0 * margin;
  // The catch tray: wide enough for what rolls off the plate.
  const double rc = std::max(2.0 * rb, rt + 4.0 * d_max);
  const double m = 3.0 * d_max;
  const Vec3 lo = slice ? Vec3{-rc - m, 0.0, -m} : Vec3{-rc - m, -rc - m, -m};
  const Vec3 hi = slice ? Vec3{rc + m, depth_m_, top + m} : Vec3{rc + m, rc + m, top + m};
  const double z0 = outlet_height_m_ + funnel_h + margin;
  auto region = fill_h <= 0.0 ? nullptr
                : slice
                    ? make_box_region({-rt + margin, 0.0, z0}, {rt - margin, depth_m_, z0 + fill_h})
                    : make_cylinder_region({0, 0, z0}, rt - margin, fill_h);
  const double cap_kg =
      protocol::particle_cap_kg(*sizes, material.particle.density_kg_m3, protocol);
  const double capacity =
      region ? lattice_capacity_kg(*region, *sizes, material.particle.density_kg_m3,
                                   Domain{lo, hi, {false, slice, false}}, FillOptions{}.lattice_gap,
                                   std::min(fill_mass, cap_kg))
             : 0.0;
  // Counted no further than the fill or the grain cap (see the sandglass).
  if (fill_mass > capacity && capacity <= cap_kg) {
    std::ostringstream s;
    s << "conical_pile: the feed section cannot hold the fill: fill_mass_kg = " << o_.fill_mass_kg
      << " kg needs more than its loose lattice fill takes (" << capacity
      << " kg); raise feed_height_m or funnel_top_diameter_m";
    throw std::invalid_argument(s.str());
  }
  protocol::check_particle_count("conical_pile", fill_mass, *sizes, material.particle.density_kg_m3,
                                 protocol);

  sim_ = std::make_unique<Simulation>(
      protocol::options_for(material, protocol, lo, hi, {false, slice, false}));
  const InstalledMaterials mat =
      install_materials(*sim_, material, o_.reduction, wall_group_names());
  const int p = mat.particle;
  const int floor = mat.wall_for("floor"), base = mat.wall_for("base");
  const int outer = mat.wall_for("outer_wall"), funnel = mat.wall_for("funnel");
  const double never = std::numeric_limits<double>::infinity();
  sim_->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), floor);
  if (slice) {
    sim_->add_wall(std::make_unique<PlaneWall>(Vec3{-rc, 0, 0}, Vec3{1, 0, 0}), outer);
    sim_->add_wall(std::make_unique<PlaneWall>(Vec3{rc, 0, 0}, Vec3{-1, 0, 0}), outer);
    sim_->add_wall(std::make_unique<RectangleWall>(Vec3{0, 0.5 * depth_m_, base_height_m_},
                                                   Vec3{0, 0, 1}, Vec3{1, 0, 0}, rb, depth_m_),
                   base);
    outlet_wall_ = sim_->add_wall(std::make_unique<OrificePlateWall>(OrificePlateWall::slot(
                                      Vec3{0, 0.5 * depth_m_, outlet_height_m_}, Vec3{0, 0, 1},
                                      Vec3{1, 0, 0}, o_.funnel_outlet_diameter_m, never, rt)),
                                  funnel);
    sim_->add_wall(
        make_slab_segment_wall(-ro, outlet_height_m_, -rt, outlet_height_m_ + funnel_h, depth_m_),
        funnel);
    sim_->add_wall(
        make_slab_segment_wall(ro, outlet_height_m_, rt, outlet_height_m_ + funnel_h, depth_m_),
        funnel);
    sim_->add_wall(make_slab_segment_wall(-rt, outlet_height_m_ + funnel_h, -rt, top, depth_m_),
                   funnel);
    sim_->add_wall(make_slab_segment_wall(rt, outlet_height_m_ + funnel_h, rt, top, depth_m_),
                   funnel);
  } else {
    sim_->add_wall(std::make_unique<CylinderWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, base_height_m_, rc),
                   outer);
    sim_->add_wall(std::make_unique<DiskWall>(Vec3{0, 0, base_height_m_}, Vec3{0, 0, 1}, rb), base);
    outlet_wall_ = sim_->add_wall(
        std::make_unique<OrificePlateWall>(OrificePlateWall::circular(
            Vec3{0, 0, outlet_height_m_}, Vec3{0, 0, 1}, o_.funnel_outlet_diameter_m, never, rt)),
        funnel);
    sim_->add_wall(
        std::make_unique<ConeWall>(Vec3{0, 0, outlet_height_m_}, Vec3{0, 0, 1}, funnel_h, ro, rt),
        funnel);
    sim_->add_wall(std::make_unique<CylinderWall>(Vec3{0, 0, outlet_height_m_ + funnel_h},
                                                  Vec3{0, 0, 1}, o_.feed_height_m, rt),
                   funnel);
  }
  FillOptions fill;
  fill.material = p;
  fill.density_kg_m3 = material.particle.density_kg_m3;
  fill.amount.mass_kg = fill_mass;
  fill.method = "lattice";
  sim_->add_inserter(make_fill_inserter(std::move(region), std::move(sizes), fill));
}

ApparatusResult ConicalPile::run(const StepObserver& observe) {
  ApparatusResult r;
  Simulation& sim = *sim_;
  r.details["apparatus"] = name();
  r.details["variant"] = o_.reduction.slice ? "slice" : "full";
  r.details["particle_diameter_m"] = diameter_m_;
  protocol::settle(sim, protocol_, protocol_.max_settle_s, observe, "fill", r.details);
  r.details["particles"] = sim.particles().size();
  static_cast<OrificePlateWall&>(sim.mutable_wall(outlet_wall_)).set_open_time(sim.time_s());
  sim.geometry_changed();
  r.details["pile_settled"] =
      protocol::settle(sim, protocol_, protocol_.max_flow_s, observe, "pour", r.details);

  const auto& pp = sim.particles();
  const double rb = 0.5 * o_.base_diameter_m;
  std::vector<Vec3> pos;
  std::vector<double> rad;
  double reach = 0.0;
  for (std::size_t i = 0; i < pp.size(); ++i) {
    const Vec3& x = pp.position_m[i];
    const double radial = o_.reduction.slice ? std::abs(x.x) : std::hypot(x.x, x.y);
    if (x.z > base_height_m_ && x.z < outlet_height_m_ && radial <= rb) {
      pos.push_back(x);
      rad.push_back(pp.radius_m[i]);
      reach = std::max(reach, radial + pp.radius_m[i]);
    }
  }
  r.details["particles_on_plate"] = pos.size();
  try {
    if (o_.reduction.slice) {
      SliceAoROptions a;
      a.long_axis = 0;
      a.base_height_m = base_height_m_;
      r.series["pile"] = to_json(measure_slice_angle_of_repose(pos, rad, a));
    } else {
      ConicalAoROptions a;
      a.base_height_m = base_height_m_;
      a.axis_centre_m = std::array<double, 2>{0.0, 0.0};
      r.series["pile"] = to_json(measure_conical_angle_of_repose(pos, rad, a));
    }
    r.observables["angle_of_repose_deg"] = r.series["pile"]["angle_of_repose_deg"];
    r.observables["angle_of_repose_uncertainty_deg"] =
        r.series["pile"]["angle_of_repose_uncertainty_deg"];
    r.observables["pile_height_m"] = r.series["pile"]["crest_height_m"];  // above the plate
  } catch (const std::runtime_error& e) {
    r.observables["angle_of_repose_deg"] = nullptr;
    r.details["angle_of_repose_error"] = e.what();
  }
  // The pile covers the plate unless too little was poured; then it is narrower.
  r.observables["pile_base_diameter_m"] = 2.0 * std::min(reach, rb);
  return r;
}

}  // namespace demcal::dem
