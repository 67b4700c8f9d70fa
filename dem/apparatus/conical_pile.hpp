#pragma once
// The conical pile test (Derakhshani et al. 2015, fig. 1; the paper's
// verification of its calibration): a funnel with a cylindrical feed section
// is filled with the outlet shut; the outlet opens once the fill is at rest and
// the material falls the drop height onto a circular base plate, forming a
// cone. Grains that roll off the plate's edge fall into a catch tray below and
// are not part of the pile. Observables: the angle of repose, the pile's
// height and base diameter.
//
// Geometry (z up; catch floor at 0, base plate at base_height_m, funnel outlet
// drop_height_m above the plate). The slice variant is a periodic slab: a
// V-shaped funnel with a slot outlet above a base strip of base_diameter_m.

#include "dem/apparatus/apparatus.hpp"

#include <string>
#include <vector>

namespace demcal::dem {

struct ConicalPileOptions {
  double funnel_top_diameter_m = 0.06;
  double funnel_outlet_diameter_m = 0.012;
  double funnel_half_angle_deg = 30.0;   // from the vertical
  double feed_height_m = 0.06;           // cylindrical section above the funnel
  double drop_height_m = 0.04;           // outlet above the base plate
  double base_diameter_m = 0.08;
  double fill_mass_kg = 0.05;            // full apparatus; the slice takes its share
  ModelReduction reduction;

  void validate() const;
};

class ConicalPile final : public Apparatus {
 public:
  ConicalPile(const ConicalPileOptions& options, const GranularMaterial& material,
              const RunProtocol& protocol);
  std::string name() const override { return "conical_pile"; }
  // Its walls in groups that may each touch the grains with an interaction of
  // their own (GranularMaterial::particle_wall_by_group): the "floor" under
  // the base, the "base" the pile stands on, the "outer_wall" around the base,
  // and the "funnel" (outlet plate, cone and cylinder above it).
  static std::vector<std::string> wall_group_names() { return {"floor", "base", "outer_wall", "funnel"}; }
  const Simulation& simulation() const override { return *sim_; }
  // What it was built from (engines/ writes other engines' decks from it).
  const ConicalPileOptions& options() const { return o_; }
  ApparatusResult run(const StepObserver& observe) override;

 private:
  ConicalPileOptions o_;
  RunProtocol protocol_;
  std::unique_ptr<Simulation> sim_;
  std::size_t outlet_wall_ = 0;
  double diameter_m_ = 0.0;
  double depth_m_ = 0.0;
  double base_height_m_ = 0.0;
  double outlet_height_m_ = 0.0;
};

}  // namespace demcal::dem
