// The run-time selection tables (config/model_registry.hpp): lookup by name in
// registration order (the order, and so the text, of every `choice` message),
// an unknown name and a duplicate registration refused, `demcal schema`
// listing every family, and the drift check: for every registered model, the
// keys its reader actually reads (reader::Table::known_keys(), run on example
// tables below) are exactly the keys it declares, so the schema cannot list a
// key the reader does not take nor miss one it does; the defaults it writes in
// are the declared ones; and values just outside a key's declared range are
// refused at the key, values just inside not for their range. A model
// registered without an example here fails the test.

#include "config/model_registry.hpp"
#include "config/models/apparatus_models.hpp"
#include "config/models/insertion_models.hpp"
#include "config/models/size_models.hpp"
#include "config/models/surrogate_models.hpp"
#include "config/models/wall_models.hpp"
#include "config/run_sanity.hpp"
#include "config/schema.hpp"
#include "config/study_config.hpp"
#include "io/observable_registry.hpp"
#include "surrogate/surrogate_fit.hpp"
#include "tests/support/study_text.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace demcal::config {
namespace {

using reader::Context;
using reader::Table;

// Each registered model's example tables (TOML bodies of one table); together
// they must make its reader ask for every key it declares.
using Examples = std::map<std::string, std::vector<std::string>>;

// A value written into a table as the schema's default text starts with it:
// 0.5, 200, true, "random", [0, 0, 0].
std::string default_text_of(const toml::node& n) {
  if (n.is_boolean()) return *n.value<bool>() ? "true" : "false";
  if (n.is_integer()) return std::to_string(*n.value<std::int64_t>());
  if (n.is_floating_point()) return reader::format_number(*n.value<double>());
  if (n.is_string()) return "\"" + *n.value<std::string>() + "\"";
  if (const toml::array* a = n.as_array()) {
    std::string s = "[";
    for (std::size_t i = 0; i < a->size(); ++i) s += (i ? ", " : "") + default_text_of((*a)[i]);
    return s + "]";
  }
  return "?";
}

// What a reader did with one example table [m]: the keys it asked for, and
// the keys it wrote in (absent from the example) with the text of their value.
// The reader must accept the example, and every key in it (finish() is called).
struct ReadResult {
  std::vector<std::string> keys;
  std::map<std::string, std::string> written_in;
};

ReadResult read_example(const std::string& body, const std::function<void(Table&)>& run) {
  ConfigDocument doc = parse_config_string("[m]\n" + body, "example.toml");
  const ConfigDocument given = parse_config_string("[m]\n" + body, "example.toml");
  const Context ctx{doc};
  Table root(ctx, doc.table, "", 1);
  Table t = root.table("m");
  run(t);
  t.finish();
  ReadResult r{t.known_keys(), {}};
  const toml::table& before = *given.table.get("m")->as_table();
  for (const auto& [k, v] : *doc.table.get("m")->as_table())
    if (!before.contains(k.str())) r.written_in[std::string(k.str())] = default_text_of(v);
  return r;
}

// The numeric bounds a declared range text starts with ("> 0", ">= 2",
// "(0, 80)", "[0, 1)", "(1, 3], ..."), as the values just outside them: the
// lower bound itself when open, else one below; the same above. Empty for a
// range that is not a plain interval (a choice, "[0, height_m)"). Integer
// ranges ("an integer in [1, 100]") likewise.
struct Probes {
  std::vector<double> outside;  // must be refused at the key
  std::vector<double> inside;   // must not be refused for its range
};

Probes range_probes(const std::string& range_text) {
  constexpr double kStep = 1e-6;
  std::smatch m;
  static const std::regex one_sided(R"(^(>=|>) (-?[0-9.e+-]+))");
  static const std::regex interval(R"(^([\[(])(-?[0-9.e+-]+), (-?[0-9.e+-]+)([\])]))");
  static const std::regex integers(R"(^an integer in \[(-?[0-9]+), (-?[0-9]+)\])");
  static const std::regex integers_from(R"(^an integer >= (-?[0-9]+))");
  if (std::regex_search(range_text, m, integers)) {
    const double lo = std::stod(m[1]), hi = std::stod(m[2]);
    return {{lo - 1, hi + 1}, {lo, hi}};
  }
  if (std::regex_search(range_text, m, integers_from)) {
    const double lo = std::stod(m[1]);
    return {{lo - 1}, {lo}};
  }
  if (std::regex_search(range_text, m, one_sided)) {
    const double lo = std::stod(m[2]);
    return m[1] == ">" ? Probes{{lo}, {lo + kStep}} : Probes{{lo - 1}, {lo}};
  }
  if (std::regex_search(range_text, m, interval)) {
    const double lo = std::stod(m[2]), hi = std::stod(m[3]);
    const bool lo_open = m[1] == "(", hi_open = m[4] == ")";
    return {{lo_open ? lo : lo - 1, hi_open ? hi : hi + 1},
            {lo_open ? lo + kStep : lo, hi_open ? hi - kStep : hi}};
  }
  return {};
}

// `body` with the value of `key = ...` replaced; "" when the key is not in it.
std::string with_value(const std::string& body, const std::string& key, double value) {
  std::istringstream in(body);
  std::string line, out;
  bool found = false;
  while (std::getline(in, line)) {
    if (line.rfind(key + " = ", 0) == 0) {
      line = key + " = " + reader::format_number(value);
      found = true;
    }
    out += line + "\n";
  }
  return found ? out : "";
}

template <class Model>
void expect_no_drift(const ModelRegistry<Model>& registry, const Examples& examples,
                     const std::function<void(const Model&, Table&)>& run) {
  int probes = 0;  // range probes run: a test that probes nothing tests nothing
  for (const auto& entry : registry.entries()) {
    const std::string& name = entry.info.name;
    const auto ex = examples.find(name);
    ASSERT_NE(ex, examples.end()) << registry.family().kind << " \"" << name
                                  << "\" is registered without an example in this test";
    std::set<std::string> declared;
    std::map<std::string, std::string> default_texts;
    for (const ModelKey& k : entry.info.keys) {
      default_texts[k.key] = k.default_text;
      EXPECT_TRUE(declared.insert(k.key).second) << name << ": " << k.key << " declared twice";
      EXPECT_FALSE(k.range_text.empty()) << name << ": " << k.key;
      EXPECT_FALSE(k.default_text.empty()) << name << ": " << k.key;
      EXPECT_FALSE(k.summary.empty()) << name << ": " << k.key;
    }
    std::set<std::string> read;
    for (const std::string& body : ex->second) {
      ReadResult result;
      try {
        result = read_example(body, [&](Table& t) { run(entry.model, t); });
      } catch (const std::exception& e) {
        ADD_FAILURE() << registry.family().kind << " \"" << name << "\": the example\n"
                      << body << "\nwas refused: " << e.what();
        continue;
      }
      // A default the reader writes in is the one the schema shows.
      for (const auto& [k, value] : result.written_in) {
        const auto d = default_texts.find(k);
        if (d == default_texts.end()) continue;  // reported below as undeclared
        EXPECT_EQ(d->second.rfind(value, 0), 0u)
            << registry.family().kind << " \"" << name << "\" writes in " << k << " = " << value
            << " but declares the default \"" << d->second << "\"";
      }
      // The range a key is declared with is the one its reader refuses values
      // outside of, at the key.
      for (const ModelKey& k : entry.info.keys) {
        const Probes p = range_probes(k.range_text);
        for (const double v : p.outside) {
          const std::string probe = with_value(body, k.key, v);
          if (probe.empty()) continue;
          try {
            (void)read_example(probe, [&](Table& t) { run(entry.model, t); });
            ADD_FAILURE() << registry.family().kind << " \"" << name << "\" accepts " << k.key
                          << " = " << v << ", outside its declared range " << k.range_text;
          } catch (const ConfigError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find("m." + k.key + ": expected"), std::string::npos)
                << name << " " << k.key << " = " << v << ": " << m;
          }
          ++probes;
        }
        // Just inside: the reader may refuse it for another reason (a
        // geometry that cannot hold the fill) but not for its range.
        // Only for a plain range: "> 0, >= min_diameter_m" is bounded by another key too.
        const bool plain = std::regex_match(
            k.range_text, std::regex(R"([^,]*(, [^,]*)?(, at most [0-9.e+]+)?)")) &&
                           k.range_text.find("_") == std::string::npos;
        for (const double v : plain ? p.inside : std::vector<double>{}) {
          const std::string probe = with_value(body, k.key, v);
          if (probe.empty()) continue;
          try {
            (void)read_example(probe, [&](Table& t) { run(entry.model, t); });
          } catch (const ConfigError& e) {
            const std::string m = e.what();
            EXPECT_TRUE(m.find("m." + k.key + ": expected a number") == std::string::npos &&
                        m.find("m." + k.key + ": expected an integer") == std::string::npos)
                << name << " " << k.key << " = " << v << " is inside its declared range "
                << k.range_text << " but refused: " << m;
          }
        }
      }
      for (const std::string& k : result.keys) {
        EXPECT_TRUE(declared.count(k) == 1)
            << registry.family().kind << " \"" << name << "\" reads \"" << k
            << "\", which it does not declare";
        read.insert(k);
      }
    }
    for (const std::string& k : declared)
      EXPECT_TRUE(read.count(k) == 1) << registry.family().kind << " \"" << name
                                      << "\" declares \"" << k << "\", which its reader never reads";
  }
  EXPECT_GT(probes, 0) << registry.family().kind << ": no declared range was probed";
}

