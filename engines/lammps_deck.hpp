#pragma once
// LAMMPS input decks (29Sep2021, GRANULAR package, atom_style sphere) written
// from demcal's apparatus descriptions: walls as fix wall/gran planes and
// fix wall/gran/region blocks, fix pour or a jittered lattice, the protocol as
// run-and-check loops (so "at rest" means demcal's rule: rms translational
// speed below rest_speed_m_s, checked every check_interval_s), m(t) through a
// fix print, the particles at the end through write_dump. Run it with
// `lmp -in <script_name>` (or mpirun) in the deck's directory.

#include "engines/apparatus_layout.hpp"
#include "engines/deck.hpp"

namespace demcal::engines {

// Refuses (never throws for) what LAMMPS or the layout cannot do; throws
// std::invalid_argument for an invalid apparatus description, as demcal would.
DeckResult write_lammps_deck(const ApparatusLayout& layout, const DeckOptions& options = {});

DeckResult write_lammps_deck(const dem::PouredSlabPileOptions& apparatus,
                             const DeckOptions& options = {});
DeckResult write_lammps_deck(const dem::RectangularContainerOptions& apparatus,
                             const dem::GranularMaterial& material,
                             const dem::RunProtocol& protocol, const DeckOptions& options = {});
DeckResult write_lammps_deck(const dem::SandglassOptions& apparatus,
                             const dem::GranularMaterial& material,
                             const dem::RunProtocol& protocol, const DeckOptions& options = {});
DeckResult write_lammps_deck(const dem::ConicalPileOptions& apparatus,
                             const dem::GranularMaterial& material,
                             const dem::RunProtocol& protocol, const DeckOptions& options = {});

}  // namespace demcal::engines
