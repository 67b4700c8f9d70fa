#include "dem/pair_scan.hpp"

#include "dem/vector_clones.hpp"

#include <algorithm>

namespace demcal::dem {

namespace {

// The scan, with or without the prefetches; inlined into each instruction-set
// version of stage_touching_pairs().
template <bool kPrefetch>
inline __attribute__((always_inline)) void scan(const NeighborList::Arrays& list,
                                                const Vec3* position_m, const double* radius_m,
                                                std::size_t i_end, PairScanCursor& cursor,
                                                ContactBatch& batch,
                                                const PartnerForceTargets* partner_targets) {
  const std::uint32_t* const first = list.first;
  const std::uint32_t* const partner = list.partner;
  const std::uint8_t* const shift_code = list.shift_code;
  const Vec3* const shift_table = list.shift_table;
  std::uint8_t* const touching = list.touching;
  // The count of taken slots lives in a register: `batch` is written through
  // byte stores, which may alias anything.
  int taken = batch.size;
  std::size_t i = cursor.i;
  std::uint32_t p = cursor.p;
  // The scan's own lookahead: the partner kAhead pairs on, whose position
  // and radius the scan reads shortly (clamped to the last pair it tests).
  constexpr std::uint32_t kAhead = 16;
  [[maybe_unused]] const std::uint32_t last_pair = first[i_end] > 0 ? first[i_end] - 1 : 0;
  for (; i < i_end; ++i) {
    const Vec3 xi = position_m[i];
    const double ri = radius_m[i];
    const std::uint32_t end = first[i + 1];
    for (; p < end; ++p) {
      const std::uint32_t j = partner[p];
      const Vec3 d = xi - (position_m[j] + shift_table[shift_code[p]]);
      const double rsum = ri + radius_m[j];
      // Written as "not parted" so that a NaN position counts as a contact.
      const bool on = !(norm2(d) >= rsum * rsum);
      // Every pair is staged and only a contact is taken, without a branch:
      // about half the listed pairs touch, a branch no predictor guesses.
      batch.stage(taken, static_cast<std::uint32_t>(i), p, touching[p] != 0);
      if constexpr (kPrefetch) {
        prefetch_for_flush(list, p, j, *partner_targets);
        const std::uint32_t j_ahead = partner[std::min(p + kAhead, last_pair)];
        __builtin_prefetch(position_m + j_ahead, 0, 3);
        __builtin_prefetch(radius_m + j_ahead, 0, 3);
      }
      touching[p] = on ? 1 : 0;
      taken += on ? 1 : 0;
      if (taken == ContactBatch::kCapacity) {
        cursor.i = i;
        cursor.p = p + 1;
        batch.size = taken;
        return;
      }
    }
  }
  cursor.i = i;
  cursor.p = p;
  batch.size = taken;
}

}  // namespace

DEMCAL_VECTOR_CLONES
void stage_touching_pairs(const NeighborList::Arrays& list, const Vec3* position_m,
                          const double* radius_m, std::size_t i_end, PairScanCursor& cursor,
                          ContactBatch& batch, const PartnerForceTargets* prefetch_for) {
  if (prefetch_for != nullptr)
    scan<true>(list, position_m, radius_m, i_end, cursor, batch, prefetch_for);
  else
    scan<false>(list, position_m, radius_m, i_end, cursor, batch, nullptr);
}

}  // namespace demcal::dem
