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

// Where the force loop adds what a contact does to the partner j: the
// particle arrays when the chunk owns j, the chunk's buffer when j lies beyond
// its range (dem/simulation.cpp). With one chunk both are the particle arrays.
struct PartnerForceTargets {
  Vec3* force_own_n;
  Vec3* torque_own_nm;
  Vec3* force_beyond_n;
  Vec3* torque_beyond_nm;
  std::size_t own_end = 0;

  Vec3* force_n(std::size_t j) const { return (j < own_end ? force_own_n : force_beyond_n) + j; }
  Vec3* torque_nm(std::size_t j) const {
    return (j < own_end ? torque_own_nm : torque_beyond_nm) + j;
  }
};

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
//
// For each tested pair it can also ask the processor to fetch what the
// batch's flush will touch: the pair's history (read by ContactBatch::gather)
// and the partner's force and torque (written when the forces are added, at
// `prefetch_for`); and the position and radius of the partner a few pairs on,
// which the scan itself reads next. The scan runs up to a batch ahead of the
// flush, so in a bed larger than the caches those misses overlap instead of
// stalling the flush one after another (BENCHMARKS.md, 2026-12-07). In a bed
// that fits in the caches the prefetches are only extra instructions: with
// `prefetch_for` null the scan issues none (worth_prefetching() decides). A
// prefetch changes no value: the results are the same bits either way.
void stage_touching_pairs(const NeighborList::Arrays& list, const Vec3* position_m,
                          const double* radius_m, std::size_t i_end, PairScanCursor& cursor,
                          ContactBatch& batch, const PartnerForceTargets* prefetch_for);

// Whether a bed's per-step data outgrow the caches, so that the prefetches
// pay for themselves. Measured on the static pile (BENCHMARKS.md,
// 2026-12-07), one thread: 3 000 particles (about 1.5 MB a step) -2 to -4 %,
// 12 000 +6 %, 24 000 +19 %, 48 000 +15 to +20 %. The bytes are what one step
// streams per particle (its arrays, about 240 B) and per listed pair (partner,
// image, flag and history, 54 B): about 500 B per particle of a pile, so the
// 4 MiB threshold (four times a core's L2 here) falls near 8 500 particles,
// between the measured loss and gain.
inline bool worth_prefetching(std::size_t particles, std::size_t listed_pairs) {
  const std::size_t bytes = particles * 240 + listed_pairs * 54;
  return bytes > (std::size_t{4} << 20);
}

// The prefetches of stage_touching_pairs() for listed pair p with partner j
// (also used by the force loop's own scan for laws that hold contacts).
[[gnu::always_inline]] inline void prefetch_for_flush(const NeighborList::Arrays& list,
                                                      std::uint32_t p, std::uint32_t j,
                                                      const PartnerForceTargets& partner) {
  // The entry's last byte: entries are 48 bytes, so every cache line of the
  // history array holds the end of one, and a scan over consecutive pairs
  // reaches every line an entry spans.
  __builtin_prefetch(reinterpret_cast<const char*>(list.history + p) + sizeof(ContactHistory) - 1,
                     0, 3);
  __builtin_prefetch(partner.force_n(j), 1, 3);
  __builtin_prefetch(partner.torque_nm(j), 1, 3);
}

}  // namespace demcal::dem
