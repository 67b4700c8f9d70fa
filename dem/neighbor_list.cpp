#include "dem/neighbor_list.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace demcal::dem {
namespace {

constexpr const char* kAxis[3] = {"x", "y", "z"};

int shift_code(int ox, int oy, int oz) { return (ox + 1) + 3 * (oy + 1) + 9 * (oz + 1); }

}  // namespace

void NeighborList::build(const std::vector<Vec3>& pos, const std::vector<double>& radius,
                         const Domain& domain, double skin_m, ThreadTeam* team) {
  const std::size_t n = pos.size();
  skin_m_ = skin_m;
  // Static split over the team's members: the list comes out the same for any team.
  const int members = team == nullptr ? 1 : team->size();
  auto for_each_member = [&](auto&& body) {
    if (members == 1) {
      body(0, std::size_t{0}, n);
      return;
    }
    team->run([&](int m) {
      body(m, ThreadTeam::split(n, members, m), ThreadTeam::split(n, members, m + 1));
    });
  };
  ++builds_;

  double r_max = 0.0;
  for (double r : radius) r_max = std::max(r_max, r);
  const double cutoff = 2.0 * r_max + skin_m;
  const Vec3 length = domain.length_m();

  std::array<int, 3> nc{};
  std::array<double, 3> inv_cell{};
  std::size_t total_cells = 1;
  for (int k = 0; k < 3; ++k) {
    if (domain.periodic[k] && length[k] < 2.0 * cutoff) {
      std::ostringstream msg;
      msg << "periodic length along " << kAxis[k] << " (" << length[k]
          << " m) must be at least twice the neighbour cut-off (" << 2.0 * cutoff
          << " m = 2 x (largest diameter + skin)); make the periodic slab thicker";
      throw std::runtime_error(msg.str());
    }
    nc[k] = std::max(1, static_cast<int>(std::floor(length[k] / std::max(cutoff, 1e-300))));
    // Bound the cell count in sparse boxes: memory should follow particles, not volume.
    nc[k] = std::min(nc[k], 1 << 10);
    total_cells *= static_cast<std::size_t>(nc[k]);
  }
  while (total_cells > 8 * n + 4096) {
    for (int k = 0; k < 3; ++k) nc[k] = std::max(1, nc[k] / 2);
    total_cells = static_cast<std::size_t>(nc[0]) * nc[1] * nc[2];
  }
  for (int k = 0; k < 3; ++k) inv_cell[k] = nc[k] / length[k];
  for (int oz = -1; oz <= 1; ++oz)
    for (int oy = -1; oy <= 1; ++oy)
      for (int ox = -1; ox <= 1; ++ox)
        shift_table_[shift_code(ox, oy, oz)] = Vec3{ox * length.x, oy * length.y, oz * length.z};

  // Counting sort of particles into cells (serial: O(n), negligible).
  cell_of_.resize(n);
  cell_start_.assign(total_cells + 1, 0);
  std::vector<std::array<int, 3>>& coord = cell_coord_;
  coord.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::array<int, 3> c{};
    for (int k = 0; k < 3; ++k) {
      int ck = static_cast<int>(std::floor((pos[i][k] - domain.lower_m[k]) * inv_cell[k]));
      c[k] = std::clamp(ck, 0, nc[k] - 1);
    }
    coord[i] = c;
    cell_of_[i] = static_cast<std::uint32_t>(c[0] + nc[0] * (c[1] + nc[1] * c[2]));
    ++cell_start_[cell_of_[i] + 1];
  }
  for (std::size_t c = 0; c < total_cells; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_particles_.resize(n);
  fill_.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    cell_particles_[fill_[cell_of_[i]]++] = static_cast<std::uint32_t>(i);

  // Visits, for particle i, each neighbouring cell's candidates j > i as a
  // range, with the image code under which they are met.
  auto for_each_candidate_range = [&](std::size_t i, auto&& visit) {
    const auto& c = coord[i];
    for (int oz = -1; oz <= 1; ++oz) {
      for (int oy = -1; oy <= 1; ++oy) {
        for (int ox = -1; ox <= 1; ++ox) {
          const int o[3] = {ox, oy, oz};
          int cc[3];
          int img[3] = {0, 0, 0};
          bool valid = true;
          for (int k = 0; k < 3 && valid; ++k) {
            cc[k] = c[k] + o[k];
            if (cc[k] < 0) {
              if (!domain.periodic[k]) valid = false;
              cc[k] += nc[k];
              img[k] = -1;
            } else if (cc[k] >= nc[k]) {
              if (!domain.periodic[k]) valid = false;
              cc[k] -= nc[k];
              img[k] = 1;
            }
          }
          if (!valid) continue;
          // With a single cell along a periodic axis, offsets -1, 0, +1 reach the
          // same cell through different images; all three are distinct shifts.
          const std::size_t cell =
              cc[0] + nc[0] * (cc[1] + static_cast<std::size_t>(nc[1]) * cc[2]);
          // A cell lists its particles in ascending order, so its partners
          // j > i are a tail of its range: start there. In spatial order a
          // neighbouring cell holds either only lower or only higher indices,
          // which halves the candidates without changing the list.
          const std::uint32_t* const cell_begin = cell_particles_.data() + cell_start_[cell];
          const std::uint32_t* const cell_end = cell_particles_.data() + cell_start_[cell + 1];
          if (cell_begin == cell_end || cell_end[-1] <= i) continue;
          const std::uint32_t* q0 = cell_begin;
          if (*q0 <= i) q0 = std::upper_bound(cell_begin, cell_end, static_cast<std::uint32_t>(i));
          visit(q0, cell_end, shift_code(img[0], img[1], img[2]));
        }
      }
    }
  };

  // One search: each member lists the pairs of its particles into its own
  // buffers, which are then laid end to end in member order.
  if (found_.size() < static_cast<std::size_t>(members))
    found_.resize(static_cast<std::size_t>(members));
  count_.assign(n + 1, 0);
  for_each_member([&](int m, std::size_t begin, std::size_t end) {
    Found& f = found_[static_cast<std::size_t>(m)];
    f.count = 0;
    for (std::size_t i = begin; i < end; ++i) {
      const std::size_t before = f.count;
      const Vec3 xi = pos[i];
      const double ri = radius[i];
      for_each_candidate_range(i, [&](const std::uint32_t* q0, const std::uint32_t* q1, int code) {
        const std::size_t room = f.count + static_cast<std::size_t>(q1 - q0);
        if (f.partner.size() < room) {
          const std::size_t grown = std::max(room, 2 * f.partner.size());
          f.partner.resize(grown);
          f.code.resize(grown);
        }
        // Every candidate is written and only a neighbour is kept: whether a
        // candidate is within reach is a branch no predictor guesses.
        std::uint32_t* const partner_out = f.partner.data();
        std::uint8_t* const code_out = f.code.data();
        const Vec3 s = shift_table_[code];
        std::size_t kept = f.count;
        for (const std::uint32_t* q = q0; q < q1; ++q) {
          const std::uint32_t j = *q;
          const Vec3 d = xi - (pos[j] + s);
          const double reach = ri + radius[j] + skin_m;
          partner_out[kept] = j;
          code_out[kept] = static_cast<std::uint8_t>(code);
          kept += norm2(d) < reach * reach ? 1 : 0;
        }
        f.count = kept;
      });
      count_[i + 1] = static_cast<std::uint32_t>(f.count - before);
    }
  });
  std::vector<std::uint32_t>& first = spare_first_;
  first.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) first[i + 1] = first[i] + count_[i + 1];
  const std::size_t pairs = first[n];

  // The new list goes into the spare arrays (their memory is reused). Only
  // the histories of touching pairs are carried; the rest are left as they
  // are, meaningless while their pair is not touching (see history()).
  resize_spares(pairs);
  std::vector<std::uint32_t>& partner = spare_partner_;
  std::vector<std::uint8_t>& codes = spare_shift_code_;
  std::vector<ContactHistory>& history = spare_history_;
  std::vector<std::uint8_t>& touching = spare_touching_;
  std::fill(touching.begin(), touching.end(), std::uint8_t{0});
  const std::size_t old_n = first_.empty() ? 0 : first_.size() - 1;

  for_each_member([&](int m, std::size_t begin, std::size_t end) {
    const Found& f = found_[static_cast<std::size_t>(m)];
    const auto kept = static_cast<std::ptrdiff_t>(f.count);
    std::copy(f.partner.begin(), f.partner.begin() + kept, partner.begin() + first[begin]);
    std::copy(f.code.begin(), f.code.begin() + kept, codes.begin() + first[begin]);
    // Carry the history of the pairs that were touching. Pairs are matched by
    // partner alone: with the slab at least two cut-offs thick a pair meets
    // through one image only, and that image changes when a particle is wrapped.
    for (std::size_t i = begin; i < std::min(end, old_n); ++i) {
      for (std::uint32_t q = first_[i]; q < first_[i + 1]; ++q) {
        if (!touching_[q]) continue;
        for (std::uint32_t p = first[i]; p < first[i + 1]; ++p) {
          if (partner[p] == partner_[q]) {
            history[p] = history_[q];
            touching[p] = 1;
            break;
          }
        }
      }
    }
  });

  swap_in_spares();
  position_at_build_ = pos;
}

