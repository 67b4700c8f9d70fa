#pragma once
// The Sandglass test of Derakhshani et al. (2015): an upper chamber filled to a
// mass, held shut by an orifice plate until the fill is at rest, then opened;
// the material discharges into a lower chamber and forms a pile there.
// Observables: discharge time, m(t) through the orifice, the steady mass flow
// rate, the angle of repose of the pile below, the bulk density of the fill.
//
// Geometry (z up, lower floor at z = 0, orifice plane at z = drop_height_m):
//   lower chamber: floor, and a cylinder (full) or two side walls (slice) of
//                  lower_diameter_m;
//   upper chamber: a cylinder (slice: two walls) of upper_diameter_m and
//                  upper_height_m above a flat or conical (hopper) bottom whose
//                  outlet is the orifice of orifice_diameter_m.
// The slice variant is a slab of the same section, periodic across its
// thickness, with a slot orifice; it holds the share of the fill that a slab of
// its thickness cut through a planar sandglass of depth upper_diameter_m holds
// (fill_mass_kg * thickness / upper_diameter_m), i.e. the same fill height.

#include "dem/apparatus/apparatus.hpp"
#include "dem/measure/fill_bulk_density.hpp"

#include <string>
#include <vector>

namespace demcal::dem {

struct SandglassOptions {
  double upper_diameter_m = 0.05;
  double upper_height_m = 0.08;      // the cylindrical part, above the bottom
  std::string bottom = "conical";    // "flat" | "conical"
  double hopper_half_angle_deg = 30.0;  // conical bottom: wall angle from the vertical
  double orifice_diameter_m = 0.008;    // the slice's slot width
  double fill_mass_kg = 0.08;           // of the full apparatus
  double lower_diameter_m = 0.12;
  double drop_height_m = 0.08;          // orifice plane above the lower floor
  // false: the run ends after max_flow_s of discharge (or when the flow ends)
  // without letting the pile settle: a flow-rate measurement (Beverloo) needs
  // only the steady part of m(t), and a deep bed would take far longer to empty.
  bool form_pile = true;
  // The fill starts as a jittered cubic lattice of this spacing, in largest
  // diameters (> 1): denser starts settle sooner; the peers' hopper uses 1.25.
  double fill_lattice_spacing_diameters = 1.05;
  ModelReduction reduction;

  // Throws std::invalid_argument naming the dimension and what it must be.
  void validate() const;
};

class Sandglass final : public Apparatus {
 public:
  // Builds the geometry and checks that the upper chamber can hold the fill;
  // throws std::invalid_argument before anything runs when it cannot.
  Sandglass(const SandglassOptions& options, const GranularMaterial& material,
            const RunProtocol& protocol);
  std::string name() const override { return "sandglass"; }
  // Its walls in groups that may each touch the grains with an interaction of
  // their own (GranularMaterial::particle_wall_by_group): the lower chamber's
  // "floor" (where the pile forms) and "lower_wall", the "orifice_plate", and
  // the "hopper" (cone and upper cylinder, or their slice walls).
  static std::vector<std::string> wall_group_names() { return {"floor", "lower_wall", "orifice_plate", "hopper"}; }
  const Simulation& simulation() const override { return *sim_; }
  // What it was built from (engines/ writes other engines' decks from it).
  const SandglassOptions& options() const { return o_; }
  ApparatusResult run(const StepObserver& observe) override;

  double fill_mass_kg() const { return fill_mass_kg_; }
  double particle_diameter_m() const { return diameter_m_; }

 private:
  // The upper chamber as the bulk-density rule sees it (dem/measure/fill_bulk_density.hpp).
  FillChamber fill_chamber() const;

  SandglassOptions o_;
  RunProtocol protocol_;
  std::unique_ptr<Simulation> sim_;
  std::size_t orifice_wall_ = 0;
  double diameter_m_ = 0.0;
  double depth_m_ = 0.0;       // slice thickness (slice variant)
  double cone_height_m_ = 0.0;
  double top_m_ = 0.0;
  double fill_mass_kg_ = 0.0;
};

}  // namespace demcal::dem
