#pragma once
// The pair loop's contact test: which of the listed pairs overlap at this
// step. It runs over every listed pair (about twice the contacts), so it is a
// function of its own over raw arrays: every pointer it needs stays in a
// register (inlined into the force loop, with its many live values, GCC
// reloaded the list's pointers from the stack at every pair), and it is built
// for each instruction set as evaluate() is.

#include "dem/contact_batch.hpp"
#include "dem/neighbor_list.hpp"
#include "dem/vec3.hpp"

#include <cstddef>
#include <cstdint>

namespace demcal::dem {

// Where a scan of the listed pairs stands: particle i and the index p of the
// next of its listed pairs to test (list.first[i] <= p <= list.first[i + 1]).
struct PairScanCursor {
  std::size_t i = 0;
  std::uint32_t p = 0;
};

// Tests the listed pairs from `cursor` on, up to the last pair of particle
// i_end - 1, and stages each pair whose spheres overlap into `batch` (from
// slot batch.size on; ContactBatch::stage). A NaN position counts as an
// overlap, so that it reaches the stability check through the forces. Each
// tested pair's touching flag is set to whether it overlaps now; its history
// is left as it is (ContactBatch::was_touching says whether it is current).
// Returns when the batch is full, with the cursor at the next pair to test, or
// when the pairs run out, with cursor.i == i_end. For a law that holds
// contacts beyond touching (adhesion) the force loop tests pairs itself.
void stage_touching_pairs(const NeighborList::Arrays& list, const Vec3* position_m,
                          const double* radius_m, std::size_t i_end, PairScanCursor& cursor,
                          ContactBatch& batch);

}  // namespace demcal::dem
