#include "engines/engine_measure.hpp"

#include "dem/measure/angle_of_repose.hpp"
#include "dem/measure/discharge.hpp"
#include "dem/measure/fill_bulk_density.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace demcal::engines {
namespace {

// The pile's AoR into the result as the apparatus record it; a pile the rules
// cannot measure leaves the observable null and says why.
template <class Measure>
void record_angle_of_repose(dem::ApparatusResult& r, Measure&& measure) {
  try {
    r.series["pile"] = dem::to_json(measure());
    r.observables["angle_of_repose_deg"] = r.series["pile"]["angle_of_repose_deg"];
    r.observables["angle_of_repose_uncertainty_deg"] =
        r.series["pile"]["angle_of_repose_uncertainty_deg"];
  } catch (const std::runtime_error& e) {
    r.observables["angle_of_repose_deg"] = nullptr;
    r.details["angle_of_repose_error"] = e.what();
  }
}

void measure_slice_pile(const std::vector<dem::Vec3>& pos, const std::vector<double>& rad,
                        int long_axis, double base_height_m, dem::ApparatusResult& r) {
  dem::SliceAoROptions a;
  a.long_axis = long_axis;
  a.base_height_m = base_height_m;
  record_angle_of_repose(r, [&] { return dem::measure_slice_angle_of_repose(pos, rad, a); });
}

// About the vertical axis through x = y = 0, from base_height_m (the full
// dem::Sandglass's lower pile: the floor; dem::ConicalPile's: its plate).
void measure_conical_pile(const std::vector<dem::Vec3>& pos, const std::vector<double>& rad,
                          double base_height_m, dem::ApparatusResult& r) {
  dem::ConicalAoROptions a;
  a.base_height_m = base_height_m;
  a.axis_centre_m = std::array<double, 2>{0.0, 0.0};
  record_angle_of_repose(r, [&] { return dem::measure_conical_angle_of_repose(pos, rad, a); });
}

// The stall time an engine's m(t) can show. The deck ends the flow when the mass
// above the orifice is unchanged over a whole chunk of stall_time_s, but it samples
// m(t) every few steps on the engine's global step grid, not at the chunk's ends: the
// first sample of the quiet chunk can fall up to one interval after its start and the
// last up to one before its end, so the constant tail the series ends with may be
// two intervals shorter than the stall time (20 samples of 4.998 ms, 0.09997 s,
// against 0.1 s: read as a flow still running, with no discharge time). demcal's own
// runs check the stall at every sample and need no such allowance.
double resolvable_stall_time_s(double stall_time_s, const MassSeries& series) {
  const std::size_t n = series.time_s.size();
  if (n < 2) return stall_time_s;
  std::vector<double> spacing(n - 1);
  for (std::size_t i = 1; i < n; ++i) spacing[i - 1] = series.time_s[i] - series.time_s[i - 1];
  std::nth_element(spacing.begin(),
                   spacing.begin() + static_cast<std::ptrdiff_t>(spacing.size() / 2),
                   spacing.end());
  const double interval = spacing[spacing.size() / 2];  // the median: robust to a short last one
  const double resolvable = stall_time_s - 2.0 * interval;
  return resolvable > 0.0 ? resolvable : stall_time_s;
}

double coord(const dem::Vec3& v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y : v.z; }

}  // namespace

namespace {

// dem/measure/fill_bulk_density's rule on the engine's dump of the settled fill; the plan
// carries the chamber (a slice when it gives the slice's thickness, else the full one).
double bulk_density_kg_m3(const nlohmann::json& b, const ParticleDump& fill, double density) {
  dem::FillChamber c;
  c.upper_radius_m = b.at("upper_radius_m").get<double>();
  c.orifice_radius_m = b.at("orifice_radius_m").get<double>();
  c.orifice_plane_z_m = b.at("orifice_plane_z_m").get<double>();
  c.hopper_height_m = b.at("hopper_height_m").get<double>();
  c.slice = b.contains("slice_thickness_m");
  if (c.slice) c.slice_thickness_m = b.at("slice_thickness_m").get<double>();
  c.bin_width_m = 2.0 * b.at("mean_diameter_m").get<double>();
  double mass = 0.0;
  for (const double r : fill.radius_m) mass += density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double surface = dem::fill_surface_height_m(fill.position_m, fill.radius_m, c);
  const double volume = dem::chamber_volume_below_m3(surface, c);
  return volume > 0.0 ? mass / volume : std::nan("");
}

}  // namespace

