#pragma once
// Verlet list built from linked cells. Holds every pair (i < j) whose surfaces
// are closer than `skin`, with the periodic image to use for j, and carries the
// contact history (tangential spring, rolling spring) of pairs that stay in the
// list across rebuilds. The list stays valid until some particle has moved
// more than skin/2 since the build. The cell size is the largest diameter plus
// the skin, so any pair of sizes is found (polydisperse beds of any ratio; a
// wide ratio only costs extra distance checks).

#include "dem/contact/contact_state.hpp"
#include "dem/domain.hpp"
#include "dem/thread_team.hpp"
#include "dem/vec3.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace demcal::dem {

class NeighborList {
 public:
  // Positions must lie inside the box along periodic axes (wrap them first).
  // Throws std::runtime_error when a periodic axis is shorter than twice the
  // cut-off (a particle would meet two images of the same neighbour). The
  // per-particle passes run on the team when one is given.
  void build(const std::vector<Vec3>& position_m, const std::vector<double>& radius_m,
             const Domain& domain, double skin_m, ThreadTeam* team = nullptr);

  // Renames the particles after they were reordered: particle i is now
  // new_index[i]. Each pair is kept with its history and image; a pair whose
  // particles swap ranks is listed under the new lower index, its image
  // reversed and its history (the spring elongation and rolling torque on the
  // first particle, both odd under the swap) negated. Call build() next: the
  // pairs are grouped by particle but not in build order.
  void renumber(const std::vector<std::uint32_t>& new_index);

  // True when some particle has moved more than half the skin since the build.
  bool needs_rebuild(const std::vector<Vec3>& position_m) const;
  double max_displacement_m(const std::vector<Vec3>& position_m) const;

  // Where each particle was at the last build, and the skin: lets the
  // integrator fold the displacement check into its own loop.
  const std::vector<Vec3>& positions_at_build() const { return position_at_build_; }
  double skin_m() const { return skin_m_; }
  std::size_t pair_count() const { return partner_.size(); }
  std::size_t build_count() const { return builds_; }

  // Pairs of particle i: indices first(i) .. first(i+1).
  std::uint32_t first(std::size_t i) const { return first_[i]; }
  std::uint32_t partner(std::size_t p) const { return partner_[p]; }
  const Vec3& image_shift(std::size_t p) const { return shift_table_[shift_code_[p]]; }
  // A pair's history means something only while touching(p) is 1: the force
  // loop does not clear the history of a pair that parts (it starts the next
  // contact of that pair from rest instead, dem/contact_batch.hpp), and a
  // build carries over the histories of touching pairs only.
  ContactHistory& history(std::size_t p) { return history_[p]; }
  std::uint8_t& touching(std::size_t p) { return touching_[p]; }

  // The same list as raw arrays, for the force loop. That loop stores a byte
  // per pair (the touching flag), and a byte store may alias any object: read
  // through the accessors above, every vector's data pointer would be loaded
  // again from memory at every pair. Valid until the next build or renumber.
  struct Arrays {
    const std::uint32_t* first;
    const std::uint32_t* partner;
    const std::uint8_t* shift_code;
    const Vec3* shift_table;
    ContactHistory* history;
    std::uint8_t* touching;
  };
  Arrays arrays() {
    return {first_.data(),        partner_.data(), shift_code_.data(),
            shift_table_.data(),  history_.data(), touching_.data()};
  }

 private:
  std::vector<std::uint32_t> first_;
  std::vector<std::uint32_t> partner_;
  std::vector<std::uint8_t> shift_code_;
  std::vector<ContactHistory> history_;
  std::vector<std::uint8_t> touching_;
  std::array<Vec3, 27> shift_table_{};
  std::vector<Vec3> position_at_build_;
  double skin_m_ = 0.0;
  std::size_t builds_ = 0;

  // Scratch reused between builds. A build or renumber writes the new list
  // into the spare arrays and then swaps them with the current ones, so the
  // list's memory is allocated once, not at every build: arrays of hundreds of
  // kilobytes were mapped, zeroed by page faults and unmapped again every few
  // dozen steps (issue 13).
  void resize_spares(std::size_t pairs);  // the spare arrays, to a list of this many pairs
  void swap_in_spares();                  // the spare arrays become the list
  std::vector<std::uint32_t> spare_first_;
  std::vector<std::uint32_t> spare_partner_;
  std::vector<std::uint8_t> spare_shift_code_;
  std::vector<ContactHistory> spare_history_;
  std::vector<std::uint8_t> spare_touching_;
  std::vector<std::uint32_t> cell_start_;
  std::vector<std::uint32_t> cell_particles_;
  std::vector<std::uint32_t> cell_of_;
  std::vector<std::array<int, 3>> cell_coord_;
  std::vector<std::uint32_t> count_;
  std::vector<std::uint32_t> fill_;
  // One member's pairs during a build: the first `count` entries. The arrays
  // are written past `count` (a candidate is written, then kept or not), so
  // they are sized ahead of the writes, not grown by push_back.
  struct Found {
    std::vector<std::uint32_t> partner;
    std::vector<std::uint8_t> code;
    std::size_t count = 0;
  };
  std::vector<Found> found_;
};

}  // namespace demcal::dem
