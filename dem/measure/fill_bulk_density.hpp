#pragma once
// The bulk density of a sandglass's settled fill, by one rule wherever the fill was made
// (demcal's own run, dem::Sandglass; another engine's dump, engines/engine_measure): the
// fill's mass over the volume of the upper chamber below the fill's surface.
//
// The surface is the mean of the highest particle tops in bins of `bin_width_m` across the
// inner 80 % of the chamber, so that the walls' rim effects and stray grains stay out of
// the mean. The chamber is a flat-bottomed or hopper-bottomed cylinder, or its slice (a
// slot of `slice_thickness_m` between periodic faces, binned along x).

#include "dem/vec3.hpp"

#include <vector>

namespace demcal::dem {

struct FillChamber {
  double orifice_plane_z_m = 0.0;  // the chamber's bottom: the orifice plate
  double upper_radius_m = 0.0;     // the chamber's radius (or half-width of a slice)
  double orifice_radius_m = 0.0;   // (half-width of a slot)
  double hopper_height_m = 0.0;    // 0: a flat bottom
  bool slice = false;
  double slice_thickness_m = 0.0;  // slice only
  double bin_width_m = 0.0;        // > 0; two mean grain diameters
};

// The fill's surface height (m, same frame as the positions); the orifice plane when no
// grain lies above it.
double fill_surface_height_m(const std::vector<Vec3>& position_m,
                             const std::vector<double>& radius_m, const FillChamber& chamber);

// The chamber's volume between the orifice plane and `height_m` (0 below the plane).
double chamber_volume_below_m3(double height_m, const FillChamber& chamber);

}  // namespace demcal::dem
