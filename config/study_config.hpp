#pragma once
// Reads a study config (TOML): one granular material, the wall material, the
// contact law, the run protocol and one or more apparatus (laboratory tests
// from dem/apparatus) that are run with them. A study names what is
// calibrated and where; the apparatus builds its own simulation from named
// dimensions, so the config holds no walls, boxes or insertions.
//
// The reader is as strict as the plain simulation config's (it is built from
// the same pieces, config/toml_reader.hpp): an unknown key, a missing required key
// (every dimension is required: the paper's are unknown, so a study states
// each one), a wrong type or an out-of-range value is a ConfigError naming
// file:line, the dotted key and what was expected. Building each apparatus is
// part of reading the file: what its constructor refuses (a chamber that cannot
// hold the fill, an orifice narrower than 3 grains, ...) is a ConfigError naming
// the apparatus table and, when the message names one, the key, before
// anything runs, e.g.
//   study.toml:31: apparatus.sandglass.fill_mass_kg: sandglass: the upper chamber
//   cannot hold the fill: ...
//
// Schema (SI units in every key name; "opt" keys may be left out, the default
// is written into the resolved config that goes into run.json):
//
//   [study]
//   name = "sandglass-quick"              # string, required; names the output directory
//   seed = 1                              # opt, integer >= 0
//   threads = 1                           # opt, integer >= 1
//
//   [material]                            # the granular material (what is calibrated)
//   name = "quartz"
//   density_kg_m3 = 2650.0
//   youngs_modulus_pa = 1e7               # or shear_modulus_pa (or both, consistent)
//   poisson_ratio = 0.25
//   size = { distribution = "uniform", min_diameter_m = 3e-4, max_diameter_m = 6e-4 }
//     monodisperse:     diameter_m
//     uniform:          min_diameter_m, max_diameter_m, or
//                       mean_diameter_m, relative_half_width   # d uniform in [mean (1 - w),
//                         mean (1 + w)], w in [0, 1): the spread as one key (alias size_spread)
//                         that a design varies at a fixed mean
//     truncated_normal: mean_diameter_m, std_dev_m, min_diameter_m, max_diameter_m
//     log_normal:       median_diameter_m, sigma_ln, min_diameter_m, max_diameter_m
//     sieve:            sieve = [[opening_m, cumulative_fraction_passing], ...]
//
//   [wall_material]                       # what every wall of the apparatus is made of
//   name = "steel"
//   density_kg_m3 = 7800.0
//   youngs_modulus_pa = 2e11              # or shear_modulus_pa
//   poisson_ratio = 0.3
//
//   [contact]
//   normal = "hertz"                      # required (names: dem::known_part_names)
//   adhesion = "none"                     # opt, "none" | "jkr": JKR cohesion
//                                         #   (dem/contact/jkr_adhesion.hpp); "jkr" needs
//                                         #   surface_energy_j_m2 in an interaction; a
//                                         #   surface energy > 0 with "none" is refused
//   tangential = "mindlin"                # required
//   rolling = "cdt"                       # required
//                                         #   "cdt" | "epsd" | "sds" | "none": "epsd"'s spring
//                                         #   follows the overlap, "sds"'s is constant as
//                                         #   LAMMPS's (dem/contact/constant_spring_rolling.hpp)
//   cdt_own_angular_velocity = false      # opt, only with rolling = "cdt"
//   restitution_model = "exact"           # opt, "exact" | "linear_spring_formula"
//
//   [interaction.particle_particle]       # and [interaction.particle_wall], both required
//   restitution = 0.6                     # (0, 1]
//   sliding_friction = 0.52               # >= 0
//   rolling_friction = 0.3                # >= 0
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
//   [protocol]                            # opt, every key opt; defaults from dem::RunProtocol
//   rest_speed_m_s = 5e-3                 # "at rest": rms speed below this (> 0),
//   check_interval_s = 0.01               #   checked at this interval (> 0)
//   max_settle_s = 2.0                    # cap on each settling phase (> 0)
//   max_flow_s = 60.0                     # cap on each flow phase (discharge, pour) (> 0)
//   sample_interval_s = 0.005             # m(t) sampling (> 0)
//   stall_time_s = 0.1                    # the flow has stopped when nothing passed for this (> 0)
//   time_step_fraction_of_rayleigh = 0.2  # (0, 1]
//   max_steps = 1e10                      # opt (not written in when absent): a run whose
//                                         #   estimated steps exceed it is refused before it
//                                         #   starts (config/run_sanity.hpp)
//   particle_order = "spatial"            # opt, "spatial" | "insertion" (not written in when
//                                         #   absent or "spatial"): how the engine stores
//                                         #   particles (dem/particle_order.hpp); "spatial"
//                                         #   re-sorts them by neighbour cell at each neighbour
//                                         #   build (the default: faster, same statistics);
//                                         #   "insertion" keeps them in the order they were
//                                         #   added (results differ bit-wise)
//   The physical sanity rules of config/run_sanity.hpp apply on top of each key's range:
//   check_interval_s >= rest_speed_m_s / g; rest_speed_m_s at most the speed of a grain
//   fallen a tenth of its diameter; at most 10 % overlap in a 1 m/s collision; the step
//   estimate. Densities are at most 3e4 kg/m3, moduli 1e13 Pa, friction coefficients 10,
//   apparatus lengths 100 m (a cone's height too); restitution with the exact model at
//   least dem::smallest_resolved_restitution() (~2.5e-7).
//
//   Several setups of one kind: name the table freely and give its kind,
//     [apparatus.orifice_16mm]
//     type = "sandglass"                  # "sandglass" | "conical_pile" | "rectangular_container"
//   (a table named after its kind needs no type). The table's name is the
//   setup's name in recordings, surrogates and reports.
//   One or more of the apparatus tables below. Every dimension is required.
//   Each also takes the model reductions (dem::ModelReduction), all opt:
//     slice = false                       # a periodic slab instead of the whole apparatus
//     slice_thickness_diameters = 4.0     # >= 2; used only when slice = true
//     coarse_graining_factor = 1.0        # > 0; every particle scaled by f, geometry kept;
//                                         #   surface energies scaled by f^2 (the grains' Bond
//                                         #   number), air drag of a parcel = f^3 grains' drag
//     shear_modulus_pa = 0.0              # >= 0; 0 keeps the material's modulus
//   (the rectangular container takes no slice keys: its thickness and boundary
//   are its own keys).
//
//   [apparatus.sandglass]
//   upper_diameter_m, upper_height_m      # the upper chamber's cylindrical part
//   bottom = "conical"                    # "flat" | "conical"
//   hopper_half_angle_deg                 # (0, 80), from the vertical; required when
//                                         #   conical, used only then
//   orifice_diameter_m                    # the slice's slot width
//   fill_mass_kg                          # of the full apparatus; a slice takes its share
//   lower_diameter_m, drop_height_m       # lower chamber; orifice plane above its floor
//   form_pile = true                      # opt; false: stop after max_flow_s of discharge,
//                                         #   no pile, no AoR (flow-rate studies, Beverloo)
//   fill_lattice_spacing_diameters = 1.05 # opt, (1, 3]: the fill's lattice, in largest diameters
//
//   [apparatus.conical_pile]
//   funnel_top_diameter_m, funnel_outlet_diameter_m, funnel_half_angle_deg (0, 80),
//   feed_height_m, drop_height_m, base_diameter_m, fill_mass_kg
//
//   [apparatus.rectangular_container]
//   width_m, height_m
//   thickness_m | thickness_diameters     # exactly one (> 0)
//   boundary = "periodic"                 # "walls" | "periodic" across the thickness
//   fill_mass_kg
//   inlet_width_m = 0.0                   # opt, >= 0; 0 = 8 mean diameters
//   inlet_height_m = 0.0                  # opt, in [0, height_m); 0 = 0.8 height_m
//   inlet_speed_m_s = 0.5                 # opt, > 0, downwards
//   median_band_diameters = 2.0           # opt, > 0
//
//   [output]
//   directory = "out/<study.name>/<apparatus>"  # opt, relative to the working directory;
//                                         #   given explicitly, it is used as is
//   vtk = false                           # opt; snapshots cost time and disk
//   snapshot_interval_s = 0.0             # opt, >= 0; 0 = only the final state
//
//   [design]                              # opt; the runs of `demcal doe`
//   (config/design_config.hpp) kind = "full_factorial"               # "full_factorial" |
//   "latin_hypercube" | "sobol" points = 20                           # latin_hypercube and sobol
//   only (required there) replicates = 1                        # opt, >= 1; replicate r runs with
//   seed study.seed + r seed = 1                              # opt, >= 0; latin_hypercube's
//   generator seed skip = 0                              # opt, sobol only parameters = { mu_r = {
//   lower = 0.05, upper = 0.6, levels = 5 }, ... }
//                                         # any --set key (mu_r, mu_s, "apparatus.x.y");
//                                         #   lower < upper; levels (>= 2) with full_factorial only
//   `demcal simulate` accepts and ignores [design]: it runs the study as written.
//
//   [surrogate]                           # opt; what `demcal fit` fits
//   (config/surrogate_config.hpp) model = "gaussian_process"            # | "polynomial"; further
//   keys per model there
//
//   [engine]                              # opt; which DEM engine runs the design points
//   (config/engine_config.hpp) kind = "demcal"  # | "liggghts" | "lammps"; launch = "mpirun -np 2
//   liggghts" (another engine only). Absent or "demcal": not part of any run key.
//
//   [calibration]                         # opt; what `demcal calibrate` fits
//   (config/calibration_config.hpp) recordings = "recordings.csv"         # relative to this file;
//   further keys there
//
//   [raw_recordings.sandglass]            # opt; each repeat's h(x) and m(t) as CSV, measured as
//   profiles = [...]  mass_series = [...] #   the runs are (config/raw_recordings.hpp)
//
// Overrides (`--set key=value`) address keys by dotted path as for plain configs
// (config/simulation_config.hpp), e.g. --set apparatus.sandglass.orifice_diameter_m=0.01.
// Aliases name the calibrated pair the way the paper does, and the parameters
// of the physics modules:
//   --set mu_s=0.52   is   --set interaction.particle_particle.sliding_friction=0.52
//   --set mu_r=0.3    is   --set interaction.particle_particle.rolling_friction=0.3
//   mu_s_wall, mu_r_wall     interaction.particle_wall.sliding_friction, .rolling_friction
//   surface_energy           interaction.particle_particle.surface_energy_j_m2
//   surface_energy_wall      interaction.particle_wall.surface_energy_j_m2
//   size_spread              material.size.relative_half_width (the mean_diameter_m form)
//   drag_scale               air.drag_scale
// A design names them the same way ([design] parameters = { size_spread = {...} }).
//
// The resolved config a run records (resolved_for) holds only the apparatus
// that ran, and no [design], so two runs of the same apparatus with the same
// inputs record the same inputs whatever else the study defines.