// A small material and protocol, as a study gives them to an apparatus reader.
const std::string kStudy = R"([study]
name = "registry"
)" +
    testing::sand_and_glass_tables(
        {.size = R"({ distribution = "uniform", min_diameter_m = 3.0e-4, max_diameter_m = 6.0e-4 })"}) +
    R"(
[apparatus.rectangular_container]
width_m = 0.22
height_m = 0.1
thickness_diameters = 4.0
boundary = "periodic"
fill_mass_kg = 0.055
coarse_graining_factor = 6.0
shear_modulus_pa = 1.0e7
)";

const char* const kReduction = R"(slice = true
slice_thickness_diameters = 4.2
coarse_graining_factor = 6.0
shear_modulus_pa = 1.0e7
)";
// Without slice_thickness_diameters: written in at its default.
const char* const kShortReduction = R"(slice = true
coarse_graining_factor = 6.0
shear_modulus_pa = 1.0e7
)";

TEST(ModelRegistry, NamesInRegistrationOrderAndTheOldMessageLists) {
  // The lists the readers' `choice` messages gave before the registries.
  EXPECT_EQ(apparatus_models().names(),
            (std::vector<std::string>{"sandglass", "conical_pile", "rectangular_container"}));
  EXPECT_EQ(known_apparatus_names(), apparatus_models().names());
  EXPECT_EQ(wall_models().names(), (std::vector<std::string>{"plane", "rectangle", "disk",
                                                             "cylinder", "cone", "orifice_plate"}));
  EXPECT_EQ(region_models().names(), (std::vector<std::string>{"box", "cylinder"}));
  EXPECT_EQ(inserter_models().names(), (std::vector<std::string>{"pour", "fill"}));
  EXPECT_EQ(size_models().names(), (std::vector<std::string>{"monodisperse", "uniform",
                                                             "truncated_normal", "log_normal",
                                                             "sieve"}));
  EXPECT_EQ(surrogate_models().names(),
            (std::vector<std::string>{"gaussian_process", "polynomial"}));
}