dem::ApparatusResult measure_engine_output(const nlohmann::json& plan, const ParticleDump& dump,
                                           const MassSeries* series,
                                           const ParticleDump* settled_fill) {
  dem::ApparatusResult r;
  const std::string kind = plan.at("kind").get<std::string>();
  r.details["apparatus"] = plan.at("apparatus");
  r.details["particles"] = dump.size();
  r.details["measured_by"] = "demcal (dem/measure) from the engine's final dump";
  if (kind == "slice_angle_of_repose") {
    std::vector<dem::Vec3> pos;
    std::vector<double> rad;
    const bool band = plan.contains("median_band");
    for (std::size_t i = 0; i < dump.size(); ++i) {
      if (band) {
        const auto& b = plan["median_band"];
        const double c = b.at("centre_m").get<double>(), h = b.at("half_width_m").get<double>();
        if (std::abs(coord(dump.position_m[i], b.at("axis").get<int>()) - c) >= h) continue;
      }
      pos.push_back(dump.position_m[i]);
      rad.push_back(dump.radius_m[i]);
    }
    r.details["median_plane_rule"] = band ? "particles within the median band" : "all particles";
    measure_slice_pile(pos, rad, plan.value("long_axis", 0), plan.value("base_height_m", 0.0), r);
    return r;
  }
  if (kind == "conical_angle_of_repose") {
    // As dem::ConicalPile: the grains on the plate, below the outlet.
    const double base = plan.at("base_height_m").get<double>();
    const double outlet = plan.at("outlet_height_m").get<double>();
    const double rb = plan.at("base_radius_m").get<double>();
    std::vector<dem::Vec3> pos;
    std::vector<double> rad;
    double reach = 0.0;
    for (std::size_t i = 0; i < dump.size(); ++i) {
      const dem::Vec3& x = dump.position_m[i];
      const double radial = std::hypot(x.x, x.y);
      if (x.z > base && x.z < outlet && radial <= rb) {
        pos.push_back(x);
        rad.push_back(dump.radius_m[i]);
        reach = std::max(reach, radial + dump.radius_m[i]);
      }
    }
    r.details["particles_on_plate"] = pos.size();
    measure_conical_pile(pos, rad, base, r);
    if (r.series.contains("pile"))
      r.observables["pile_height_m"] = r.series["pile"]["crest_height_m"];
    r.observables["pile_base_diameter_m"] = 2.0 * std::min(reach, rb);
    return r;
  }
  if (kind == "sandglass_slice" || kind == "sandglass_full") {
    // As dem::Sandglass for either variant; the full one is axisymmetric about x = y = 0.
    const bool full = kind == "sandglass_full";
    if (series == nullptr) throw std::invalid_argument("sandglass measurement: no mass series");
    const double fill = series->fill_mass_kg();
    dem::DischargeOptions dopt;
    dopt.stall_time_s = resolvable_stall_time_s(plan.at("stall_time_s").get<double>(), *series);
    // As dem::Sandglass: a flat bottom keeps dead zones, so a clog is judged
    // by an arch over the orifice, not by the fraction discharged.
    dopt.complete_fraction = 1e-9;
    dem::DischargeAnalysis flow =
        dem::analyse_discharge(series->time_s, series->discharged_kg, fill, dopt);
    const double zo = plan.at("orifice_plane_z_m").get<double>();
    const double w = plan.at("orifice_width_m").get<double>();
    if (flow.status == "complete" && flow.discharged_fraction < 1.0) {
      std::size_t over = 0;
      for (const auto& x : dump.position_m) {
        const double off_axis = full ? std::hypot(x.x, x.y) : std::abs(x.x);
        if (x.z > zo && x.z < zo + 2.0 * w && off_axis < 0.25 * w) ++over;
      }
      r.details["grains_over_orifice_at_stop"] = over;
      if (over > 0) {
        std::ostringstream status;
        status << "clogged: an arch over the orifice after " << 100.0 * flow.discharged_fraction
               << " % discharged at t = " << flow.flow_stopped_s << " s";
        flow.status = status.str();
        flow.clogged = true;
        flow.discharge_time_s = dem::DischargeAnalysis::kNaN;
      } else {
        r.details["retained_in_dead_zones_fraction"] = 1.0 - flow.discharged_fraction;
      }
    }
    r.details["fill_mass_kg"] = fill;
    if (settled_fill != nullptr && plan.contains("bulk_density")) {
      const double rho = bulk_density_kg_m3(plan.at("bulk_density"), *settled_fill,
                                            plan.at("density_kg_m3").get<double>());
      if (std::isfinite(rho)) r.observables["bulk_density_kg_m3"] = rho;
    }
    r.details["discharge"] = dem::to_json(flow);
    r.observables["discharge_time_s"] = std::isfinite(flow.discharge_time_s)
                                            ? nlohmann::json(flow.discharge_time_s)
                                            : nlohmann::json();
    r.observables["mass_flow_rate_kg_s"] = std::isfinite(flow.mass_flow_rate_kg_s)
                                               ? nlohmann::json(flow.mass_flow_rate_kg_s)
                                               : nlohmann::json();
    r.series["discharged_mass"] = dem::series_to_json(series->time_s, series->discharged_kg);
    if (plan.value("form_pile", true)) {
      std::vector<dem::Vec3> pos;
      std::vector<double> rad;
      for (std::size_t i = 0; i < dump.size(); ++i)
        if (dump.position_m[i].z < zo) {
          pos.push_back(dump.position_m[i]);
          rad.push_back(dump.radius_m[i]);
        }
      if (full)
        measure_conical_pile(pos, rad, 0.0, r);
      else
        measure_slice_pile(pos, rad, 0, 0.0, r);
    }
    return r;
  }
  throw std::invalid_argument("unknown measurement kind \"" + kind + "\"");
}

dem::ApparatusResult measure_engine_run(const Deck& deck, const std::filesystem::path& dir) {
  const ParticleDump dump = read_custom_dump(dir / deck.final_dump_name);
  if (deck.mass_series_name.empty())
    return measure_engine_output(deck.record.at("measurement"), dump, nullptr);
  const MassSeries series = read_mass_series(dir / deck.mass_series_name);
  if (!deck.fill_dump_name.empty()) {
    const ParticleDump fill = read_custom_dump(dir / deck.fill_dump_name);
    return measure_engine_output(deck.record.at("measurement"), dump, &series, &fill);
  }
  return measure_engine_output(deck.record.at("measurement"), dump, &series);
}

}  // namespace demcal::engines
