#pragma once
// What an adaptive design asks for and what comes back: one run is one simulator call at a
// parameter point with a replicate index and a seed. The design never runs anything itself;
// the caller's evaluator (a DEM campaign, or an analytic function in tests) does.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace demcal::calibrate {

// One run the design wants. (batch, slot) names it: batch 0 is the space-filling start,
// slot its position in the batch. A replicate repeats an earlier point's theta exactly, with
// its own seed, so that the DEM's scatter is measured there.
struct RunRequest {
  std::size_t batch = 0;
  std::size_t slot = 0;
  std::vector<double> theta;  // parameter units, in the problem's parameter order
  int replicate = 0;          // 0 for the first run at this theta, 1 for the second, ...
  std::uint64_t seed = 0;     // for the simulator's random numbers; fixed by the design's seed
  // Why the design chose it, e.g. "space-filling start" or "posterior-weighted variance".
  std::string reason;
  // The acquisition value when chosen (see weighted_variance_acquisition.hpp); NaN for the
  // start and for replicates.
  double acquisition = 0.0;
};

// A finished run: the request and one value per recording (the design problem's
// recordings, in order), in the recordings' units; NaN where the run failed or did not
// measure it (such values are left out of the fits).
struct RunResult {
  RunRequest request;
  std::vector<double> observables;
};

// Runs a batch (all its runs may run at once) and returns one observables vector per
// request, in the requests' order.
using RunEvaluator =
    std::function<std::vector<std::vector<double>>(const std::vector<RunRequest>& batch)>;

// The seed of run (batch, slot) of a design seeded with `design_seed`: a SplitMix64 hash, so
// that neighbouring runs get unrelated streams and a run's seed does not depend on how many
// runs came before it.
std::uint64_t run_seed(std::uint64_t design_seed, std::size_t batch, std::size_t slot);

}  // namespace demcal::calibrate
