#pragma once
// demcal's own measurement of an engine's run: the final particles and m(t)
// read back (dump_reader.hpp) and measured by dem/measure with the rules the
// demcal apparatus use, so an engine run yields the same observables, under
// the same names, as a demcal run.

#include "dem/apparatus/apparatus.hpp"
#include "engines/deck.hpp"
#include "engines/dump_reader.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace demcal::engines {

// `plan` is the layout's measurement (Deck::record["measurement"]). The series
// is needed for a discharge plan and ignored otherwise. A pile that cannot be
// measured gives angle_of_repose_deg = null and the reason in details, as the
// demcal apparatus do.
// With `settled_fill` (the particles when the fill has settled, before the
// orifice opens) and a plan that carries "bulk_density", the sandglass's
// bulk_density_kg_m3 by dem::Sandglass's rule: fill mass over the chamber
// volume below the fill surface (the mean of the highest grain tops in bins
// of 2 d across the inner 80 % of the chamber).
dem::ApparatusResult measure_engine_output(const nlohmann::json& plan,
                                           const ParticleDump& final_state,
                                           const MassSeries* series,
                                           const ParticleDump* settled_fill = nullptr);

// Reads the deck's outputs from the run directory and measures them.
dem::ApparatusResult measure_engine_run(const Deck& deck,
                                        const std::filesystem::path& run_directory);

}  // namespace demcal::engines
