#pragma once
// LIGGGHTS 3.8 input decks written from demcal's apparatus descriptions:
// materials per atom type (1 grains, 2 walls) as property/global fixes, planes
// as fix wall/gran primitives, solid blocks, hopper plates, cylinders, cones and
// discs as STL meshes this writer emits (engines/stl_mesh.hpp, fix mesh/surface), insertion by
// insert/pour or a jittered lattice, the protocol as run-and-check loops on demcal's rest rule,
// m(t) through a fix print, the particles at the end through a custom dump. Run it with `liggghts
// -in <script_name>` in the deck's directory.

#include "engines/apparatus_layout.hpp"
#include "engines/deck.hpp"
#include "engines/stl_mesh.hpp"

namespace demcal::engines {

DeckResult write_liggghts_deck(const ApparatusLayout& layout, const DeckOptions& options = {});

DeckResult write_liggghts_deck(const dem::PouredSlabPileOptions& apparatus,
                               const DeckOptions& options = {});
DeckResult write_liggghts_deck(const dem::RectangularContainerOptions& apparatus,
                               const dem::GranularMaterial& material,
                               const dem::RunProtocol& protocol, const DeckOptions& options = {});
DeckResult write_liggghts_deck(const dem::SandglassOptions& apparatus,
                               const dem::GranularMaterial& material,
                               const dem::RunProtocol& protocol, const DeckOptions& options = {});
DeckResult write_liggghts_deck(const dem::ConicalPileOptions& apparatus,
                               const dem::GranularMaterial& material,
                               const dem::RunProtocol& protocol, const DeckOptions& options = {});

}  // namespace demcal::engines
