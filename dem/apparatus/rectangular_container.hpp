#pragma once
// The rectangular container of adjustable thickness (Derakhshani et al. 2015,
// fig. 2): sand is poured between the front and rear walls from a narrow inlet
// above the centre and forms a heap whose angle of repose is read in the
// median plane. The paper describes the material as poured ("sand particles are
// poured between the front and rear walls"), so the release here is a pour, not
// a gate. Front and rear are walls or a periodic boundary; the paper's finding
// is that the walls stop mattering at 32 d, the periodic boundary at 4 d.
//
// Geometry: x across the width (side walls at +-width/2), y across the
// thickness (0..t), z up (floor at 0).

#include "dem/apparatus/apparatus.hpp"

#include <string>
#include <vector>

namespace demcal::dem {

struct RectangularContainerOptions {
  double width_m = 0.2;
  double height_m = 0.1;
  // The thickness t, in metres or in mean particle diameters (give exactly one).
  double thickness_m = 0.0;
  double thickness_diameters = 0.0;
  std::string boundary = "walls";  // "walls" | "periodic" across the thickness
  double fill_mass_kg = 0.0;       // of the container as given (t included)
  double inlet_width_m = 0.0;      // 0: 8 mean diameters
  double inlet_height_m = 0.0;     // bottom of the inlet above the floor; 0: 0.8 height_m
  double inlet_speed_m_s = 0.5;    // downwards
  // The angle is read from particles within this many diameters of the median
  // plane (all of them when the container is thinner than twice this).
  double median_band_diameters = 2.0;
  ModelReduction reduction;  // coarse graining and modulus; `slice` does not apply

  void validate() const;
};

class RectangularContainer final : public Apparatus {
 public:
  RectangularContainer(const RectangularContainerOptions& options, const GranularMaterial& material,
                       const RunProtocol& protocol);
  std::string name() const override { return "rectangular_container"; }
  // Its walls in groups that may each touch the grains with an interaction of
  // their own (GranularMaterial::particle_wall_by_group): the "floor", the
  // "end_walls" at either end of its width, and the "side_walls" that bound
  // its thickness (absent when the thickness is periodic).
  static std::vector<std::string> wall_group_names() { return {"floor", "end_walls", "side_walls"}; }
  const Simulation& simulation() const override { return *sim_; }
  // What it was built from (engines/ writes other engines' decks from it).
  const RectangularContainerOptions& options() const { return o_; }
  ApparatusResult run(const StepObserver& observe) override;

  double thickness_m() const { return thickness_m_; }
  double particle_diameter_m() const { return diameter_m_; }

 private:
  RectangularContainerOptions o_;
  RunProtocol protocol_;
  std::unique_ptr<Simulation> sim_;
  double diameter_m_ = 0.0;
  double thickness_m_ = 0.0;
};

}  // namespace demcal::dem
