#include "engines/apparatus_layout.hpp"

#include "dem/material.hpp"
#include "dem/random.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace demcal::engines {
namespace {

constexpr double kPi = std::numbers::pi;

// The time step demcal would take: the fraction of the Rayleigh time of the
// smallest grain of the (reduced) particle material (Simulation::prepare).
double demcal_time_step_s(const dem::GranularMaterial& m, const dem::ModelReduction& r,
                          const dem::SizeDistribution& sizes, const dem::RunProtocol& p) {
  dem::Material particle = m.particle;
  if (r.shear_modulus_pa > 0.0) {
    particle.shear_modulus_pa = r.shear_modulus_pa;
    particle.youngs_modulus_pa = 0.0;
  }
  return p.time_step_fraction_of_rayleigh *
         dem::rayleigh_time_s(particle, 0.5 * sizes.min_diameter_m());
}

std::size_t count_for_mass(double mass_kg, double density, const dem::SizeDistribution& sizes) {
  const double mean_mass = density * kPi / 6.0 * sizes.mean_diameter_cubed_m3();
  return static_cast<std::size_t>(std::llround(mass_kg / mean_mass));
}

// The sites of a simple cubic lattice of spacing a (at (i + 1/2) a, as LAMMPS's
// `lattice sc a origin 0.5 0.5 0.5` places them) within radius_m of the vertical
// axis, layer on layer from the first lattice line at or above z_from_m, enough
// layers for `count` grains. sites_per_layer is 0 when none fits.
LatticeFill cylindrical_lattice(double radius_m, double spacing_m, double z_from_m,
                                std::size_t count, double d_max) {
  LatticeFill f;
  f.spacing_m = spacing_m;
  const double a = spacing_m;
  const double z0 = std::ceil(z_from_m / a) * a;
  const double x0 = -std::ceil(radius_m / a) * a;
  f.cylinder_radius_m = radius_m;
  for (long i = static_cast<long>(std::llround(x0 / a)); (i + 0.5) * a <= -x0; ++i)
    for (long j = static_cast<long>(std::llround(x0 / a)); (j + 0.5) * a <= -x0; ++j)
      if (std::hypot((i + 0.5) * a, (j + 0.5) * a) <= radius_m) ++f.sites_per_layer;
  f.count = count;
  f.layers = f.sites_per_layer == 0 ? 0 : (count + f.sites_per_layer - 1) / f.sites_per_layer;
  f.region = {{x0, x0, z0}, {-x0, -x0, z0 + static_cast<double>(f.layers) * a}};
  // Neighbours approach by at most 0.8 of the gap: no overlap, and no crystal.
  f.jitter_m = 0.4 * (a - d_max);
  return f;
}

// What every layout records of the material and the run, as demcal would run them.
void take_material_and_protocol(ApparatusLayout& l, const dem::GranularMaterial& material,
                                const dem::ModelReduction& reduction,
                                const dem::SizeDistribution& sizes,
                                const dem::RunProtocol& protocol) {
  l.size_classes = size_classes(sizes);
  l.density_kg_m3 = material.particle.density_kg_m3;
  l.time_step_s = demcal_time_step_s(material, reduction, sizes, protocol);
  l.seed = protocol.seed;
  l.protocol = protocol;
  l.material = material;
  l.reduction = reduction;
}

nlohmann::json vec(const dem::Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }
nlohmann::json box_json(const BoxRegion& b) {
  return {{"lower_m", vec(b.lower_m)}, {"upper_m", vec(b.upper_m)}};
}

}  // namespace

std::vector<std::pair<double, double>> size_classes(const dem::SizeDistribution& sizes,
                                                    int classes) {
  if (sizes.min_diameter_m() == sizes.max_diameter_m()) return {{sizes.min_diameter_m(), 1.0}};
  if (classes < 1) throw std::invalid_argument("size_classes: classes must be >= 1");
  // A fixed seed: the deck is a pure function of the description.
  dem::Random rng(20240917);
  const std::size_t per = 4000;
  std::vector<double> d(per * static_cast<std::size_t>(classes));
  for (double& x : d) x = sizes.sample_diameter_m(rng);
  std::sort(d.begin(), d.end());
  std::vector<std::pair<double, double>> out;
  for (int c = 0; c < classes; ++c) {
    double cubes = 0.0;
    for (std::size_t i = c * per; i < (c + 1) * per; ++i) cubes += d[i] * d[i] * d[i];
    // The class mean of d^3 keeps the class's mass per grain.
    out.emplace_back(std::cbrt(cubes / static_cast<double>(per)), 1.0 / classes);
  }
  return out;
}