TEST(ModelRegistry, TheReadersSurrogateKindsAreTheOnesTheFitterKnows) {
  // Two tables for one family, each where its layer needs it (config reads the keys,
  // surrogate/ fits): a kind in one and not the other would be accepted and then refused.
  EXPECT_EQ(surrogate_models().names(), surrogate::surrogate_model_names());
}

TEST(ModelRegistry, SchemaListsTheObservablesFromTheirRegistry) {
  const std::string table = schema_text("observables");
  for (const auto& o : io::observable_registry())
    EXPECT_NE(table.find(std::string(o.name)), std::string::npos) << o.name;
  EXPECT_NE(schema_text("").find(table), std::string::npos) << "the full listing ends with it";
}

TEST(ModelRegistry, LookupByNameAndUnknownName) {
  ASSERT_NE(apparatus_models().find("conical_pile"), nullptr);
  EXPECT_EQ(apparatus_models().find("conical_pile")->info.name, "conical_pile");
  EXPECT_EQ(apparatus_models().find("hourglass"), nullptr);
  EXPECT_EQ(&size_models().at("sieve"), size_models().find("sieve"));
  try {
    (void)apparatus_models().at("hourglass");
    ADD_FAILURE() << "an unknown apparatus was found";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              "apparatus: unknown name \"hourglass\"; expected one of \"sandglass\", "
              "\"conical_pile\", \"rectangular_container\"");
  }
  EXPECT_THROW((void)wall_models().at("sphere"), ConfigError);
}