#include "config/calibration_config.hpp"
#include "config/design_config.hpp"
#include "config/diagnosis_config.hpp"
#include "config/engine_config.hpp"
#include "config/raw_recordings.hpp"
#include "config/simulation_config.hpp"
#include "config/surrogate_config.hpp"
#include "config/toml_reader.hpp"
#include "dem/apparatus/apparatus.hpp"
#include "dem/apparatus/granular_material.hpp"

#include <toml++/toml.h>

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace demcal::config {

// The apparatus a study can define, as named in [apparatus.<name>]: the names
// of the apparatus registry (config/models/apparatus_models.hpp), in
// registration order.
const std::vector<std::string>& known_apparatus_names();

// mu_s, mu_r and the other short names listed above.
const OverrideAliases& study_override_aliases();

// A config is a study config when it has an [apparatus] table.
bool is_study_config(const ConfigDocument& doc);

struct StudyApparatus {
  std::string name;      // the setup: the table's name
  std::string kind;      // "sandglass", "conical_pile", "rectangular_container"
  std::size_t line = 0;  // of its table, for messages
  std::unique_ptr<dem::Apparatus> apparatus;  // built, not yet run
};

struct StudyConfig {
  std::string file;
  std::string name;
  dem::GranularMaterial material;
  dem::RunProtocol protocol;
  std::vector<StudyApparatus> apparatus;  // every one defined, in file order
  // directory is empty unless the file (or --output) gives it: the default
  // depends on the apparatus (output_directory()).
  OutputSettings output;
  // [design], when the study has one (config/design_config.hpp).
  std::optional<DesignConfig> design;
  // [surrogate], when the study has one (config/surrogate_config.hpp).
  std::optional<SurrogateConfig> surrogate;
  // [calibration], when the study has one (config/calibration_config.hpp).
  std::optional<CalibrationConfig> calibration;
  // [diagnosis], when the study has one (config/diagnosis_config.hpp).
  std::optional<DiagnosisConfig> diagnosis;
  // [engine], when the study has one (config/engine_config.hpp): absent or
  // kind = "demcal" runs demcal's own engine.
  std::optional<EngineConfig> engine;
  // [raw_recordings.<setup>], when the study has it (config/raw_recordings.hpp): profiles
  // and m(t) series measured as the runs are, added to the recordings.
  std::optional<RawRecordingsConfig> raw_recordings;
  // The whole config after overrides, with every default written in.
  toml::table resolved;
};

// Builds every apparatus the document defines; the document's table is
// consumed (defaults are written in and it becomes StudyConfig::resolved).
StudyConfig build_study(ConfigDocument&& doc);

// read_config_file + apply_override (with the aliases) for each + build_study.
StudyConfig load_study_config(const std::filesystem::path& path,
                              const std::vector<std::string>& overrides);

// The apparatus to run: `requested` if given (an error listing the defined
// ones when the study has no such apparatus), else the only one defined (an
// error listing them when there are several).
StudyApparatus& select_apparatus(StudyConfig& study, const std::optional<std::string>& requested);

std::filesystem::path output_directory(const StudyConfig& study, const std::string& apparatus);

// The resolved config of a run of one apparatus: the others left out and the
// output directory written in.
toml::table resolved_for(const StudyConfig& study, const std::string& apparatus);

}  // namespace demcal::config
