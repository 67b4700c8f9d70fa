#pragma once
// The order particles are stored in. Insertion order (the engine's default in
// SimulationOptions; the config readers' default is spatial since run keys of
// version 2, issue 13) keeps each particle at the index it was added with. Spatial order sorts them by the
// cell of a grid as wide as the neighbour cut-off at every neighbour build, so
// a particle's neighbours sit at nearby indices: a thread's contiguous chunk
// of particles then has partners only in a narrow window of indices (fewer
// force-buffer entries to clear and sum), and the contact loop reads memory
// that is near in the cache. It changes the order of every floating-point sum
// over particles, so results differ bit-wise from insertion order (they still
// repeat bit for bit for a seed and thread count).

#include "dem/domain.hpp"
#include "dem/vec3.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace demcal::dem {

enum class ParticleOrder { kInsertion, kSpatial };

// "insertion" | "spatial".
const char* particle_order_name(ParticleOrder order);
// The names above, for config readers and command lines.
const std::vector<std::string>& particle_order_names();
// Throws std::invalid_argument naming the known names when `name` is none of them.
ParticleOrder parse_particle_order(const std::string& name);

// The spatial order of `position_m`: entry k is the index of the particle to
// store at k. Particles are sorted by the cell of a grid of about `cell_m`
// over the domain (at most 1024 cells an axis and about 8 cells a particle,
// like the neighbour grid), the axis with the most cells varying slowest so
// that a contiguous run of indices is a thin slab of the domain; within a
// cell they keep their present order (a stable sort, so the order is
// deterministic). Positions outside the box are clamped to its edge cells.
std::vector<std::uint32_t> spatial_order(const std::vector<Vec3>& position_m, const Domain& domain,
                                         double cell_m);

}  // namespace demcal::dem
