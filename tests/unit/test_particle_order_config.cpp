// [protocol] particle_order: absent means "spatial" (the default since run keys of
// version 2, issue 13), and so does "spatial" given (not written in: the same key);
// "insertion" reaches the engine's options and gives the runs a key of their own; an
// unknown name is refused by key.
#include "config/simulation_config.hpp"
#include "config/study_config.hpp"
#include "study/run_store.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace demcal::study {
namespace {

const std::string kQuick = std::string(DEMCAL_SOURCE_DIR) + "/studies/sandglass-quick/study.toml";

TEST(ParticleOrderConfig, DefaultIsSpatialNotWrittenInAndInsertionGetsItsOwnKey) {
  const config::StudyConfig base = config::load_study_config(kQuick, {});
  ASSERT_FALSE(base.apparatus.empty());
  const std::string app = base.apparatus.front().name;
  EXPECT_EQ(base.protocol.particle_order, dem::ParticleOrder::kSpatial);
  EXPECT_FALSE(base.resolved.at_path("protocol.particle_order"));
  const std::string key0 = run_key_for(base, app, 1, 1).digest;

  const config::StudyConfig spatial =
      config::load_study_config(kQuick, {"protocol.particle_order=\"spatial\""});
  EXPECT_EQ(spatial.protocol.particle_order, dem::ParticleOrder::kSpatial);
  EXPECT_EQ(run_key_for(spatial, app, 1, 1).digest, key0) << "the default must not change keys";
  EXPECT_FALSE(spatial.resolved.at_path("protocol.particle_order"));

  const config::StudyConfig insertion =
      config::load_study_config(kQuick, {"protocol.particle_order=insertion"});
  EXPECT_EQ(insertion.protocol.particle_order, dem::ParticleOrder::kInsertion);
  EXPECT_NE(run_key_for(insertion, app, 1, 1).digest, key0);
  EXPECT_EQ(insertion.resolved.at_path("protocol.particle_order").value<std::string>(),
            std::string("insertion"));
}

TEST(ParticleOrderConfig, UnknownNameIsRefusedByKey) {
  try {
    config::load_study_config(kQuick, {"protocol.particle_order=morton"});
    FAIL() << "accepted particle_order = morton";
  } catch (const config::ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("protocol.particle_order"), std::string::npos) << what;
    EXPECT_NE(what.find("\"spatial\""), std::string::npos) << what;
  }
}

// The plain simulation config's [simulation] particle_order, the same way.
TEST(ParticleOrderConfig, SimulationConfigKey) {
  const std::string pile = std::string(DEMCAL_SOURCE_DIR) + "/studies/poured-pile/study.toml";
  const config::SimulationConfig base = config::load_simulation_config(pile, {});
  EXPECT_EQ(base.simulation->options().particle_order, dem::ParticleOrder::kSpatial);
  EXPECT_FALSE(base.resolved.at_path("simulation.particle_order"));
  const config::SimulationConfig spatial =
      config::load_simulation_config(pile, {"simulation.particle_order=\"spatial\""});
  EXPECT_EQ(spatial.simulation->options().particle_order, dem::ParticleOrder::kSpatial);
  EXPECT_FALSE(spatial.resolved.at_path("simulation.particle_order"));
  const config::SimulationConfig insertion =
      config::load_simulation_config(pile, {"simulation.particle_order=insertion"});
  EXPECT_EQ(insertion.simulation->options().particle_order, dem::ParticleOrder::kInsertion);
  EXPECT_TRUE(insertion.resolved.at_path("simulation.particle_order"));
  EXPECT_THROW(config::load_simulation_config(pile, {"simulation.particle_order=bogus"}),
               config::ConfigError);
}

}  // namespace
}  // namespace demcal::study
