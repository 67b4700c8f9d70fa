#include "calibrate/adaptive_design_runs.hpp"

namespace demcal::calibrate {

std::uint64_t run_seed(std::uint64_t design_seed, std::size_t batch, std::size_t slot) {
  // SplitMix64 (Steele, Lea & Flood 2014) over the three numbers in turn.
  auto mix = [](std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  };
  std::uint64_t h = mix(design_seed);
  h = mix(h ^ static_cast<std::uint64_t>(batch));
  h = mix(h ^ static_cast<std::uint64_t>(slot));
  return h;
}

}  // namespace demcal::calibrate
