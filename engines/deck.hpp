#pragma once
// An input deck for another engine: the script, any files it reads (meshes),
// the names of what it writes, and the record of how it was made (the
// parameter mapping and the apparatus layout) for the run store.

#include "engines/parameter_mapping.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace demcal::engines {

struct DeckOptions {
  std::string script_name = "in.demcal";
  std::string final_dump_name = "final.dump";        // particles at the end (custom dump)
  std::string mass_series_name = "mass_series.txt";  // discharge runs only
  std::string fill_dump_name = "fill.dump";  // the settled fill before opening (LAMMPS discharges)
  // Verlet skin as a fraction of the largest diameter (demcal's default).
  double skin_fraction_of_diameter = 0.3;
  int thermo_every_steps = 2000;
  MappingOptions mapping;
};

struct Deck {
  std::string engine;  // "lammps" | "liggghts"
  std::string script_name;
  std::string script;
  std::vector<std::pair<std::string, std::string>> files;  // (name, content) beside the script
  std::string final_dump_name;
  std::string mass_series_name;  // empty when the run records no m(t)
  std::string fill_dump_name;    // empty when the deck writes no dump of the settled fill
  nlohmann::json record;         // {"engine", "mapping", "layout", "measurement"}
};

struct DeckResult {
  std::optional<Deck> deck;
  std::string refusal;
  bool ok() const { return deck.has_value(); }
};

// The revision of an engine's deck writer: raised when a change to the decks
// changes the runs' results, and written into the run key (study/run_store.hpp)
// when above 1, so a store never reuses a run made from an older deck.
// LAMMPS: 1. LIGGGHTS: 1 the first; 2 (issue 17) every fix wall/gran line ends
// with "limitForce on" (wall impacts no longer end attractive).
int deck_revision(const std::string& engine);

// Writes the script and its files into `directory` (created if missing).
void write_deck_files(const Deck& deck, const std::filesystem::path& directory);

// Locale-independent shortest round-trip text of a number, as decks print them.
std::string deck_number(double value);

struct LatticeFill;  // engines/apparatus_layout.hpp

// The region a lattice fill's sites are created in, from z_lower_m to the
// fill's top: its box, or the box's sites within its cylinder's radius. The
// same command in LAMMPS and LIGGGHTS.
std::string lattice_fill_region_command(const LatticeFill& fill, const std::string& name,
                                        double z_lower_m);

}  // namespace demcal::engines
