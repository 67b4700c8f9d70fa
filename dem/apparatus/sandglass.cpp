#include "dem/apparatus/sandglass.hpp"

#include "dem/insertion/inserter.hpp"
#include "dem/measure/angle_of_repose.hpp"
#include "dem/measure/discharge.hpp"
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

void SandglassOptions::validate() const {
  protocol::require_positive("sandglass", upper_diameter_m, "upper_diameter_m");
  protocol::require_positive("sandglass", upper_height_m, "upper_height_m");
  protocol::require_positive("sandglass", orifice_diameter_m, "orifice_diameter_m");
  protocol::require_positive("sandglass", fill_mass_kg, "fill_mass_kg");
  protocol::require_positive("sandglass", lower_diameter_m, "lower_diameter_m");
  protocol::require_positive("sandglass", drop_height_m, "drop_height_m");
  if (bottom != "flat" && bottom != "conical")
    throw std::invalid_argument("sandglass: bottom must be \"flat\" or \"conical\", not \"" +
                                bottom + "\"");
  if (!(hopper_half_angle_deg > 0.0 && hopper_half_angle_deg < 80.0))
    throw std::invalid_argument(
        "sandglass: hopper_half_angle_deg must lie in (0, 80) degrees from the vertical");
  if (orifice_diameter_m >= upper_diameter_m)
    throw std::invalid_argument(
        "sandglass: orifice_diameter_m must be smaller than upper_diameter_m");
  if (lower_diameter_m < upper_diameter_m)
    throw std::invalid_argument(
        "sandglass: lower_diameter_m must be at least upper_diameter_m (the lower chamber "
        "surrounds the upper one's outlet)");
  if (!(fill_lattice_spacing_diameters > 1.0 && fill_lattice_spacing_diameters <= 3.0))
    throw std::invalid_argument("sandglass: fill_lattice_spacing_diameters must lie in (1, 3]");
  if (reduction.slice && !(reduction.slice_thickness_diameters >= 2.0))
    throw std::invalid_argument("sandglass: slice_thickness_diameters must be >= 2");
}