double ApparatusLayout::mean_particle_mass_kg() const {
  double cubes = 0.0;
  for (const auto& [d, p] : size_classes) cubes += p * d * d * d;
  return density_kg_m3 * kPi / 6.0 * cubes;
}

nlohmann::json ApparatusLayout::to_json() const {
  nlohmann::json j;
  j["apparatus"] = apparatus;
  j["variant"] = variant;
  // Absent when there are none: the records of the older layouts stay as they were.
  if (!approximations.empty()) j["approximations"] = approximations;
  j["box"] = box_json(box);
  j["periodic"] = periodic;
  j["planes"] = nlohmann::json::array();
  for (const auto& p : planes)
    j["planes"].push_back({{"name", p.name},
                           {"axis", p.axis},
                           {"position_m", p.position_m},
                           {"normal_sign", p.normal_sign}});
  auto blocks_json = [](const std::vector<SolidBlock>& bs) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& b : bs)
      a.push_back({{"name", b.name}, {"lower_m", vec(b.lower_m)}, {"upper_m", vec(b.upper_m)}});
    return a;
  };
  j["blocks"] = blocks_json(blocks);
  j["closing_blocks"] = blocks_json(closing_blocks);
  j["opened_blocks"] = blocks_json(opened_blocks);
  // Absent when there are none: the records of flat-bottomed layouts stay as they were.
  if (!slanted_plates.empty()) {
    j["slanted_plates"] = nlohmann::json::array();
    for (const auto& sp : slanted_plates)
      j["slanted_plates"].push_back({{"name", sp.name},
                                     {"x_lower_m", sp.x_lower_m},
                                     {"x_upper_m", sp.x_upper_m},
                                     {"z_lower_m", sp.z_lower_m},
                                     {"z_upper_m", sp.z_upper_m},
                                     {"tilt_x_m", sp.tilt_x_m}});
  }
  if (pour)
    j["pour"] = {{"region", box_json(pour->region)},
                 {"speed_m_s", pour->speed_m_s},
                 {"batch_volume_fraction", pour->batch_volume_fraction}};
  j["shells"] = nlohmann::json::array();
  for (const auto& sh : shells)
    j["shells"].push_back({{"name", sh.name},
                           {"radius_lower_m", sh.radius_lower_m},
                           {"radius_upper_m", sh.radius_upper_m},
                           {"z_lower_m", sh.z_lower_m},
                           {"z_upper_m", sh.z_upper_m}});
  auto discs_json = [](const std::vector<AxialDisc>& ds) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& dd : ds)
      a.push_back({{"name", dd.name},
                   {"radius_m", dd.radius_m},
                   {"z_lower_m", dd.z_lower_m},
                   {"z_upper_m", dd.z_upper_m}});
    return a;
  };
  j["discs"] = discs_json(discs);
  j["closing_discs"] = discs_json(closing_discs);
  // Absent when there are none: the records of the older layouts stay as they were.
  if (!annuli.empty()) {
    j["annuli"] = nlohmann::json::array();
    for (const auto& a : annuli)
      j["annuli"].push_back({{"name", a.name},
                             {"inner_radius_m", a.inner_radius_m},
                             {"outer_radius_m", a.outer_radius_m},
                             {"z_lower_m", a.z_lower_m},
                             {"z_upper_m", a.z_upper_m}});
  }
  if (lattice)
    j["lattice_fill"] = {
        {"region", box_json(lattice->region)}, {"cylinder_radius_m", lattice->cylinder_radius_m},
        {"spacing_m", lattice->spacing_m},     {"jitter_m", lattice->jitter_m},
        {"layers", lattice->layers},           {"sites_per_layer", lattice->sites_per_layer}};
  j["particles"] = particles;
  j["size_classes"] = size_classes;
  j["density_kg_m3"] = density_kg_m3;
  j["time_step_s"] = time_step_s;
  j["seed"] = seed;
  j["rest_speed_m_s"] = protocol.rest_speed_m_s;
  j["check_interval_s"] = protocol.check_interval_s;
  if (discharge) {
    j["orifice_plane_z_m"] = orifice_plane_z_m;
    j["upper_chamber"] = box_json(upper_chamber);
    j["form_pile"] = form_pile;
  }
  j["measurement"] = measurement;
  return j;
}