void NeighborList::resize_spares(std::size_t pairs) {
  spare_partner_.resize(pairs);
  spare_shift_code_.resize(pairs);
  spare_history_.resize(pairs);
  spare_touching_.resize(pairs);
}

void NeighborList::swap_in_spares() {
  first_.swap(spare_first_);
  partner_.swap(spare_partner_);
  shift_code_.swap(spare_shift_code_);
  history_.swap(spare_history_);
  touching_.swap(spare_touching_);
}

void NeighborList::renumber(const std::vector<std::uint32_t>& new_index) {
  if (first_.empty()) return;
  // Particles added since the build are not listed yet: new_index may be longer.
  const std::size_t listed = first_.size() - 1;
  const std::size_t n = new_index.size();
  if (n < listed)
    throw std::invalid_argument("NeighborList::renumber: " + std::to_string(n) +
                                " new indices for " + std::to_string(listed) + " listed particles");
  const std::size_t pairs = partner_.size();
  std::vector<std::uint32_t>& first = spare_first_;
  first.assign(n + 1, 0);
  for (std::size_t i = 0; i < listed; ++i)
    for (std::uint32_t q = first_[i]; q < first_[i + 1]; ++q)
      ++first[std::min(new_index[i], new_index[partner_[q]]) + 1];
  for (std::size_t i = 0; i < n; ++i) first[i + 1] += first[i];
  std::vector<std::uint32_t>& fill = fill_;
  fill.assign(first.begin(), first.end() - 1);
  resize_spares(pairs);
  std::vector<std::uint32_t>& partner = spare_partner_;
  std::vector<std::uint8_t>& codes = spare_shift_code_;
  std::vector<ContactHistory>& history = spare_history_;
  std::vector<std::uint8_t>& touching = spare_touching_;
  for (std::size_t i = 0; i < listed; ++i) {
    for (std::uint32_t q = first_[i]; q < first_[i + 1]; ++q) {
      const std::uint32_t a = new_index[i], b = new_index[partner_[q]];
      const std::uint32_t p = fill[std::min(a, b)]++;
      touching[p] = touching_[q];
      if (a < b) {
        partner[p] = b;
        codes[p] = shift_code_[q];
        history[p] = history_[q];
      } else {
        partner[p] = a;
        codes[p] = static_cast<std::uint8_t>(26 - shift_code_[q]);  // the opposite image
        history[p].tangential_displacement_m = -history_[q].tangential_displacement_m;
        history[p].rolling_torque_nm = -history_[q].rolling_torque_nm;
      }
    }
  }
  swap_in_spares();
  if (position_at_build_.size() == listed && listed == n) {
    std::vector<Vec3> moved(n);
    for (std::size_t i = 0; i < n; ++i) moved[new_index[i]] = position_at_build_[i];
    position_at_build_ = std::move(moved);
  } else {
    position_at_build_.clear();  // not comparable: the next step rebuilds
  }
}

double NeighborList::max_displacement_m(const std::vector<Vec3>& pos) const {
  if (pos.size() != position_at_build_.size()) return std::numeric_limits<double>::infinity();
  double max2 = 0.0;
  const std::size_t n = pos.size();
  for (std::size_t i = 0; i < n; ++i) max2 = std::max(max2, norm2(pos[i] - position_at_build_[i]));
  return std::sqrt(max2);
}

bool NeighborList::needs_rebuild(const std::vector<Vec3>& pos) const {
  return max_displacement_m(pos) > 0.5 * skin_m_;
}

}  // namespace demcal::dem
