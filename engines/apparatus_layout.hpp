#pragma once
// demcal's apparatus, restated as the primitives an input deck is written
// from: a box, planes and solid blocks as walls, an inlet or a lattice fill,
// the protocol (pour or fill, settle, open, flow, come to rest) and what is
// measured at the end. Built from the same option structs the apparatus in
// dem/apparatus/ are built from, with the same derived numbers (the slice's
// share of the fill, the inlet, the time step), so an engine deck and a demcal
// run describe one experiment. What cannot be written as these primitives is
// refused by name.

#include "dem/apparatus/apparatus.hpp"
#include "dem/apparatus/conical_pile.hpp"
#include "dem/apparatus/poured_slab_pile.hpp"
#include "dem/apparatus/rectangular_container.hpp"
#include "dem/apparatus/sandglass.hpp"
#include "dem/vec3.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace demcal::engines {

// An infinite plane normal to an axis; grains stay on the side `normal_sign`
// points to (+1: coordinate above position_m).
struct AxisPlane {
  std::string name;
  int axis = 2;  // 0 x, 1 y, 2 z
  double position_m = 0.0;
  int normal_sign = 1;
};

// A solid rectangular block; grains stay outside it. An extent along a
// periodic axis spans the whole box.
struct SolidBlock {
  std::string name;
  dem::Vec3 lower_m;
  dem::Vec3 upper_m;
};

// A plate slanted in the x-z plane (a parallelepiped): its bottom face spans
// x_lower_m..x_upper_m at z_lower_m, its top face the same shifted by tilt_x_m
// at z_upper_m; it spans the box along y. Grains stay outside it. The slice
// sandglass's hopper is two of them.
struct SlantedPlate {
  std::string name;
  double x_lower_m = 0.0;
  double x_upper_m = 0.0;
  double z_lower_m = 0.0;
  double z_upper_m = 0.0;
  double tilt_x_m = 0.0;
};

// A surface of revolution about the vertical axis through x = y = 0: a cylinder
// (equal radii) or a cone frustum, open at both ends; grains stay inside it.
struct AxialShell {
  std::string name;
  double radius_lower_m = 0.0;
  double radius_upper_m = 0.0;
  double z_lower_m = 0.0;
  double z_upper_m = 0.0;
};

// A solid disc (a short vertical cylinder) about the same axis; grains stay outside it.
struct AxialDisc {
  std::string name;
  double radius_m = 0.0;
  double z_lower_m = 0.0;
  double z_upper_m = 0.0;
};

// A solid plate about the same axis with a circular hole through it (the 3D
// sandglass's orifice plate); grains stay outside it: above, below and in the
// hole. An engine whose primitives cannot express it may leave it out only when
// `if_left_out` says what that changes (stated as an approximation); with
// `if_left_out` empty it must refuse the layout.
struct AxialAnnulus {
  std::string name;
  double inner_radius_m = 0.0;
  double outer_radius_m = 0.0;
  double z_lower_m = 0.0;
  double z_upper_m = 0.0;
  std::string if_left_out;
};

struct BoxRegion {
  dem::Vec3 lower_m;
  dem::Vec3 upper_m;
};

struct PourInlet {
  BoxRegion region;
  double speed_m_s = 0.5;  // downwards
  double batch_volume_fraction = 0.3;
};

// A simple cubic lattice of `spacing_m`, sites (i + 1/2) spacing inside
// `region` (the region is aligned to the lattice), jittered by up to
// jitter_m in each direction; the top layer is thinned at random to `count`.
// With cylinder_radius_m > 0 the sites are those of the box that also lie
// within that radius of the vertical axis (a cylindrical fill).
struct LatticeFill {
  BoxRegion region;
  double cylinder_radius_m = 0.0;
  double spacing_m = 0.0;
  double jitter_m = 0.0;
  std::size_t sites_per_layer = 0;
  std::size_t layers = 0;
  std::size_t count = 0;
};

struct ApparatusLayout {
  std::string apparatus;  // "poured_slab_pile", "rectangular_container", "sandglass"
  std::string variant;    // "slice" | "walls" | "periodic" | ...
  BoxRegion box;
  std::array<bool, 3> periodic{false, false, false};
  std::vector<AxisPlane> planes;
  std::vector<SolidBlock> blocks;            // for the whole run
  std::vector<SolidBlock> closing_blocks;    // the shut orifice: removed at opening
  std::vector<SolidBlock> opened_blocks;     // the plate with its opening: added at opening
  std::vector<SlantedPlate> slanted_plates;  // hopper plates, for the whole run
  std::vector<AxialShell> shells;            // funnels and cylinders, for the whole run
  std::vector<AxialDisc> discs;              // for the whole run
  std::vector<AxialDisc> closing_discs;      // the shut outlet: removed at opening
  std::vector<AxialAnnulus> annuli;          // plates with a hole, for the whole run
  std::optional<PourInlet> pour;
  std::optional<LatticeFill> lattice;
  std::size_t particles = 0;
  // Diameters and their number fractions (one class: monodisperse).
  std::vector<std::pair<double, double>> size_classes;
  double density_kg_m3 = 0.0;
  double time_step_s = 0.0;
  std::uint64_t seed = 1;
  dem::RunProtocol protocol;
  // Release (conical pile): after the fill has settled the closing discs go
  // and the run continues until at rest (no m(t)).
  bool release = false;
  // Discharge (sandglass): the plane the orifice sits in and the chamber above it;
  // discharged mass = fill - mass inside upper_chamber.
  bool discharge = false;
  double orifice_plane_z_m = 0.0;
  BoxRegion upper_chamber;
  bool form_pile = true;
  // The material as demcal runs it (for the parameter mapping) and the reduction.
  dem::GranularMaterial material;
  dem::ModelReduction reduction;
  // How demcal measures the engine's output (engine_measure.hpp reads it).
  nlohmann::json measurement;
  // Where the written geometry is not demcal's (deck headers and the run record say so).
  std::vector<std::string> approximations;

  double mean_particle_mass_kg() const;
  nlohmann::json to_json() const;  // geometry and protocol for the run record
};

struct LayoutResult {
  std::optional<ApparatusLayout> layout;
  std::string refusal;
  bool ok() const { return layout.has_value(); }
};

LayoutResult layout_poured_slab_pile(const dem::PouredSlabPileOptions& options);
LayoutResult layout_rectangular_container(const dem::RectangularContainerOptions& options,
                                          const dem::GranularMaterial& material,
                                          const dem::RunProtocol& protocol);
// The slice variant, flat-bottomed or with its hopper (two slanted plates from
// the orifice's edges up to the chamber walls, as dem::Sandglass builds them),
// and the full (3D) sandglass with its conical hopper (cylinders, a cone, the
// shut orifice as a disc); the full one with a flat bottom is refused (its
// plate with a circular hole is not written as a primitive yet).
LayoutResult layout_sandglass(const dem::SandglassOptions& options,
                              const dem::GranularMaterial& material,
                              const dem::RunProtocol& protocol);
// The full (3D) pile: the funnel as a cone and a cylinder, the shut outlet and
// the base plate as discs. The slice's V-shaped funnel (slanted plates) is refused.
LayoutResult layout_conical_pile(const dem::ConicalPileOptions& options,
                                 const dem::GranularMaterial& material,
                                 const dem::RunProtocol& protocol);

// Equal-number classes of a size distribution (class mean diameters, drawn
// with a fixed seed so decks repeat); one class for a monodisperse one.
std::vector<std::pair<double, double>> size_classes(const dem::SizeDistribution& sizes,
                                                    int classes = 8);

}  // namespace demcal::engines