LayoutResult layout_poured_slab_pile(const dem::PouredSlabPileOptions& o) {
  ApparatusLayout l;
  l.apparatus = "poured_slab_pile";
  l.variant = "slice";
  const double d = o.diameter_m;
  const double slab = o.slab_thickness_diameters * d;
  const double half = 0.5 * o.box_length_m;
  l.box = {{-half, 0.0, -0.001}, {half, slab, o.box_height_m}};
  l.periodic = {false, true, false};
  l.planes = {{"floor", 2, 0.0, 1}, {"left", 0, -half, 1}, {"right", 0, half, -1}};
  const double ix = o.inlet_half_width_diameters * d;
  l.pour = PourInlet{{{-ix, 0.0, o.inlet_bottom_m}, {ix, slab, o.inlet_top_m}},
                     o.inlet_speed_m_s,
                     o.batch_volume_fraction};
  l.particles = o.particles;
  l.size_classes = {{d, 1.0}};
  l.density_kg_m3 = o.density_kg_m3;
  l.time_step_s = o.time_step_s;
  l.seed = o.seed;
  // make_poured_slab_pile's callers: at rest below 2 mm/s (the peers' threshold), checked every 5
  // ms.
  l.protocol.rest_speed_m_s = 2e-3;
  l.protocol.check_interval_s = 5e-3;
  l.protocol.max_flow_s = 10.0;

  dem::GranularMaterial& m = l.material;
  m.particle.name = "grain";
  m.particle.density_kg_m3 = o.density_kg_m3;
  m.particle.youngs_modulus_pa = o.youngs_modulus_pa;
  m.particle.poisson_ratio = o.poisson_ratio;
  m.wall = m.particle;
  m.wall.name = "wall";
  m.particle_particle.restitution = o.restitution;
  m.particle_particle.sliding_friction = o.sliding_friction;
  m.particle_particle.rolling_friction = o.rolling_friction;
  m.particle_wall = m.particle_particle;
  m.particle_wall.sliding_friction = o.wall_sliding_friction;
  m.particle_wall.rolling_friction = o.wall_rolling_friction;
  m.contact.rolling = o.rolling_model;
  m.sizes = dem::make_monodisperse(d);
  l.measurement = {{"kind", "slice_angle_of_repose"},
                   {"apparatus", l.apparatus},
                   {"long_axis", 0},
                   {"base_height_m", 0.0},
                   {"density_kg_m3", l.density_kg_m3}};
  return {std::move(l), ""};
}

