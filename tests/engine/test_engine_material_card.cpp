// The LAMMPS and LIGGGHTS material cards run in their engines (issue 17: "a
// pile made with the card gives the calibrated AoR within the DEM's scatter").
// From the checked-in calibrated study tests/data/engines/card-pile/ the card is
// exported as `demcal export --to lammps|liggghts` writes it; the pile deck demcal writes for the
// study at the calibrated values (the path its calibration ran on) is run
// as it is, and again with every contact parameter taken out of it and the card
// `include`d instead: the second script carries only geometry, insertion and
// run control, so the card alone must say every contact parameter LAMMPS needs.
// Both piles are measured by demcal's own AoR code, over a few seeds.
// Labelled `engine`; each skipped, with the reason, when its engine (lmp,
// liggghts) is absent. About 2 min each on one core.
#include "config/study_config.hpp"
#include "engines/engine_measure.hpp"
#include "engines/engine_run.hpp"
#include "study/engine_evaluator.hpp"
#include "study/material_export.hpp"
#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace demcal::engines {
namespace {

namespace fs = std::filesystem;

const fs::path kStudyDir = fs::path(DEMCAL_SOURCE_DIR) / "tests/data/engines/card-pile";

// The launch line: the environment variable overrides (e.g. "mpirun -np 2 lmp").
std::string engine_command(const char* variable, const char* fallback) {
  const char* v = std::getenv(variable);
  return v != nullptr && *v != '\0' ? std::string(v) : std::string(fallback);
}

std::string first_word(const std::string& s) { return s.substr(0, s.find(' ')); }

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> w;
  for (std::string s; in >> s;) w.push_back(s);
  return w;
}

// demcal's deck with its contact law replaced by the card: the pair_style and
// pair_coeff lines by `include <card>`, each wall fix's model arguments by the
// card's ${demcal_wall}, the grains' density by ${demcal_density}. Every
// replacement must happen, and no contact parameter of the deck may remain.
std::string script_with_card(const std::string& deck, const std::string& card_name) {
  const std::set<std::string> wall_styles = {"xplane", "yplane", "zplane", "zcylinder", "region"};
  std::istringstream in(deck);
  std::ostringstream out;
  int pair_lines = 0, walls = 0, densities = 0;
  for (std::string line; std::getline(in, line);) {
    const std::vector<std::string> w = words(line);
    if (w.empty() || w[0][0] == '#') {
      out << line << "\n";
      continue;
    }
    if (w[0] == "pair_style" || w[0] == "pair_coeff") {
      if (pair_lines++ == 0) out << "include         " << card_name << "\n";
      continue;
    }
    std::vector<std::string> kept;
    for (std::size_t i = 0; i < w.size(); ++i) {
      kept.push_back(w[i]);
      if (w[0] == "fix" && w[i] == "granular" && i >= 3 && w[3].rfind("wall/gran", 0) == 0) {
        std::size_t j = i + 1;
        while (j < w.size() && wall_styles.count(w[j]) == 0) ++j;
        EXPECT_LT(j, w.size()) << "no wall style in: " << line;
        kept.push_back("${demcal_wall}");
        i = j - 1;
        ++walls;
      } else if (w[0] == "fix" && w[i] == "dens" && i + 2 < w.size()) {
        kept.push_back("${demcal_density}");
        kept.push_back("${demcal_density}");
        i += 2;
        ++densities;
      }
    }
    std::string joined;
    for (const std::string& k : kept) joined += (joined.empty() ? "" : " ") + k;
    out << joined << "\n";
  }
  EXPECT_EQ(pair_lines, 2) << "the deck's contact law is not where the test expects it";
  EXPECT_GT(walls, 0) << "no wall/gran fix in the deck";
  EXPECT_EQ(densities, 1) << "no density in the deck's insertion";
  const std::string s = out.str();
  for (const char* term : {" hertz ", " mindlin ", " sds ", " tsuji "}) {
    std::istringstream lines(s);
    for (std::string line; std::getline(lines, line);) {
      if (!line.empty() && line[0] != '#') {
        EXPECT_EQ(line.find(term), std::string::npos) << "contact term left in: " << line;
      }
    }
  }
  return s;
}

// The same for LIGGGHTS: the material fixes (fix mN all property/global ...),
// hard_particles, pair_style and pair_coeff give way to `include <card>`. The
// wall fixes keep their model keywords (the card's comment states them: they
// choose the model, they hold no parameter), the particle template its
// density (the card states it in a comment: LIGGGHTS takes it there).
std::string liggghts_script_with_card(const std::string& deck, const std::string& card_name) {
  std::istringstream in(deck);
  std::ostringstream out;
  int removed = 0;
  bool included = false;
  for (std::string line; std::getline(in, line);) {
    const std::vector<std::string> w = words(line);
    const bool material =
        !w.empty() && (w[0] == "hard_particles" || w[0] == "pair_style" || w[0] == "pair_coeff" ||
                       (w[0] == "fix" && w.size() > 3 && w[3] == "property/global"));
    if (!material) {
      out << line << "\n";
      continue;
    }
    ++removed;
    if (!included) out << "include         " << card_name << "\n";
    included = true;
  }
  EXPECT_GE(removed, 8) << "the deck's material is not where the test expects it";
  const std::string s = out.str();
  for (const char* term : {"youngsModulus", "coefficientFriction", "coefficientRollingFriction",
                           "coefficientRestitution", "poissonsRatio"})
    EXPECT_EQ(s.find(term), std::string::npos) << term << " left in the script";
  return s;
}