TEST(ModelRegistry, DuplicateRegistrationRefused) {
  using Reader = int (*)();
  ModelRegistry<Reader> r({"test family", "", "nowhere"});
  const Reader one = [] { return 1; };
  r.add({"a", "the first", {}}, one);
  r.add({"b", "the second", {}}, one);
  try {
    r.add({"a", "a second a", {}}, one);
    ADD_FAILURE() << "a duplicate name was accepted";
  } catch (const std::logic_error& e) {
    EXPECT_EQ(std::string(e.what()), "test family \"a\" is registered twice");
  }
  EXPECT_THROW(r.add({"", "no name", {}}, one), std::logic_error);
  EXPECT_EQ(r.names(), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(r.at("a").info.summary, "the first");
}

TEST(ModelRegistry, SchemaListsEveryFamily) {
  const std::string all = schema_text("");
  for (const ModelFamilyListing& f : model_families()) {
    EXPECT_FALSE(f.models.empty()) << f.family.kind;
    for (const ModelInfo& m : f.models) {
      EXPECT_NE(all.find(f.family.kind + " \"" + m.name + "\""), std::string::npos)
          << f.family.kind << " " << m.name;
      for (const ModelKey& k : m.keys)
        EXPECT_NE(schema_text(m.name).find("  " + k.key), std::string::npos) << m.name << k.key;
    }
  }
  const std::string size = schema_text("size");
  EXPECT_EQ(size, schema_text("size distribution"));
  for (const std::string& n : size_models().names())
    EXPECT_NE(size.find("size distribution \"" + n + "\""), std::string::npos) << n;
  EXPECT_EQ(size.find("apparatus"), std::string::npos) << size;

  const std::string apparatus = schema_text("apparatus");
  for (const std::string& n : apparatus_models().names())
    EXPECT_NE(apparatus.find("apparatus \"" + n + "\""), std::string::npos) << n;
  EXPECT_EQ(apparatus.find("wall \""), std::string::npos) << apparatus;

  const std::string sandglass = schema_text("sandglass");
  EXPECT_NE(sandglass.find("apparatus \"sandglass\"\n  [apparatus.sandglass], or "
                           "[apparatus.<setup>] with type = \"sandglass\""),
            std::string::npos)
      << sandglass;
  EXPECT_NE(sandglass.find("  orifice_diameter_m [m]  range > 0, at most 100  default required"),
            std::string::npos)
      << sandglass;
  EXPECT_NE(sandglass.find("  hopper_half_angle_deg [deg]  range (0, 80)"), std::string::npos)
      << sandglass;
  EXPECT_EQ(sandglass.find("conical_pile"), std::string::npos) << sandglass;

  // A name shared by two families (a cylinder wall, a cylinder region) lists both.
  const std::string cylinder = schema_text("cylinder");
  EXPECT_NE(cylinder.find("wall \"cylinder\""), std::string::npos) << cylinder;
  EXPECT_NE(cylinder.find("region \"cylinder\""), std::string::npos) << cylinder;

  try {
    (void)schema_text("hourglass");
    ADD_FAILURE() << "an unknown schema name was accepted";
  } catch (const ConfigError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("schema: unknown name \"hourglass\"; known: ", 0), 0u) << m;
    for (const char* known : {"\"apparatus\"", "\"sandglass\"", "\"size\"", "\"size distribution\"",
                              "\"wall\"", "\"orifice_plate\"", "\"insertion\"", "\"region\"",
                              "\"surrogate\"", "\"polynomial\"", "\"contact\"", "\"candidates\""})
      EXPECT_NE(m.find(known), std::string::npos) << known << " in " << m;
  }
}