LayoutResult layout_rectangular_container(const dem::RectangularContainerOptions& options,
                                          const dem::GranularMaterial& material,
                                          const dem::RunProtocol& protocol) {
  dem::RectangularContainerOptions o = options;
  o.validate();
  if (!material.sizes)
    throw std::invalid_argument("rectangular_container: the material has no size distribution");
  ApparatusLayout l;
  l.apparatus = "rectangular_container";
  l.variant = o.boundary;
  auto sizes = dem::scaled_sizes(material.sizes, o.reduction.coarse_graining_factor);
  const double d = dem::mean_diameter_m(*sizes);
  const double d_max = sizes->max_diameter_m();
  const double t = o.thickness_m > 0.0 ? o.thickness_m : o.thickness_diameters * d;
  const bool periodic = o.boundary == "periodic";
  if (t < (periodic ? 2.7 : 1.1) * d_max)
    throw std::invalid_argument(
        "rectangular_container: the thickness is too thin for the particles");
  const double half = 0.5 * o.width_m;
  const double inlet_half = 0.5 * (o.inlet_width_m > 0.0 ? o.inlet_width_m : 8.0 * d);
  const double inlet_z = o.inlet_height_m > 0.0 ? o.inlet_height_m : 0.8 * o.height_m;
  const double inlet_top = std::min(o.height_m, inlet_z + 5.0 * d);
  if (inlet_half >= half)
    throw std::invalid_argument("rectangular_container: the inlet is wider than the container");
  const double margin = 3.0 * d_max;
  l.box = {{-half - margin, periodic ? 0.0 : -margin, -margin},
           {half + margin, t + (periodic ? 0.0 : margin), o.height_m + margin}};
  l.periodic = {false, periodic, false};
  l.planes = {{"floor", 2, 0.0, 1}, {"left", 0, -half, 1}, {"right", 0, half, -1}};
  if (!periodic) {
    l.planes.push_back({"front", 1, 0.0, 1});
    l.planes.push_back({"rear", 1, t, -1});
  }
  dem::PourOptions pour_defaults;
  // Inset from the front and rear walls by a radius: LAMMPS's fix pour places
  // grains without looking at walls, and one placed into a wall is shot out of
  // the box (measured: 9 lost, the pour stalled at 1603 of 2079). demcal's
  // inserter keeps clear of walls by itself.
  const double inset = periodic ? 0.0 : 0.5 * d_max;
  l.pour = PourInlet{{{-inlet_half, inset, inlet_z}, {inlet_half, t - inset, inlet_top}},
                     o.inlet_speed_m_s,
                     pour_defaults.batch_volume_fraction};
  l.particles = count_for_mass(o.fill_mass_kg, material.particle.density_kg_m3, *sizes);
  take_material_and_protocol(l, material, o.reduction, *sizes, protocol);
  const double band = o.median_band_diameters * d;
  l.measurement = {{"kind", "slice_angle_of_repose"},
                   {"apparatus", l.apparatus},
                   {"long_axis", 0},
                   {"base_height_m", 0.0},
                   {"density_kg_m3", l.density_kg_m3}};
  if (t >= 2.0 * band)
    l.measurement["median_band"] = {{"axis", 1}, {"centre_m", 0.5 * t}, {"half_width_m", band}};
  return {std::move(l), ""};
}

