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

}  // namespace demcal::testing
