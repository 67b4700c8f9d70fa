// Fitting surrogates to replicated designs (surrogate/surrogate_fit.hpp), the
// [surrogate] table, reading doe.csv and recordings, and `demcal fit` /
// `demcal inspect` end to end on a synthetic design table.

#include "config/doe_csv.hpp"
#include "cli/fit_command.hpp"
#include "config/recordings_csv.hpp"
#include "config/study_config.hpp"
#include "config/toml_reader.hpp"
#include "surrogate/surrogate_fit.hpp"
#include "surrogate/surrogate_io.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>

namespace demcal {
namespace {

namespace fs = std::filesystem;

// AoR-like smooth truth over (mu_r, mu_s) in [0.05, 0.6] x [0.2, 0.9].
double truth(double mu_r, double mu_s) { return 20.0 + 18.0 * mu_r + 12.0 * mu_s - 6.0 * mu_r * mu_r + 4.0 * mu_r * mu_s; }

surrogate::ReplicatedData grid_data(double noise_sd, int replicates, std::uint64_t seed) {
  surrogate::ReplicatedData d;
  d.input_names = {"mu_r", "mu_s"};
  d.lower = {0.05, 0.2};
  d.upper = {0.6, 0.9};
  d.output_name = "angle_of_repose_deg";
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_sd);
  std::vector<std::array<double, 3>> rows;
  int point = 0;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j, ++point)
      for (int r = 0; r < replicates; ++r) {
        const double a = 0.05 + 0.55 * i / 4.0, b = 0.2 + 0.7 * j / 4.0;
        rows.push_back({a, b, truth(a, b) + noise(rng)});
        d.group.push_back(point);
      }
  d.x.resize(static_cast<Eigen::Index>(rows.size()), 2);
  d.y.resize(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t k = 0; k < rows.size(); ++k) {
    d.x(static_cast<Eigen::Index>(k), 0) = rows[k][0];
    d.x(static_cast<Eigen::Index>(k), 1) = rows[k][1];
    d.y(static_cast<Eigen::Index>(k)) = rows[k][2];
  }
  return d;
}

TEST(SurrogateFit, PooledReplicateScatterMatchesTheNoise) {
  // 25 points x 4 replicates: 75 degrees of freedom, so the pooled sd is within ~25 % of 0.8.
  const auto d = grid_data(0.8, 4, 3);
  const auto s = surrogate::replicate_scatter(d);
  EXPECT_EQ(s.points, 25);
  EXPECT_EQ(s.degrees_of_freedom, 75);
  EXPECT_NEAR(s.sd, 0.8, 0.2);
  EXPECT_DOUBLE_EQ(s.mean_replicates, 4.0);
}

TEST(SurrogateFit, GaussianProcessWithReplicateNuggetPredictsTheTruthAndPassesTheScatterCheck) {
  const auto d = grid_data(0.5, 2, 7);
  surrogate::SurrogateSpec spec;  // GP, Matern 5/2, constant mean, nugget from replicates
  const auto f = surrogate::fit_surrogate(d, spec);
  EXPECT_EQ(f.runs, 50u);
  EXPECT_EQ(f.loo.observed.size(), 25);  // fitted to the point means
  Eigen::MatrixXd pts(3, 2);
  pts << 0.2, 0.4, 0.45, 0.75, 0.33, 0.55;
  const auto p = f.model->predict(pts);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(p.mean(i), truth(pts(i, 0), pts(i, 1)), 0.6) << i;
  EXPECT_TRUE(f.scatter_check.within_scatter) << f.scatter_check.message;
  EXPECT_GT(f.validation.q_squared, 0.95);
}

TEST(SurrogateFit, PolynomialDegreeByCrossValidationFindsTheQuadratic) {
  const auto d = grid_data(0.05, 2, 11);
  surrogate::SurrogateSpec spec;
  spec.model = "polynomial";
  const auto f = surrogate::fit_surrogate(d, spec);
  ASSERT_FALSE(f.degrees_tried.empty());
  EXPECT_EQ(dynamic_cast<const surrogate::PolynomialSurface&>(*f.model).degree(), 2);
}

TEST(SurrogateFit, SavedFitRoundTripsWithItsValidation) {
  const auto d = grid_data(0.5, 2, 5);
  const auto f = surrogate::fit_surrogate(d, surrogate::SurrogateSpec{});
  const auto g = surrogate::fitted_surrogate_from_json(nlohmann::json::parse(f.to_json().dump()));
  Eigen::MatrixXd pts(2, 2);
  pts << 0.1, 0.3, 0.5, 0.8;
  EXPECT_NEAR((f.model->predict_mean(pts) - g.model->predict_mean(pts)).cwiseAbs().maxCoeff(), 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(f.scatter.sd, g.scatter.sd);
  EXPECT_NEAR(f.validation.rmse, g.validation.rmse, 1e-12);
  EXPECT_EQ(f.spec.nugget, g.spec.nugget);
}

TEST(SurrogateFit, RefusesWhatCannotBeFittedNamingTheOutput) {
  auto d = grid_data(0.5, 1, 5);
  try {
    surrogate::fit_surrogate(d, surrogate::SurrogateSpec{});  // nugget from replicates, none given
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("angle_of_repose_deg: nugget = \"replicates\" needs replicates"),
              std::string::npos)
        << e.what();
  }
  auto bad = grid_data(0.5, 2, 5);
  bad.x(1, 0) += 0.01;  // a replicate at other inputs
  EXPECT_THROW(surrogate::fit_surrogate(bad, surrogate::SurrogateSpec{}), std::invalid_argument);
  surrogate::SurrogateSpec wrong;
  wrong.model = "spline";
  EXPECT_THROW(surrogate::fit_surrogate(grid_data(0.5, 2, 5), wrong), std::invalid_argument);
}