namespace {

// The sandglass's numbers as dem::Sandglass derives them, for either variant.
struct SandglassGeometry {
  double d = 0.0, d_max = 0.0;      // mean and largest (coarse-grained) diameter
  double ru = 0.0, rl = 0.0;        // upper and lower chamber radius (half-widths in a slice)
  double r0 = 0.0;                  // orifice radius (half-width of the slot)
  double zo = 0.0;                  // the orifice plane
  double cone_h = 0.0;              // the hopper's height (0 for a flat bottom)
  double zc = 0.0, top = 0.0;       // where the chamber's vertical walls begin and end
  double margin = 0.0, wall = 0.0;  // box margin; plate and wall thickness
};

SandglassGeometry sandglass_geometry(const dem::SandglassOptions& o,
                                     const dem::SizeDistribution& sizes) {
  SandglassGeometry g;
  g.d = dem::mean_diameter_m(sizes);
  g.d_max = sizes.max_diameter_m();
  g.ru = 0.5 * o.upper_diameter_m;
  g.rl = 0.5 * o.lower_diameter_m;
  g.r0 = 0.5 * o.orifice_diameter_m;
  g.zo = o.drop_height_m;
  g.cone_h =
      o.bottom == "conical" ? (g.ru - g.r0) / std::tan(o.hopper_half_angle_deg * kPi / 180.0) : 0.0;
  g.zc = g.zo + g.cone_h;
  g.top = g.zc + o.upper_height_m;
  g.margin = 3.0 * g.d_max;
  g.wall = 2.0 * g.d_max;
  return g;
}

// How demcal measures a sandglass run of either variant (engine_measure.cpp), with
// the chamber's numbers for dem::Sandglass's bulk-density rule, applied to a dump
// of the settled fill. slice_thickness_m is 0 for the full (3D) sandglass.
nlohmann::json sandglass_measurement(const ApparatusLayout& l, const dem::SandglassOptions& o,
                                     const dem::RunProtocol& protocol, double hopper_height_m,
                                     double mean_diameter_m, double slice_thickness_m) {
  const bool slice = slice_thickness_m > 0.0;
  nlohmann::json m = {{"kind", slice ? "sandglass_slice" : "sandglass_full"},
                      {"apparatus", l.apparatus},
                      {"orifice_plane_z_m", o.drop_height_m},
                      {"orifice_width_m", o.orifice_diameter_m},
                      {"form_pile", o.form_pile},
                      {"stall_time_s", protocol.stall_time_s},
                      {"density_kg_m3", l.density_kg_m3}};
  m["bulk_density"] = {{"upper_radius_m", 0.5 * o.upper_diameter_m},
                       {"orifice_radius_m", 0.5 * o.orifice_diameter_m},
                       {"orifice_plane_z_m", o.drop_height_m},
                       {"hopper_height_m", hopper_height_m},
                       {"mean_diameter_m", mean_diameter_m}};
  if (slice) m["bulk_density"]["slice_thickness_m"] = slice_thickness_m;
  return m;
}

// The full (3D) sandglass as dem::Sandglass builds it: the floor, the lower
// chamber's cylinder up to the orifice plane, the orifice plate (a plate with a
// circular hole out to the wider chamber's radius), the hopper's cone from the
// orifice up to the upper chamber's cylinder when the bottom is conical; the
// shut orifice is a disc under the hole, removed at opening. With a hopper the
// plate outside the cone's outlet is the lower chamber's ceiling, touched only
// by a lower pile grown up to the orifice plane: an engine without a plate
// with a hole may leave it out, saying so. With a flat bottom the fill rests on
// it: it must be written.
LayoutResult layout_full_sandglass(const dem::SandglassOptions& o,
                                   const dem::GranularMaterial& material,
                                   const dem::RunProtocol& protocol, ApparatusLayout l,
                                   const dem::SizeDistribution& sizes, const SandglassGeometry& g) {
  const double d = g.d, d_max = g.d_max, ru = g.ru, rl = g.rl, r0 = g.r0, zo = g.zo;
  const double cone_h = g.cone_h, zc = g.zc, top = g.top, margin = g.margin, plate = g.wall;
  const bool conical = o.bottom == "conical";
  l.variant = "full";
  const double r_box = std::max(rl, ru);
  l.box = {{-r_box - margin, -r_box - margin, -margin},
           {r_box + margin, r_box + margin, top + margin}};
  l.periodic = {false, false, false};
  l.planes = {{"floor", 2, 0.0, 1}};
  l.shells = {{"lower_wall", rl, rl, 0.0, zo}};
  if (conical) l.shells.push_back({"hopper", r0, ru, zo, zc});
  l.shells.push_back({"upper_wall", ru, ru, zc, top});
  l.closing_discs = {{"orifice_shut", r0 + plate, zo - plate, zo}};
  std::string left_out;
  if (conical) {
    std::ostringstream ceiling;
    ceiling << "the orifice plate outside the hopper's outlet (the lower chamber's ceiling, radius "
            << r0 << " to " << rl << " m at z = " << zo
            << " m) is not a wall: only a lower pile grown up to the orifice plane touches it";
    left_out = ceiling.str();
  }
  l.annuli = {{"orifice_plate", r0, r_box, zo - plate, zo, left_out}};

  const double a = o.fill_lattice_spacing_diameters * d_max;
  // A site's grain stays off the chamber wall.
  const LatticeFill f = cylindrical_lattice(
      ru - d_max - 0.5 * a, a, zc + d_max,
      count_for_mass(o.fill_mass_kg, material.particle.density_kg_m3, sizes), d_max);
  if (f.sites_per_layer == 0)
    throw std::invalid_argument("sandglass: the upper chamber is too narrow for the fill lattice");
  if (f.region.upper_m.z > top - d_max) {
    std::ostringstream s;
    s << "sandglass: the upper chamber cannot hold the fill: " << o.fill_mass_kg << " kg needs "
      << f.layers << " lattice layers of " << a << " m; raise upper_height_m or lower fill_mass_kg";
    throw std::invalid_argument(s.str());
  }
  l.lattice = f;
  l.particles = f.count;
  take_material_and_protocol(l, material, o.reduction, sizes, protocol);
  l.discharge = true;
  l.orifice_plane_z_m = zo;
  l.upper_chamber = {{-ru, -ru, zo}, {ru, ru, top + margin}};
  l.form_pile = o.form_pile;
  l.measurement = sandglass_measurement(l, o, protocol, cone_h, d, 0.0);
  return {std::move(l), ""};
}

}  // namespace

