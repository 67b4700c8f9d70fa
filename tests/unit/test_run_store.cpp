// The run store: SHA-256 and the canonical key text, run keys that depend on
// what determines a run and on nothing else (not key order, not 1 vs 1.0, not
// the study's name or output), and files that are whole or absent.
#include "study/run_store.hpp"
#include "config/study_config.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace demcal::cli {
namespace {

using namespace demcal::config;
using namespace demcal::study;

namespace fs = std::filesystem;

TEST(RunStoreHash, Sha256MatchesKnownDigests) {
  // Lengths around the padding boundaries (55, 56, 64) and several blocks.
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(std::string(55, 'a')),
            "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318");
  EXPECT_EQ(sha256_hex(std::string(56, 'a')),
            "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a");
  EXPECT_EQ(sha256_hex(std::string(64, 'a')),
            "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb");
  EXPECT_EQ(sha256_hex(std::string(1000, 'a')),
            "41edece42d63e8d9bf515a9ba6932e1c20cbc9f5a5d134645adb5db1b9737ea3");
}

TEST(RunStoreHash, CanonicalTextIgnoresKeyOrderAndIntegralFloats) {
  // Built in a different order, 1.0 for 1: the same canonical text, whose
  // SHA-256 is pinned here (Python: json.dumps(k, sort_keys=True,
  // separators=(',', ':'))). A change to it would orphan every existing store.
  nlohmann::json a;
  a["threads"] = 1;
  a["seed"] = 3;
  a["key_version"] = 1.0;
  a["inputs"]["b"] = nlohmann::json::array({1.0, 2.5, {{"z", true}, {"a", nullptr}}});
  a["inputs"]["a"] = "x";
  a["apparatus"] = "sandglass";
  const std::string text = canonical_json(a);
  EXPECT_EQ(text,
            R"({"apparatus":"sandglass","inputs":{"a":"x","b":[1,2.5,{"a":null,"z":true}]},)"
            R"("key_version":1,"seed":3,"threads":1})");
  const RunKey k = make_run_key(a);
  EXPECT_EQ(k.digest, "fe7dd89f3a3d4f9947542d062a0d67a18de3c043ce47c55f6d5338498222dd36");
  EXPECT_EQ(k.hash, "fe7dd89f3a3d4f99");
  nlohmann::json b = nlohmann::json::parse(text);
  EXPECT_EQ(make_run_key(b).digest, k.digest);
}

// A small study; `variant` writes the same study differently (tables and keys
// in another order, 1 for 1.0, another name and output) or changes it.
std::string study_text(int variant) {
  const std::string material = R"(
[material]
name = "sand"
density_kg_m3 = 2650.0
shear_modulus_pa = 3.0e10
poisson_ratio = 0.25
size = { distribution = "uniform", min_diameter_m = 3.0e-4, max_diameter_m = 6.0e-4 }
[wall_material]
name = "glass"
density_kg_m3 = 2500.0
youngs_modulus_pa = 6.3e10
poisson_ratio = 0.23
[contact]
normal = "hertz"
tangential = "mindlin"
rolling = "cdt"
)";
  const std::string interaction_a = R"(
[interaction.particle_particle]
restitution = 0.6
sliding_friction = 0.52
rolling_friction = 0.3
[interaction.particle_wall]
restitution = 0.6
sliding_friction = 0.5
rolling_friction = 0.3
)";
  const std::string interaction_b = R"(
[interaction.particle_wall]
rolling_friction = 0.3
sliding_friction = 0.5
restitution = 0.6
[interaction.particle_particle]
rolling_friction = 0.3
restitution = 0.6
sliding_friction = 0.52
)";
  const std::string container_a = R"(
[protocol]
max_flow_s = 1.0
[apparatus.rectangular_container]
width_m = 0.16
height_m = 0.06
thickness_diameters = 4.0
boundary = "periodic"
fill_mass_kg = 0.05
coarse_graining_factor = 10.0
shear_modulus_pa = 1.0e6
)";
  const std::string container_b = R"(
[apparatus.rectangular_container]
shear_modulus_pa = 1e6
coarse_graining_factor = 10
fill_mass_kg = 0.05
boundary = "periodic"
thickness_diameters = 4
height_m = 0.06
width_m = 0.16
[protocol]
max_flow_s = 1
)";
  switch (variant) {
    case 0:
      return "[study]\nname = \"a\"\nseed = 1\n" + material + interaction_a + container_a;
    case 1:  // the same run, written differently, another name and output
      return container_b + interaction_b + material +
             "[study]\nname = \"b\"\n[output]\ndirectory = \"elsewhere\"\nvtk = true\n";
    default:
      return "";
  }
}

RunKey key_of(const std::string& text, std::uint64_t seed, int threads,
              const std::vector<std::string>& overrides = {}) {
  ConfigDocument doc = parse_config_string(text, "study.toml");
  for (const auto& o : overrides) apply_override(doc, o, study_override_aliases());
  const StudyConfig study = build_study(std::move(doc));
  return run_key_for(study, "rectangular_container", seed, threads);
}