Sandglass::Sandglass(const SandglassOptions& options, const GranularMaterial& material,
                     const RunProtocol& protocol)
    : o_(options), protocol_(protocol) {
  o_.validate();
  if (!material.sizes)
    throw std::invalid_argument("sandglass: the material has no size distribution");
  auto sizes = scaled_sizes(material.sizes, o_.reduction.coarse_graining_factor);
  diameter_m_ = mean_diameter_m(*sizes);
  const double d_max = sizes->max_diameter_m();
  const bool slice = o_.reduction.slice;
  const double ru = 0.5 * o_.upper_diameter_m;
  const double rl = 0.5 * o_.lower_diameter_m;
  const double r0 = 0.5 * o_.orifice_diameter_m;
  const double zo = o_.drop_height_m;
  cone_height_m_ =
      o_.bottom == "conical" ? (ru - r0) / std::tan(o_.hopper_half_angle_deg * kPi / 180.0) : 0.0;
  top_m_ = zo + cone_height_m_ + o_.upper_height_m;
  depth_m_ = slice ? o_.reduction.slice_thickness_diameters * diameter_m_ : 0.0;
  fill_mass_kg_ = slice ? o_.fill_mass_kg * depth_m_ / o_.upper_diameter_m : o_.fill_mass_kg;

  if (o_.orifice_diameter_m < 3.0 * diameter_m_) {
    std::ostringstream s;
    s << "sandglass: orifice_diameter_m (" << o_.orifice_diameter_m
      << " m) is below 3 particle diameters (" << 3.0 * diameter_m_
      << " m); the flow would arch at once. Widen it or reduce coarse_graining_factor";
    throw std::invalid_argument(s.str());
  }

  // The fill goes into the cylindrical part as a jittered lattice; check the
  // lattice has the sites before anything is built.
  const double margin = d_max;
  const double fill_height = o_.upper_height_m - 2.0 * margin;
  const double m = 3.0 * d_max;
  const Vec3 lo = slice ? Vec3{-rl - m, 0.0, -m} : Vec3{-rl - m, -rl - m, -m};
  const Vec3 hi = slice ? Vec3{rl + m, depth_m_, top_m_ + m} : Vec3{rl + m, rl + m, top_m_ + m};
  const double z0 = zo + cone_height_m_ + margin;
  auto region =
      fill_height <= 0.0 ? nullptr
      : slice ? make_box_region({-ru + margin, 0.0, z0}, {ru - margin, depth_m_, z0 + fill_height})
              : make_cylinder_region({0, 0, z0}, ru - margin, fill_height);
  const double cap_kg =
      protocol::particle_cap_kg(*sizes, material.particle.density_kg_m3, protocol);
  const double capacity_kg =
      region ? lattice_capacity_kg(*region, *sizes, material.particle.density_kg_m3,
                                   Domain{lo, hi, {false, slice, false}},
                                   o_.fill_lattice_spacing_diameters - 1.0,
                                   std::min(fill_mass_kg_, cap_kg))
             : 0.0;
  // Counted no further than the fill or the grain cap: beyond the cap the
  // capacity is unknown, and the fill is refused for its grain count below.
  if (fill_mass_kg_ > capacity_kg && capacity_kg <= cap_kg) {
    std::ostringstream s;
    s << "sandglass: the upper chamber cannot hold the fill: fill_mass_kg = " << o_.fill_mass_kg
      << " kg" << (slice ? " (the slice's share " + std::to_string(fill_mass_kg_) + " kg)" : "")
      << " needs more than the loose lattice fill of its cylindrical part takes (" << capacity_kg
      << " kg); raise upper_height_m or upper_diameter_m, or lower fill_mass_kg";
    throw std::invalid_argument(s.str());
  }
  protocol::check_particle_count("sandglass", fill_mass_kg_, *sizes,
                                 material.particle.density_kg_m3, protocol);

  sim_ = std::make_unique<Simulation>(
      protocol::options_for(material, protocol, lo, hi, {false, slice, false}));
  const InstalledMaterials mat =
      install_materials(*sim_, material, o_.reduction, wall_group_names());
  const int p = mat.particle;
  const int floor = mat.wall_for("floor"), lower = mat.wall_for("lower_wall");
  const int plate = mat.wall_for("orifice_plate"), hopper = mat.wall_for("hopper");

  sim_->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), floor);
  const double never = std::numeric_limits<double>::infinity();
  if (slice) {
    sim_->add_wall(std::make_unique<PlaneWall>(Vec3{-rl, 0, 0}, Vec3{1, 0, 0}), lower);
    sim_->add_wall(std::make_unique<PlaneWall>(Vec3{rl, 0, 0}, Vec3{-1, 0, 0}), lower);
    orifice_wall_ = sim_->add_wall(std::make_unique<OrificePlateWall>(OrificePlateWall::slot(
                                       Vec3{0, 0.5 * depth_m_, zo}, Vec3{0, 0, 1}, Vec3{1, 0, 0},
                                       o_.orifice_diameter_m, never)),
                                   plate);
    if (cone_height_m_ > 0.0) {
      sim_->add_wall(make_slab_segment_wall(-r0, zo, -ru, zo + cone_height_m_, depth_m_), hopper);
      sim_->add_wall(make_slab_segment_wall(r0, zo, ru, zo + cone_height_m_, depth_m_), hopper);
    }
    sim_->add_wall(make_slab_segment_wall(-ru, zo + cone_height_m_, -ru, top_m_, depth_m_), hopper);
    sim_->add_wall(make_slab_segment_wall(ru, zo + cone_height_m_, ru, top_m_, depth_m_), hopper);
  } else {
    sim_->add_wall(std::make_unique<CylinderWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, zo, rl), lower);
    orifice_wall_ =
        sim_->add_wall(std::make_unique<OrificePlateWall>(OrificePlateWall::circular(
                           Vec3{0, 0, zo}, Vec3{0, 0, 1}, o_.orifice_diameter_m, never, rl)),
                       plate);
    if (cone_height_m_ > 0.0)
      sim_->add_wall(
          std::make_unique<ConeWall>(Vec3{0, 0, zo}, Vec3{0, 0, 1}, cone_height_m_, r0, ru),
          hopper);
    sim_->add_wall(std::make_unique<CylinderWall>(Vec3{0, 0, zo + cone_height_m_}, Vec3{0, 0, 1},
                                                  o_.upper_height_m, ru),
                   hopper);
  }

  FillOptions fill;
  fill.material = p;
  fill.density_kg_m3 = material.particle.density_kg_m3;
  fill.amount.mass_kg = fill_mass_kg_;
  fill.method = "lattice";
  fill.lattice_gap = o_.fill_lattice_spacing_diameters - 1.0;
  sim_->add_inserter(make_fill_inserter(std::move(region), std::move(sizes), fill));
}