// ---------------------------------------------------------------- files

struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name)
      : path(fs::temp_directory_path() / ("demcal_fit_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

void write(const fs::path& p, const std::string& text) {
  std::ofstream f(p);
  f << text;
}

std::string study_text(const std::string& surrogate_table) {
  std::ifstream in(fs::path(DEMCAL_SOURCE_DIR) / "tests/data/doe-tiny/study.toml");
  std::stringstream s;
  s << in.rdbuf();
  std::string t = s.str();
  const auto at = t.find("[design]");
  return t.substr(0, at) +
         "[design]\nkind = \"full_factorial\"\nreplicates = 2\nparameters = { mu_r = { lower = 0.05, upper = 0.6, "
         "levels = 5 }, mu_s = { lower = 0.2, upper = 0.9, levels = 5 } }\n\n" +
         surrogate_table;
}

// A doe.csv as `demcal doe` writes it, with the AoR from `truth` plus noise.
void write_doe_csv(const fs::path& p) {
  std::ofstream f(p);
  f << "point,replicate,seed,apparatus,mu_r,mu_s,angle_of_repose_deg,discharge_time_s,mass_flow_rate_kg_s,"
       "bulk_density_kg_m3,status,hash\n";
  std::mt19937_64 rng(1);
  std::normal_distribution<double> noise(0.0, 0.5);
  int point = 0;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j, ++point)
      for (int r = 0; r < 2; ++r) {
        const double a = 0.05 + 0.55 * i / 4.0, b = 0.2 + 0.7 * j / 4.0;
        f << point << "," << r << "," << 1 + r << ",rectangular_container," << a << "," << b << ","
          << truth(a, b) + noise(rng) << ",,,,ok," << std::hex << 1000 + point * 2 + r << std::dec << "\n";
      }
}

// The fit of dir/study.toml to a freshly written dir/doe.csv, into dir/out.
cli::FitOptions fit_options_with_table(const fs::path& dir) {
  write_doe_csv(dir / "doe.csv");
  cli::FitOptions o;
  o.study = dir / "study.toml";
  o.output_dir = dir / "out";
  o.doe_csv = dir / "doe.csv";
  return o;
}

TEST(FitCommand, FitsSavesAndInspectsFromADesignTable) {
  TempDir dir("cmd");
  write(dir.path / "study.toml", study_text("[surrogate]\nmodel = \"gaussian_process\"\nmean = \"linear\"\n"));
  const cli::FitOptions o = fit_options_with_table(dir.path);
  std::ostringstream out, log;
  const auto r = cli::fit(o, out, log);
  ASSERT_EQ(r.files.size(), 1u);
  EXPECT_EQ(r.files[0].filename(), "rectangular_container.angle_of_repose_deg.json");
  std::ifstream in(r.files[0]);
  const auto f = surrogate::fitted_surrogate_from_json(nlohmann::json::parse(in));
  Eigen::MatrixXd pt(1, 2);
  pt << 0.3, 0.5;
  EXPECT_NEAR(f.model->predict_mean(pt)(0), truth(0.3, 0.5), 0.6);
  const fs::path html = cli::inspect(o, out, log);
  ASSERT_TRUE(fs::exists(html));
  std::ifstream h(html);
  std::stringstream hs;
  hs << h.rdbuf();
  EXPECT_NE(hs.str().find("<svg"), std::string::npos);
  EXPECT_NE(hs.str().find("Sobol"), std::string::npos);
  EXPECT_TRUE(fs::exists(html.parent_path() / "inspection.json"));
  EXPECT_TRUE(fs::exists(html.parent_path() / "rectangular_container_angle_of_repose_deg_parity.csv"));
}

TEST(FitCommand, AListedObservableIsFittedWhereMeasuredAndRefusedWhereNoRunMeasuredIt) {
  // Several setups: a container measures no discharge time; listing the time
  // must not stop the fit of the container's AoR, but a name no run measured is refused.
  TempDir dir("listed");
  write(dir.path / "study.toml",
        study_text("[surrogate]\nmodel = \"polynomial\"\ndegree = 2\n"
                   "observables = [\"angle_of_repose_deg\", \"discharge_time_s\"]\n"));
  const cli::FitOptions o = fit_options_with_table(dir.path);
  std::ostringstream out, log;
  // doe.csv has only the container's AoR: the time is listed but measured by no run.
  try {
    cli::fit(o, out, log);
    FAIL() << "a listed observable that no run measured was accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("observables lists discharge_time_s, but no run in"), std::string::npos)
        << e.what();
  }
  // With a sandglass row that measured it, the container's AoR and the sandglass's time are fitted.
  {
    std::ofstream f(dir.path / "doe.csv", std::ios::app);
    for (int k = 0; k < 10; ++k)
      f << 100 + k << ",0,1,sandglass," << 0.05 + 0.05 * k << "," << 0.2 + 0.07 * ((3 * k) % 10) << ",,"
        << 0.4 + 0.02 * k + 0.001 * k * k << ",,,ok," << std::hex << 5000 + k << std::dec << "\n";
  }
  const auto r = cli::fit(o, out, log);
  std::set<std::string> names;
  for (const auto& file : r.files) names.insert(file.filename().string());
  EXPECT_EQ(names, (std::set<std::string>{"rectangular_container.angle_of_repose_deg.json",
                                          "sandglass.discharge_time_s.json"}));
}

TEST(FitCommand, SurrogateTableIsStrict) {
  TempDir dir("strict");
  write(dir.path / "a.toml", study_text("[surrogate]\nmodel = \"polynomial\"\nkernel = \"matern52\"\n"));
  try {
    config::load_study_config(dir.path / "a.toml", {});
    FAIL();
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("surrogate.kernel: applies only to model = \"gaussian_process\""),
              std::string::npos)
        << e.what();
  }
  write(dir.path / "b.toml", study_text("[surrogate]\nobservables = [\"angle_of_repose\"]\n"));
  EXPECT_THROW(config::load_study_config(dir.path / "b.toml", {}), config::ConfigError);
  write(dir.path / "c.toml", study_text("[surrogate]\ndegree = 5\nmodel = \"polynomial\"\n"));
  EXPECT_THROW(config::load_study_config(dir.path / "c.toml", {}), config::ConfigError);
}