TEST(RunStoreHash, RunKeyDependsOnWhatDeterminesTheRunOnly) {
  const RunKey a = key_of(study_text(0), 1, 1);
  EXPECT_EQ(a.hash.size(), 16u);
  EXPECT_EQ(a.digest.substr(0, 16), a.hash);
  EXPECT_EQ(key_of(study_text(0), 1, 1).digest, a.digest) << "stable across builds";
  EXPECT_EQ(key_of(study_text(1), 1, 1).digest, a.digest)
      << "key order, 1 vs 1.0, study name and [output] do not matter";
  // A value set to what it already is: the same run.
  EXPECT_EQ(key_of(study_text(0), 1, 1, {"mu_r=0.3"}).digest, a.digest);
  // What determines the run does.
  EXPECT_NE(key_of(study_text(0), 1, 1, {"mu_r=0.31"}).digest, a.digest);
  EXPECT_NE(key_of(study_text(0), 1, 1, {"mu_s=0.5"}).digest, a.digest);
  EXPECT_NE(key_of(study_text(0), 1, 1, {"apparatus.rectangular_container.fill_mass_kg=0.04"}).digest,
            a.digest);
  EXPECT_NE(key_of(study_text(0), 1, 1, {"protocol.max_settle_s=1.5"}).digest, a.digest)
      << "a default written in counts like any value";
  EXPECT_NE(key_of(study_text(0), 2, 1).digest, a.digest) << "seed";
  EXPECT_NE(key_of(study_text(0), 1, 2).digest, a.digest) << "threads";
  // The key holds the inputs of this apparatus, without [study], [output], [design].
  EXPECT_FALSE(a.key["inputs"].contains("study"));
  EXPECT_FALSE(a.key["inputs"].contains("output"));
  EXPECT_EQ(a.key["seed"], 1);
  EXPECT_EQ(a.key["apparatus"], "rectangular_container");
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("demcal-run-store-" + name + "-" +
                                                   std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

nlohmann::json record_for(const RunKey& k, const std::string& status) {
  return {{"design", {{"hash", k.hash}, {"digest", k.digest}, {"status", status}}},
          {"observables", {{"angle_of_repose_deg", 31.5}}}};
}

void write_raw(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

TEST(RunStoreFiles, StoredRecordsLoadAndNothingElseDoes) {
  const fs::path dir = fresh_dir("load");
  const RunStore store(dir / "runs");
  const RunKey k = make_run_key({{"x", 1}});
  EXPECT_FALSE(store.load(k.hash, k.digest)) << "nothing stored yet";
  store.store(k.hash, record_for(k, "ok"));
  const auto loaded = store.load(k.hash, k.digest);
  ASSERT_TRUE(loaded);
  EXPECT_EQ((*loaded)["observables"]["angle_of_repose_deg"], 31.5);
  // Only the file itself is in the directory: the temporary was renamed.
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir / "runs")) {
    ++files;
    EXPECT_EQ(e.path().filename().string(), k.hash + ".json");
  }
  EXPECT_EQ(files, 1u);

  // A file that is not a whole record of this key is not a result.
  std::string problem;
  const RunKey other = make_run_key({{"x", 2}});
  write_raw(store.file_for(other.hash), record_for(other, "ok").dump().substr(0, 30));
  EXPECT_FALSE(store.load(other.hash, other.digest, &problem));
  EXPECT_NE(problem.find("not a JSON object"), std::string::npos) << problem;
  write_raw(store.file_for(other.hash), record_for(k, "ok").dump());
  EXPECT_FALSE(store.load(other.hash, other.digest, &problem)) << "another key's digest";
  write_raw(store.file_for(other.hash), record_for(other, "running").dump());
  EXPECT_FALSE(store.load(other.hash, other.digest, &problem)) << "unknown status";
  store.store(other.hash, record_for(other, "failed"));
  EXPECT_TRUE(store.load(other.hash, other.digest));
  fs::remove_all(dir);
}

TEST(RunStoreFiles, AnInterruptedWriteLeavesNoResultAndItsTemporaryIsCleanedUp) {
  const fs::path dir = fresh_dir("interrupted");
  const RunStore store(dir);
  const RunKey k = make_run_key({{"x", 3}});
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  // A writer killed between writing and renaming: half a record under the
  // temporary name, with a pid that no longer runs (a child that has exited).
  const pid_t dead = fork();
  if (dead == 0) _exit(0);
  ASSERT_GT(dead, 0);
  int status = 0;
  waitpid(dead, &status, 0);
  const std::string half = record_for(k, "ok").dump(2).substr(0, 40);
  const fs::path stale =
      dir / ("." + k.hash + ".json." + host + "." + std::to_string(dead) + ".0.tmp");
  const fs::path live =
      dir / ("." + k.hash + ".json." + host + "." + std::to_string(getpid()) + ".7.tmp");
  const fs::path remote = dir / ("." + k.hash + ".json.some-other-host.1.0.tmp");
  for (const fs::path& p : {stale, live, remote}) write_raw(p, half);

  EXPECT_FALSE(store.load(k.hash, k.digest)) << "a temporary is never read as a result";
  EXPECT_EQ(remove_stale_temporaries(dir), 1u);
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live)) << "its writer (this process) may still rename it";
  EXPECT_TRUE(fs::exists(remote)) << "another host's writer may be alive";
  store.store(k.hash, record_for(k, "ok"));
  EXPECT_TRUE(store.load(k.hash, k.digest));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace demcal::cli
