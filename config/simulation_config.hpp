#pragma once
// Reads a simulation config (TOML) into a fully assembled dem::Simulation plus
// the run-control and output settings. The reader is strict because a typo in
// a calibration input silently falls back to a default and wastes a campaign:
// every unknown key, missing required key, wrong type or out-of-range value is
// a ConfigError naming file, line, dotted key and what was expected, e.g.
//   poured.toml:14: interaction[1].sliding_friction: expected a number >= 0, got -0.2
//
// Schema (SI units in every key name; "opt" keys may be left out, the default
// is written into the resolved config that goes into run.json):
//
//   [simulation]
//   name = "pile"                         # string, required
//   seed = 1                              # opt, integer >= 0
//   threads = 1                           # opt, integer >= 1
//   gravity_m_s2 = [0, 0, -9.81]          # opt
//   time_step_s = 0.0                     # opt, 0 = fraction of the Rayleigh time
//   time_step_fraction_of_rayleigh = 0.2  # opt, (0, 1]
//   skin_fraction_of_diameter = 0.3       # opt, > 0
//   restitution_model = "exact"           # opt, "exact" | "linear_spring_formula"
//   max_speed_m_s = 0.0                   # opt, 0 = derived from the box
//   particle_order = "spatial"            # opt, "spatial" | "insertion" (not written in when
//                                         #   absent or "spatial"): dem/particle_order.hpp
//
//   [domain]
//   lower_m = [x, y, z]                   # required
//   upper_m = [x, y, z]                   # required
//   periodic = [false, false, false]      # opt
//
//   [contact]
//   normal = "hertz"                      # required (names: dem::known_part_names)
//   adhesion = "none"                     # opt, "none" | "jkr" (JKR cohesion,
//                                         #   dem/contact/jkr_adhesion.hpp): "jkr" needs
//                                         #   surface_energy_j_m2 in some [[interaction]]; a
//                                         #   surface energy > 0 with "none" is refused
//   tangential = "mindlin"                # required
//   rolling = "epsd"                      # required
//                                         #   "cdt" | "epsd" | "sds" | "none": "epsd"'s spring
//                                         #   follows the overlap, "sds"'s is constant as
//                                         #   LAMMPS's (dem/contact/constant_spring_rolling.hpp)
//   cdt_own_angular_velocity = false      # opt, only with rolling = "cdt"
//
//   [[material]]                          # one or more
//   name = "grain"
//   density_kg_m3 = 2650.0
//   youngs_modulus_pa = 1e7               # or shear_modulus_pa (or both, consistent)
//   poisson_ratio = 0.3
//
//   [[interaction]]                       # one per pair of materials that can meet
//   materials = ["grain", "grain"]
//   restitution = 0.6                     # (0, 1]
//   sliding_friction = 0.5                # >= 0
//   rolling_friction = 0.1                # >= 0
//   rolling_stiffness_factor = 2.25       # opt, > 0
//   rolling_damping_ratio = 0.3           # opt, >= 0
//   surface_energy_j_m2 = 0.0             # opt, >= 0: JKR surface energy gamma of each surface
//                                         #   (pull-off 3 pi gamma R*); not written in when absent
//   <a contact part's own keys>           # opt: each part declares its keys, units, ranges and
//                                         #   defaults (dem/contact/part_parameter.hpp); they are
//                                         #   not written in when absent, refused unless their
//                                         #   part is in [contact]; list: `demcal schema contact`
//
//   [air]                                 # opt; absent = no air (not written in)
//   drag = "none"                         # opt, "none" | "schiller_naumann" (dem/air_drag.hpp):
//                                         #   drag of still air on every particle
//   density_kg_m3 = 1.2                   # opt, > 0
//   dynamic_viscosity_pa_s = 1.8e-5       # opt, > 0
//   drag_scale = 1.0                      # opt, >= 0: multiplies the whole drag; the strength
//                                         #   `demcal diagnose` varies: 1 = still air as
//                                         #   Schiller-Naumann gives it, 0 = off, between = a
//                                         #   partial effect (e.g. drag screened in a dense
//                                         #   stream); not written in when absent
//
//   [[wall]]
//   type = "plane"                        # see below for each type's geometry keys
//   material = "steel"
//   name = "floor"                        # opt, default "<type>-<index>"
//   velocity_m_s = [0, 0, 0]              # opt: WallMotion
//   moves_from_s = 0.0                    # opt
//   moves_until_s = inf                   # opt
//     plane:         point_m, normal
//     rectangle:     centre_m, normal, axis_u, half_length_u_m, half_length_v_m
//     disk:          centre_m, normal, radius_m
//     cylinder:      base_m, axis, length_m, radius_m
//     cone:          base_m, axis, length_m, radius_base_m, radius_end_m
//     orifice_plate: centre_m, normal, open_time_s, and either diameter_m (a
//                    circular hole) or width_m + axis_u (a slot across axis_u);
//                    opt outer_radius_m (0 = unbounded plate)
//
//   [[insertion]]
//   type = "pour"                         # "pour" | "fill"
//   material = "grain"
//   count = 1500                          # count and/or mass_kg (whichever is reached first)
//   mass_kg = 0.0
//   size = { distribution = "monodisperse", diameter_m = 1e-3 }
//     uniform:          min_diameter_m, max_diameter_m, or
//                       mean_diameter_m, relative_half_width (d uniform in
//                         [mean (1 - w), mean (1 + w)], 0 <= w < 1)
//     truncated_normal: mean_diameter_m, std_dev_m, min_diameter_m, max_diameter_m
//     log_normal:       median_diameter_m, sigma_ln, min_diameter_m, max_diameter_m
//     sieve:            sieve = [[opening_m, cumulative_fraction_passing], ...]
//   region = { shape = "box", lower_m = [..], upper_m = [..] }
//          | { shape = "cylinder", base_centre_m = [..], radius_m = .., height_m = .. }
//   attempts_per_particle = 200           # opt (fill: 400)
//   pour:  velocity_m_s = [0,0,0] (opt), start_s = 0 (opt), and at most one of
//          rate_particles_per_s (> 0) or batch_volume_fraction (default 0.3)
//   fill:  time_s = 0 (opt), method = "random" | "lattice" (opt), lattice_gap = 0.05 (opt)
//
//   [run]
//   end_time_s = 2.0                      # required, > 0
//   stop_at_rest = true                   # opt: stop once insertion is done and the
//   rest_speed_m_s = 2e-3                 # opt      rms translational speed is below this,
//   check_interval_s = 0.01               # opt      checked at this interval
//
//   [output]
//   directory = "out/<simulation.name>"   # opt, relative to the working directory
//   vtk = true                            # opt
//   snapshot_interval_s = 0.0             # opt, 0 = only the final state
//
// Overrides (`--set key=value`) address keys by dotted path. The value is
// parsed as a TOML value (number, bool, "string", [array], {inline table}); a
// bare word that is not valid TOML is taken as a string. Arrays of tables are
// indexed as interaction[0] or selected by name: material.sand, wall.floor (a
// wall without a name by its default, wall.plane-0), interaction.sand-steel
// (either order; names containing '.' cannot be selected). Value arrays may be indexed too:
// domain.upper_m[2]. A key the schema does not know is an error naming it.

#include "config/toml_reader.hpp"
#include "dem/simulation.hpp"

#include <toml++/toml.h>

#include <cstddef>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace demcal::config {

struct RunControl {
  double end_time_s = 0.0;
  bool stop_at_rest = true;
  double rest_speed_m_s = 2e-3;
  double check_interval_s = 0.01;
};

struct OutputSettings {
  std::filesystem::path directory;
  bool vtk = true;
  double snapshot_interval_s = 0.0;
};

struct SimulationConfig {
  std::string file;
  std::string name;
  std::unique_ptr<dem::Simulation> simulation;  // assembled, not yet stepped
  RunControl run;
  OutputSettings output;
  std::vector<std::string> wall_names;       // in the order of simulation->walls()
  std::vector<std::string> insertion_types;  // in the order of simulation->inserters()
  // The whole config after overrides, with every default written in.
  toml::table resolved;
};

// Builds from the document; the document's table is consumed (defaults are
// written into it and it is moved into SimulationConfig::resolved).
SimulationConfig build_simulation(ConfigDocument&& doc);

// read_config_file + apply_override for each + build_simulation.
SimulationConfig load_simulation_config(const std::filesystem::path& path,
                                        const std::vector<std::string>& overrides);

}  // namespace demcal::config