LayoutResult layout_sandglass(const dem::SandglassOptions& options,
                              const dem::GranularMaterial& material,
                              const dem::RunProtocol& protocol) {
  dem::SandglassOptions o = options;
  o.validate();
  if (!material.sizes)
    throw std::invalid_argument("sandglass: the material has no size distribution");
  // A polydisperse fill: the lattice is spaced for the largest diameter, and the
  // deck gives its sites the size classes' diameters at random (lammps_deck.cpp).
  auto sizes = dem::scaled_sizes(material.sizes, o.reduction.coarse_graining_factor);
  ApparatusLayout l;
  l.apparatus = "sandglass";
  l.variant = "slice";
  const SandglassGeometry g = sandglass_geometry(o, *sizes);
  const double d = g.d, d_max = g.d_max, ru = g.ru, rl = g.rl, r0 = g.r0, zo = g.zo;
  const double cone_h = g.cone_h, zc = g.zc, top = g.top;
  const double depth = o.reduction.slice_thickness_diameters * d;
  const double fill_mass = o.fill_mass_kg * depth / o.upper_diameter_m;
  if (o.orifice_diameter_m < 3.0 * d) {
    std::ostringstream s;
    s << "sandglass: orifice_diameter_m (" << o.orifice_diameter_m
      << " m) is below 3 particle diameters (" << 3.0 * d << " m); the flow would arch at once";
    throw std::invalid_argument(s.str());
  }
  const double margin = g.margin, wall = g.wall;
  if (!o.reduction.slice)
    return layout_full_sandglass(o, material, protocol, std::move(l), *sizes, g);
  l.box = {{-rl - margin, 0.0, -margin}, {rl + margin, depth, top + margin}};
  l.periodic = {false, true, false};
  l.planes = {{"floor", 2, 0.0, 1}, {"lower_left", 0, -rl, 1}, {"lower_right", 0, rl, -1}};
  l.blocks = {{"upper_left", {-ru - wall, 0.0, zc}, {-ru, depth, top}},
              {"upper_right", {ru, 0.0, zc}, {ru + wall, depth, top}}};
  if (cone_h > 0.0)
    // Inner faces from (-+r0, zo) up to (-+ru, zc), as make_slab_segment_wall's segments.
    l.slanted_plates = {{"hopper_left", -r0 - wall, -r0, zo, zc, -(ru - r0)},
                        {"hopper_right", r0, r0 + wall, zo, zc, ru - r0}};
  l.closing_blocks = {{"orifice_shut", {-ru - wall, 0.0, zo - wall}, {ru + wall, depth, zo}}};
  l.opened_blocks = {{"plate_left", {-ru - wall, 0.0, zo - wall}, {-r0, depth, zo}},
                     {"plate_right", {r0, 0.0, zo - wall}, {ru + wall, depth, zo}}};

  // Lattice lines at multiples of the spacing, sites halfway between them.
  LatticeFill f;
  f.spacing_m = o.fill_lattice_spacing_diameters * d_max;
  const double a = f.spacing_m;
  const double x0 = std::ceil((-ru + d_max) / a) * a, x1 = std::floor((ru - d_max) / a) * a;
  const double ny = std::floor(depth / a);
  const double z0 = std::ceil((zc + d_max) / a) * a;
  const auto nx = static_cast<std::size_t>(std::llround((x1 - x0) / a));
  f.sites_per_layer = nx * static_cast<std::size_t>(ny);
  f.count = count_for_mass(fill_mass, material.particle.density_kg_m3, *sizes);
  if (f.sites_per_layer == 0)
    throw std::invalid_argument("sandglass: the upper chamber is too narrow for the fill lattice");
  f.layers = (f.count + f.sites_per_layer - 1) / f.sites_per_layer;
  if (z0 + static_cast<double>(f.layers) * a > top - d_max) {
    std::ostringstream s;
    s << "sandglass: the upper chamber cannot hold the fill: the slice's share " << fill_mass
      << " kg needs " << f.layers << " lattice layers of " << a
      << " m; raise upper_height_m or lower fill_mass_kg";
    throw std::invalid_argument(s.str());
  }
  f.region = {{x0, 0.0, z0}, {x1, ny * a, z0 + static_cast<double>(f.layers) * a}};
  // Neighbours approach by at most 0.8 of the gap: no overlap, and no crystal.
  f.jitter_m = 0.4 * (a - d_max);
  l.lattice = f;
  l.particles = f.count;
  take_material_and_protocol(l, material, o.reduction, *sizes, protocol);
  l.discharge = true;
  l.orifice_plane_z_m = zo;
  l.upper_chamber = {{-ru, 0.0, zo}, {ru, depth, top + margin}};
  l.form_pile = o.form_pile;
  l.measurement = sandglass_measurement(l, o, protocol, cone_h, d, depth);
  return {std::move(l), ""};
}

