#pragma once
// The material tables most unit tests' studies share: quartz sand grains in glass walls,
// Hertz-Mindlin with a rolling part, the paper's frictions. A test writes its own [study]
// and apparatus around them, so that what it is about stands out of the text.
#include <string>

namespace demcal::testing {

struct SandAndGlassOptions {
  // The [material] size, an inline TOML table.
  std::string size = R"({ distribution = "monodisperse", diameter_m = 4.5e-4 })";
  std::string rolling = "cdt";  // [contact] rolling
};

// [material], [wall_material], [contact], [interaction.particle_particle] and
// [interaction.particle_wall], each followed by a blank line except the last.
inline std::string sand_and_glass_tables(const SandAndGlassOptions& o = {}) {
  return R"([material]
name = "sand"
density_kg_m3 = 2650.0
shear_modulus_pa = 3.0e10
poisson_ratio = 0.25
size = )" +
         o.size +
         R"(

[wall_material]
name = "glass"
density_kg_m3 = 2500.0
youngs_modulus_pa = 6.3e10
poisson_ratio = 0.23

[contact]
normal = "hertz"
tangential = "mindlin"
rolling = ")" +
         o.rolling +
         R"("

[interaction.particle_particle]
restitution = 0.6
sliding_friction = 0.52
rolling_friction = 0.3

[interaction.particle_wall]
restitution = 0.6
sliding_friction = 0.5
rolling_friction = 0.3
)";
}

// A small periodic container slab and a 3-point design over mu_r: the study body of the
// engine-dispatch tests, whose fake engines never run a real DEM.
inline std::string small_container_design_tables() {
  return R"(
[apparatus.rectangular_container]
width_m = 0.22
height_m = 0.1
thickness_diameters = 4.0
boundary = "periodic"
fill_mass_kg = 0.055
coarse_graining_factor = 6.0
shear_modulus_pa = 1.0e7

[design]
kind = "full_factorial"
parameters = { mu_r = { lower = 0.1, upper = 0.3, levels = 3 } }
)";
}

}  // namespace demcal::testing