TEST(ModelRegistryDrift, ApparatusReadersReadExactlyTheirDeclaredKeys) {
  ConfigDocument doc = parse_config_string(kStudy, "study.toml");
  const StudyConfig study = build_study(std::move(doc));
  const Examples examples = {
      {"sandglass",
       {std::string(R"(upper_diameter_m = 0.08
upper_height_m = 0.12
bottom = "conical"
hopper_half_angle_deg = 30.0
orifice_diameter_m = 0.02
fill_mass_kg = 0.31
lower_diameter_m = 0.2
drop_height_m = 0.08
form_pile = true
fill_lattice_spacing_diameters = 1.05
)") + kReduction,
        std::string(R"(upper_diameter_m = 0.08
upper_height_m = 0.12
bottom = "flat"
orifice_diameter_m = 0.02
fill_mass_kg = 0.2
lower_diameter_m = 0.2
drop_height_m = 0.08
)") + kShortReduction}},
      {"conical_pile",
       {std::string(R"(funnel_top_diameter_m = 0.08
funnel_outlet_diameter_m = 0.02
funnel_half_angle_deg = 30.0
feed_height_m = 0.125
drop_height_m = 0.06
base_diameter_m = 0.12
fill_mass_kg = 0.2
)") + kReduction,
        std::string(R"(funnel_top_diameter_m = 0.08
funnel_outlet_diameter_m = 0.02
funnel_half_angle_deg = 30.0
feed_height_m = 0.125
drop_height_m = 0.06
base_diameter_m = 0.12
fill_mass_kg = 0.2
)") + kShortReduction}},
      {"rectangular_container",
       {R"(width_m = 0.22
height_m = 0.1
thickness_diameters = 4.0
boundary = "periodic"
fill_mass_kg = 0.055
inlet_width_m = 0.01
inlet_height_m = 0.08
inlet_speed_m_s = 0.5
median_band_diameters = 2.0
coarse_graining_factor = 6.0
shear_modulus_pa = 1.0e7
)",
        R"(width_m = 0.22
height_m = 0.1
thickness_m = 0.011
boundary = "walls"
fill_mass_kg = 0.055
coarse_graining_factor = 6.0
shear_modulus_pa = 1.0e7
)"}}};
  expect_no_drift<ApparatusModel>(apparatus_models(), examples,
                                  [&](const ApparatusModel& m, Table& t) {
                                    EXPECT_NE(m.read(t, study.material, kDefaultMaxSteps,
                                                     study.protocol),
                                              nullptr);
                                    EXPECT_FALSE(m.wall_group_names().empty());
                                  });
}

TEST(ModelRegistryDrift, WallReadersReadExactlyTheirDeclaredKeys) {
  const Examples examples = {
      {"plane", {"point_m = [0, 0, 0]\nnormal = [0, 0, 1]\n"}},
      {"rectangle",
       {"centre_m = [0, 0, 0]\nnormal = [0, 0, 1]\naxis_u = [1, 0, 0]\nhalf_length_u_m = 0.1\n"
        "half_length_v_m = 0.2\n"}},
      {"disk", {"centre_m = [0, 0, 0]\nnormal = [0, 0, 1]\nradius_m = 0.1\n"}},
      {"cylinder", {"base_m = [0, 0, 0]\naxis = [0, 0, 1]\nlength_m = 0.2\nradius_m = 0.1\n"}},
      {"cone",
       {"base_m = [0, 0, 0]\naxis = [0, 0, 1]\nlength_m = 0.2\nradius_base_m = 0.01\n"
        "radius_end_m = 0.1\n"}},
      {"orifice_plate",
       {"centre_m = [0, 0, 0]\nnormal = [0, 0, 1]\nopen_time_s = 0.1\ndiameter_m = 0.01\n"
        "outer_radius_m = 0.1\n",
        "centre_m = [0, 0, 0]\nnormal = [0, 0, 1]\nopen_time_s = 0.1\nwidth_m = 0.01\n"
        "axis_u = [1, 0, 0]\n",
        "centre_m = [0, 0, 0]\nnormal = [0, 0, 1]\nopen_time_s = 0.1\ndiameter_m = 0.01\n"}}};
  expect_no_drift<WallReader>(wall_models(), examples, [](const WallReader& read, Table& t) {
    EXPECT_NE(read(t), nullptr);
  });
}

TEST(ModelRegistryDrift, RegionAndInserterReadersReadExactlyTheirDeclaredKeys) {
  const Examples regions = {
      {"box", {"lower_m = [0, 0, 0]\nupper_m = [0.1, 0.1, 0.1]\n"}},
      {"cylinder", {"base_centre_m = [0, 0, 0]\nradius_m = 0.05\nheight_m = 0.1\n"}}};
  expect_no_drift<RegionReader>(region_models(), regions, [](const RegionReader& read, Table& t) {
    EXPECT_NE(read(t), nullptr);
  });

  const Examples inserters = {
      {"pour",
       {"velocity_m_s = [0, 0, -0.1]\nstart_s = 0.0\nbatch_volume_fraction = 0.2\n"
        "attempts_per_particle = 100\n",
        "rate_particles_per_s = 1000.0\n", ""}},
      {"fill", {"time_s = 0.0\nmethod = \"lattice\"\nlattice_gap = 0.05\n"
                "attempts_per_particle = 100\n", ""}}};
  InsertionCommon common;
  common.material = 0;
  common.density_kg_m3 = 2650.0;
  common.amount.count = 10;
  common.gravity_m_s2 = {0, 0, -9.81};
  expect_no_drift<InserterReader>(
      inserter_models(), inserters, [&](const InserterReader& read, Table& t) {
        EXPECT_NE(read(t, common, dem::make_box_region({0, 0, 0}, {0.1, 0.1, 0.1}),
                       dem::make_monodisperse(2e-3)),
                  nullptr);
      });
}

TEST(ModelRegistryDrift, SizeAndSurrogateReadersReadExactlyTheirDeclaredKeys) {
  const Examples sizes = {
      {"monodisperse", {"diameter_m = 1e-3\n"}},
      {"uniform",
       {"min_diameter_m = 1e-3\nmax_diameter_m = 2e-3\n",
        "mean_diameter_m = 1e-3\nrelative_half_width = 0.2\n"}},
      {"truncated_normal",
       {"mean_diameter_m = 1e-3\nstd_dev_m = 1e-4\nmin_diameter_m = 8e-4\nmax_diameter_m = 1.2e-3\n"}},
      {"log_normal",
       {"median_diameter_m = 1e-3\nsigma_ln = 0.2\nmin_diameter_m = 8e-4\n"
        "max_diameter_m = 1.2e-3\n"}},
      {"sieve", {"sieve = [[5e-4, 0.0], [1e-3, 0.5], [2e-3, 1.0]]\n"}}};
  expect_no_drift<SizeReader>(size_models(), sizes, [](const SizeReader& read, Table& t) {
    EXPECT_NE(read(t), nullptr);
  });

  const Examples surrogates = {
      {"gaussian_process",
       {"kernel = \"squared_exponential\"\nmean = \"linear\"\nnugget = \"none\"\nstarts = 4\n"
        "seed = 2\n", ""}},
      {"polynomial", {"degree = 2\n", ""}}};
  expect_no_drift<SurrogateReader>(surrogate_models(), surrogates,
                                   [](const SurrogateReader& read, Table& t) {
                                     surrogate::SurrogateSpec spec;
                                     read(t, spec);
                                   });
}

}  // namespace
}  // namespace demcal::config