LayoutResult layout_conical_pile(const dem::ConicalPileOptions& options,
                                 const dem::GranularMaterial& material,
                                 const dem::RunProtocol& protocol) {
  dem::ConicalPileOptions o = options;
  o.validate();
  if (!material.sizes)
    throw std::invalid_argument("conical_pile: the material has no size distribution");
  if (o.reduction.slice)
    return {std::nullopt,
            "conical_pile: the slice's V-shaped funnel (two slanted plates) is not written as deck "
            "primitives yet; use the full pile"};
  auto sizes = dem::scaled_sizes(material.sizes, o.reduction.coarse_graining_factor);
  // The numbers dem::ConicalPile derives, the same way.
  const double d = dem::mean_diameter_m(*sizes);
  const double d_max = sizes->max_diameter_m();
  const double rt = 0.5 * o.funnel_top_diameter_m, ro = 0.5 * o.funnel_outlet_diameter_m;
  const double rb = 0.5 * o.base_diameter_m;
  if (o.funnel_outlet_diameter_m < 4.0 * d)
    throw std::invalid_argument(
        "conical_pile: funnel_outlet_diameter_m must be at least 4 particle diameters");
  const double funnel_h = (rt - ro) / std::tan(o.funnel_half_angle_deg * kPi / 180.0);
  const double base = std::max(0.3 * rb, 10.0 * d_max);
  const double outlet = base + o.drop_height_m;
  const double top = outlet + funnel_h + o.feed_height_m;
  const double rc = std::max(2.0 * rb, rt + 4.0 * d_max);
  const double margin = 3.0 * d_max;
  const double plate = 2.0 * d_max;  // thickness of the base plate and of the shut outlet

  ApparatusLayout l;
  l.apparatus = "conical_pile";
  l.variant = "full";
  l.box = {{-rc - margin, -rc - margin, -margin}, {rc + margin, rc + margin, top + margin}};
  l.planes = {{"catch_floor", 2, 0.0, 1}};
  l.shells = {{"catch_tray", rc, rc, 0.0, base},
              {"funnel", ro, rt, outlet, outlet + funnel_h},
              {"feed", rt, rt, outlet + funnel_h, top}};
  l.discs = {{"base_plate", rb, base - plate, base}};
  l.closing_discs = {{"outlet_shut", rt, outlet - plate, outlet}};

  const double a = (1.0 + dem::FillOptions{}.lattice_gap) * d_max;
  const double fill_mass = o.fill_mass_kg;
  // A site's grain stays off the feed wall.
  const LatticeFill f = cylindrical_lattice(
      rt - d_max - 0.5 * a, a, outlet + funnel_h + d_max,
      count_for_mass(fill_mass, material.particle.density_kg_m3, *sizes), d_max);
  if (f.sites_per_layer == 0)
    throw std::invalid_argument(
        "conical_pile: the feed section is too narrow for the fill lattice");
  if (f.region.upper_m.z > top - d_max) {
    std::ostringstream s;
    s << "conical_pile: the feed section cannot hold the fill: " << fill_mass << " kg needs "
      << f.layers << " lattice layers of " << a
      << " m; raise feed_height_m or funnel_top_diameter_m";
    throw std::invalid_argument(s.str());
  }
  l.lattice = f;
  l.particles = f.count;
  take_material_and_protocol(l, material, o.reduction, *sizes, protocol);
  l.release = true;
  l.measurement = {{"kind", "conical_angle_of_repose"},
                   {"apparatus", l.apparatus},
                   {"base_height_m", base},
                   {"outlet_height_m", outlet},
                   {"base_radius_m", rb},
                   {"density_kg_m3", l.density_kg_m3}};
  return {std::move(l), ""};
}

}  // namespace demcal::engines