double angle(const Deck& deck, const fs::path& dir) {
  const dem::ApparatusResult r = measure_engine_run(deck, dir);
  EXPECT_FALSE(r.observables["angle_of_repose_deg"].is_null()) << r.details.dump(2);
  return r.observables["angle_of_repose_deg"].is_null()
             ? std::nan("")
             : r.observables["angle_of_repose_deg"].get<double>();
}

double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

double variance(const std::vector<double>& v) {
  const double m = mean(v);
  double s = 0.0;
  for (double x : v) s += (x - m) * (x - m);
  return s / static_cast<double>(v.size() - 1);
}

struct CardCase {
  std::string engine;  // "lammps" | "liggghts"
  std::string command;
  std::vector<std::string> overrides;  // the study's [engine] for this engine
};

// Criterion, fixed before measuring: with the seeds' AoR a_i (deck) and b_i
// (card), |mean(b) - mean(a)| <= 2 sqrt(var(a)/n + var(b)/n) + 1 deg (the
// floor: demcal's AoR of a ~2000-parcel heap is read to about a degree).
void card_against_deck(const CardCase& c) {
  const fs::path work = testing::fresh_dir("engine", "material-card-" + c.engine);

  // The card, as `demcal export tests/data/engines/card-pile/study.toml --to <engine>
  // --output tests/data/engines/card-pile/calibrated` writes it.
  study::MaterialExportOptions o;
  o.study = kStudyDir / "study.toml";
  o.overrides = c.overrides;
  o.output_dir = kStudyDir / "calibrated";
  o.to = c.engine;
  o.card = work / ("card." + c.engine);
  const study::MaterialExportOutcome exported = study::export_material_card(o);
  ASSERT_EQ(exported.input.calibrated.size(), 2u);
  const double mu_r = exported.input.calibrated[0].value;
  const double mu_s = exported.input.calibrated[1].value;
  const std::string card_name = o.card->filename().string();

  const std::vector<std::uint64_t> seeds = {1, 2, 3};
  std::vector<double> deck_aor, card_aor;
  double wall_s = 0.0;
  for (const std::uint64_t seed : seeds) {
    std::vector<std::string> overrides = c.overrides;
    overrides.push_back("mu_r=" + std::to_string(mu_r));
    overrides.push_back("mu_s=" + std::to_string(mu_s));
    overrides.push_back("study.seed=" + std::to_string(seed));
    const config::StudyConfig s = config::load_study_config(o.study, overrides);
    const Deck deck = study::engine_deck(s, s.apparatus.front());
    EngineLaunch launch;
    launch.command = c.command;
    launch.timeout_s = 600.0;  // a stuck run fails the test rather than the CI job

    const fs::path deck_dir = work / ("deck-" + std::to_string(seed));
    wall_s += run_engine(deck, launch, deck_dir).wall_time_s;
    deck_aor.push_back(angle(deck, deck_dir));

    Deck with_card = deck;
    with_card.script = c.engine == "lammps" ? script_with_card(deck.script, card_name)
                                            : liggghts_script_with_card(deck.script, card_name);
    with_card.files.emplace_back(card_name, testing::slurp(*o.card));
    const fs::path card_dir = work / ("card-" + std::to_string(seed));
    wall_s += run_engine(with_card, launch, card_dir).wall_time_s;
    card_aor.push_back(angle(with_card, card_dir));
    std::cout << c.engine << " seed " << seed << ": AoR deck " << deck_aor.back() << " deg, card "
              << card_aor.back() << " deg\n";
  }
  const double n = static_cast<double>(seeds.size());
  const double difference = mean(card_aor) - mean(deck_aor);
  const double se = std::sqrt(variance(deck_aor) / n + variance(card_aor) / n);
  std::cout << c.engine << " card vs deck at mu_r " << mu_r << ", mu_s " << mu_s << ": AoR "
            << mean(card_aor) << " vs " << mean(deck_aor) << " deg (sd of the deck's "
            << std::sqrt(variance(deck_aor)) << " deg), difference " << difference
            << " deg, its standard error " << se << " deg; " << 2 * seeds.size() << " runs, "
            << wall_s << " s of engine wall time\n";
  EXPECT_LE(std::abs(difference), 2.0 * se + 1.0);
  if (!::testing::Test::HasFailure()) fs::remove_all(work);
}

TEST(EngineMaterialCard, LammpsCardGivesTheDeckAngleOfReposeWithinTheScatter) {
  const std::string command = engine_command("DEMCAL_LAMMPS", "lmp");
  if (!executable_available(first_word(command)))
    GTEST_SKIP() << "LAMMPS not installed: \"" << first_word(command)
                 << "\" is not on PATH (apt-get install lammps, or set DEMCAL_LAMMPS)";
  card_against_deck({"lammps", command, {}});
}

TEST(EngineMaterialCard, LiggghtsCardGivesTheDeckAngleOfReposeWithinTheScatter) {
  const std::string command = engine_command("DEMCAL_LIGGGHTS", "liggghts");
  if (!executable_available(first_word(command)))
    GTEST_SKIP() << "LIGGGHTS not installed: \"" << first_word(command)
                 << "\" is not on PATH (apt-get install liggghts, or set DEMCAL_LIGGGHTS)";
  card_against_deck({"liggghts", command, {"engine.kind=liggghts", "engine.launch=" + command}});
}

}  // namespace
}  // namespace demcal::engines