TEST(DoeCsv, MalformedTablesAreRefusedWithFileAndLine) {
  TempDir dir("csv");
  write(dir.path / "t.csv",
        "point,replicate,seed,apparatus,mu_r,angle_of_repose_deg,discharge_time_s,mass_flow_rate_kg_s,"
        "bulk_density_kg_m3,status,hash\n0,0,1,sandglass,0.1,30.5,,,,ok,ab\n1,0,1,sandglass,0.2,abc,,,,ok,cd\n");
  try {
    config::read_doe_csv(dir.path / "t.csv");
    FAIL();
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("t.csv:3: column angle_of_repose_deg"), std::string::npos) << e.what();
  }
}

TEST(RecordingsCsv, ReadsValidRowsAndRefusesBadOnesWithTheReason) {
  TempDir dir("rec");
  const std::vector<std::string> setups = {"sandglass"};
  write(dir.path / "ok.csv",
        "setup,observable,value,sigma,unit\nsandglass,angle_of_repose_deg,41.57,1.0,deg\n"
        "sandglass,discharge_time_s,6.56,0.15,s\n");
  const auto r = config::read_recordings_csv(dir.path / "ok.csv", setups);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_DOUBLE_EQ(r[1].value, 6.56);
  const auto refused = [&](const std::string& row, const std::string& why) {
    write(dir.path / "bad.csv", "setup,observable,value,sigma,unit\n" + row + "\n");
    try {
      config::read_recordings_csv(dir.path / "bad.csv", setups);
      ADD_FAILURE() << row;
    } catch (const config::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("bad.csv:2: " + why), std::string::npos) << e.what();
    }
  };
  refused("hopper,angle_of_repose_deg,41,1,deg", "setup \"hopper\" is not an apparatus of the study");
  refused("sandglass,angle_of_repose,41,1,deg", "observable \"angle_of_repose\" is not one demcal measures");
  refused("sandglass,angle_of_repose_deg,41,,deg", "sigma: missing");
  refused("sandglass,angle_of_repose_deg,41,0,deg", "sigma: expected a number > 0");
  refused("sandglass,angle_of_repose_deg,forty,1,deg", "value: expected a finite number");
  refused("sandglass,discharge_time_s,6.5,0.1,ms", "unit \"ms\" does not fit discharge_time_s");

  // The optional repeats column: how many tests a value is the mean of.
  write(dir.path / "rep.csv",
        "setup,observable,value,sigma,unit,repeats\nsandglass,angle_of_repose_deg,41.57,0.5,deg,5\n");
  const auto rep = config::read_recordings_csv(dir.path / "rep.csv", setups);
  ASSERT_EQ(rep.size(), 1u);
  EXPECT_EQ(rep[0].repeats, 5);
  EXPECT_EQ(r[0].repeats, 1);
  for (const char* bad : {"0", "2.5", "many"}) {
    write(dir.path / "rep.csv",
          std::string("setup,observable,value,sigma,unit,repeats\nsandglass,angle_of_repose_deg,41.57,0.5,deg,") + bad +
              "\n");
    try {
      config::read_recordings_csv(dir.path / "rep.csv", setups);
      ADD_FAILURE() << bad;
    } catch (const config::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("rep.csv:2: repeats"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace demcal
