#pragma once
// Materials and apparatus for the engines/ tests: the peers' quasi-2D pile
// material (d = 1 mm, E = 1e7 Pa, e = 0.6) with demcal's epsd rolling, small
// enough that a deck written from it runs in seconds.

#include "dem/apparatus/granular_material.hpp"
#include "dem/apparatus/sandglass.hpp"
#include "dem/size_distribution.hpp"

namespace demcal::testing {

inline dem::GranularMaterial peer_material(const std::string& rolling = "epsd") {
  dem::GranularMaterial m;
  m.particle.name = "grain";
  m.particle.density_kg_m3 = 2650.0;
  m.particle.youngs_modulus_pa = 1e7;
  m.particle.poisson_ratio = 0.3;
  m.wall = m.particle;
  m.wall.name = "wall";
  m.particle_particle.restitution = 0.6;
  m.particle_particle.sliding_friction = 0.5;
  m.particle_particle.rolling_friction = 0.1;
  m.particle_wall = m.particle_particle;
  m.particle_wall.sliding_friction = 0.9;
  m.particle_wall.rolling_friction = 0.3;
  m.contact.rolling = rolling;
  m.sizes = dem::make_monodisperse(1e-3);
  return m;
}

// The Sandglass slice the engine tests share, for peer_material's 1 mm grains: a
// 24 mm chamber over an 8 mm slot 30 mm above the floor of a 60 mm lower
// chamber, flat-bottomed, a 10 g fill on a lattice spaced 1.25 d.
inline dem::SandglassOptions small_sandglass_slice(double thickness_diameters = 4.0) {
  dem::SandglassOptions s;
  s.bottom = "flat";
  s.reduction.slice = true;
  s.reduction.slice_thickness_diameters = thickness_diameters;
  s.upper_diameter_m = 0.024;
  s.orifice_diameter_m = 0.008;
  s.upper_height_m = 0.05;
  s.lower_diameter_m = 0.06;
  s.drop_height_m = 0.03;
  s.fill_mass_kg = 0.01;
  s.fill_lattice_spacing_diameters = 1.25;
  return s;
}

// The same slice with the base study's hopper (30 deg from the vertical) and no
// pile below: the chamber must empty.
inline dem::SandglassOptions small_hopper_slice(double thickness_diameters = 4.0) {
  dem::SandglassOptions s = small_sandglass_slice(thickness_diameters);
  s.bottom = "conical";
  s.hopper_half_angle_deg = 30.0;
  s.form_pile = false;
  return s;
}

// The full (3D) sandglass for peer_material's 1 mm grains: a 24 mm chamber on a
// 30-degree hopper down to an 8 mm orifice 30 mm above the floor of a 60 mm
// lower chamber.
inline dem::SandglassOptions small_full_sandglass(double fill_mass_kg) {
  dem::SandglassOptions s;
  s.bottom = "conical";
  s.hopper_half_angle_deg = 30.0;
  s.reduction.slice = false;
  s.upper_diameter_m = 0.024;
  s.orifice_diameter_m = 0.008;
  s.upper_height_m = 0.03;
  s.lower_diameter_m = 0.06;
  s.drop_height_m = 0.03;
  s.fill_mass_kg = fill_mass_kg;
  s.fill_lattice_spacing_diameters = 1.25;
  return s;
}

}  // namespace demcal::testing