FillChamber Sandglass::fill_chamber() const {
  FillChamber c;
  c.orifice_plane_z_m = o_.drop_height_m;
  c.upper_radius_m = 0.5 * o_.upper_diameter_m;
  c.orifice_radius_m = 0.5 * o_.orifice_diameter_m;
  c.hopper_height_m = cone_height_m_;
  c.slice = o_.reduction.slice;
  c.slice_thickness_m = depth_m_;
  c.bin_width_m = 2.0 * diameter_m_;
  return c;
}

ApparatusResult Sandglass::run(const StepObserver& observe) {
  ApparatusResult r;
  Simulation& sim = *sim_;
  r.details["apparatus"] = name();
  r.details["variant"] = o_.reduction.slice ? "slice" : "full";
  r.details["particle_diameter_m"] = diameter_m_;
  r.details["fill_mass_kg"] = fill_mass_kg_;
  if (o_.reduction.slice) r.details["slice_thickness_m"] = depth_m_;

  // 1. Fill the upper chamber and let it settle with the orifice shut.
  const bool settled =
      protocol::settle(sim, protocol_, protocol_.max_settle_s, observe, "fill", r.details);
  const double fill_mass = protocol::total_mass_kg(sim.particles());
  const FillChamber chamber = fill_chamber();
  const double surface =
      fill_surface_height_m(sim.particles().position_m, sim.particles().radius_m, chamber);
  const double bulk_volume = chamber_volume_below_m3(surface, chamber);
  r.details["particles"] = sim.particles().size();
  r.details["fill_settled"] = settled;
  r.details["fill_surface_height_m"] = surface;
  if (bulk_volume > 0.0) r.observables["bulk_density_kg_m3"] = fill_mass / bulk_volume;

  // 2. Open the orifice and record m(t): the mass whose centre has passed the plate.
  const double opened = sim.time_s();
  static_cast<OrificePlateWall&>(sim.mutable_wall(orifice_wall_)).set_open_time(opened);
  sim.geometry_changed();
  const auto& pp = sim.particles();
  const double zo = o_.drop_height_m;
  DischargeRecorder recorder(zo, opened, protocol_.sample_interval_s);
  recorder.reserve_for(protocol_.max_flow_s);
  recorder.sample(sim);
  double last_change = opened;
  double last_mass = 0.0;
  std::string ended = "time cap (max_flow_s)";
  while (sim.time_s() - opened < protocol_.max_flow_s) {
    sim.step();
    if (observe) observe(sim, "discharge");
    if (!recorder.due(sim.time_s())) continue;
    recorder.sample(sim);
    const double below = recorder.mass_kg().back();
    if (below > last_mass) {
      last_mass = below;
      last_change = sim.time_s();
    }
    if (below >= fill_mass * (1.0 - 1e-12)) {
      ended = "all mass discharged";
      break;
    }
    if (sim.time_s() - last_change > protocol_.stall_time_s) {
      ended = "no mass passed for stall_time_s";
      break;
    }
  }
  r.details["discharge_ended_because"] = ended;
  DischargeOptions dopt;
  dopt.stall_time_s = protocol_.stall_time_s;
  // A flat bottom keeps dead zones at rest beside a clear orifice: the flow has
  // ended, not clogged. A clog is an arch: grains resting over the opening.
  // So the fraction rule is off and the arch is looked for directly.
  dopt.complete_fraction = 1e-9;
  DischargeAnalysis flow = recorder.analyse(dopt);
  if (flow.status == "complete" && flow.discharged_fraction < 1.0) {
    const double r0 = 0.5 * o_.orifice_diameter_m;
    std::size_t over = 0;
    for (std::size_t i = 0; i < pp.size(); ++i) {
      const Vec3& x = pp.position_m[i];
      const double off_axis = o_.reduction.slice ? std::abs(x.x) : std::hypot(x.x, x.y);
      // The central half only: a grain resting on the plate's edge has its
      // centre just inside the opening, but nothing can rest over its middle
      // unless an arch spans the opening.
      if (x.z > zo && x.z < zo + 2.0 * o_.orifice_diameter_m && off_axis < 0.5 * r0) ++over;
    }
    r.details["grains_over_orifice_at_stop"] = over;
    if (over > 0) {
      std::ostringstream status;
      status << "clogged: an arch over the orifice after " << 100.0 * flow.discharged_fraction
             << " % discharged at t = " << flow.flow_stopped_s << " s";
      flow.status = status.str();
      flow.clogged = true;
      flow.discharge_time_s = DischargeAnalysis::kNaN;
    } else {
      r.details["retained_in_dead_zones_fraction"] = 1.0 - flow.discharged_fraction;
    }
  }
  r.details["discharge"] = to_json(flow);
  r.observables["discharge_time_s"] = std::isfinite(flow.discharge_time_s)
                                          ? nlohmann::json(flow.discharge_time_s)
                                          : nlohmann::json();
  r.observables["mass_flow_rate_kg_s"] = std::isfinite(flow.mass_flow_rate_kg_s)
                                             ? nlohmann::json(flow.mass_flow_rate_kg_s)
                                             : nlohmann::json();
  r.series["discharged_mass"] = recorder.series_json();

  r.details["form_pile"] = o_.form_pile;
  if (!o_.form_pile) return r;

  // 3. Let the pile below come to rest and measure its angle of repose.
  r.details["pile_settled"] =
      protocol::settle(sim, protocol_, protocol_.max_settle_s, observe, "pile", r.details);
  std::vector<Vec3> pos;
  std::vector<double> rad;
  for (std::size_t i = 0; i < pp.size(); ++i)
    if (pp.position_m[i].z < zo) {
      pos.push_back(pp.position_m[i]);
      rad.push_back(pp.radius_m[i]);
    }
  try {
    if (o_.reduction.slice) {
      SliceAoROptions a;
      a.long_axis = 0;
      r.series["pile"] = to_json(measure_slice_angle_of_repose(pos, rad, a));
    } else {
      ConicalAoROptions a;
      a.axis_centre_m = std::array<double, 2>{0.0, 0.0};
      r.series["pile"] = to_json(measure_conical_angle_of_repose(pos, rad, a));
    }
    r.observables["angle_of_repose_deg"] = r.series["pile"]["angle_of_repose_deg"];
    r.observables["angle_of_repose_uncertainty_deg"] =
        r.series["pile"]["angle_of_repose_uncertainty_deg"];
  } catch (const std::runtime_error& e) {
    r.observables["angle_of_repose_deg"] = nullptr;
    r.details["angle_of_repose_error"] = e.what();
  }
  return r;
}

}  // namespace demcal::dem
