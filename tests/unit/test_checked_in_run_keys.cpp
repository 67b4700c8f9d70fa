// The run keys of the checked-in studies, pinned (issue 14: "nothing changes for users").
// A run key is the content hash of a run's resolved inputs (study/run_store.hpp); a refactor
// of the readers, the registries or the resolved config that changes one orphans every run
// of every existing store and makes the checked-in tables disagree with a rerun. Each study's
// whole plan is pinned: the number of distinct runs, the first run's key and the SHA-256 of
// all keys in plan order. An adaptive study's plan is its start batch (the runs it asks for
// before any has returned: a function of its [design] keys and seed alone).
//
// When a change is meant to change results (a new engine behaviour, a key_version bump),
// rerun with DEMCAL_PRINT_RUN_KEYS=1 and replace the table below, saying why in the commit.
#include "calibrate/adaptive_design.hpp"
#include "config/canonical_json.hpp"
#include "study/adaptive_campaign.hpp"
#include "study/doe_plan.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace demcal::study {
namespace {

struct PinnedPlan {
  const char* study;  // relative to the source tree
  std::size_t runs;
  const char* first_hash;
  const char* all_keys_sha256;
};

const PinnedPlan kPinned[] = {
#include "checked_in_run_keys.inc"
};

TEST(CheckedInRunKeys, EveryPlannedRunKeepsItsKey) {
  const bool print = std::getenv("DEMCAL_PRINT_RUN_KEYS") != nullptr;
  for (const PinnedPlan& p : kPinned) {
    SCOPED_TRACE(p.study);
    const std::filesystem::path file = std::filesystem::path(DEMCAL_SOURCE_DIR) / p.study;
    DoePlan plan = plan_doe(file, {}, {}, 1);
    if (plan.design.adaptive) {
      const AdaptiveStudyDesign d = adaptive_study_design(plan);
      calibrate::AdaptiveDesign design(d.problem, d.options);
      plan_adaptive_runs(plan, design.next_runs({}));
    }
    std::string all;
    for (const PlannedRun& r : plan.runs) all += r.key.digest + "\n";
    const std::string sha = config::sha256_hex(all);
    const std::string first = plan.runs.empty() ? "" : plan.runs.front().key.hash;
    if (print)
      std::printf("    {\"%s\", %zu, \"%s\", \"%s\"},\n", p.study, plan.runs.size(), first.c_str(),
                  sha.c_str());
    EXPECT_EQ(plan.runs.size(), p.runs);
    EXPECT_EQ(first, p.first_hash);
    EXPECT_EQ(sha, p.all_keys_sha256);
  }
}

}  // namespace
}  // namespace demcal::study
