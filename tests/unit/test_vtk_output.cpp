// VTK snapshots: well-formed XML with the arrays and counts ParaView expects,
// collections listing every snapshot with its time, and no temporary files left.

#include "dem/output/vtk_writer.hpp"
#include "dem/simulation.hpp"
#include "dem/wall/bounded_plane_wall.hpp"
#include "dem/wall/plane_wall.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace demcal::dem {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Checks that tags nest and close properly (the subset of XML the writer uses:
// a declaration, elements, attributes, text). Returns "" or what is wrong.
std::string xml_nesting_error(const std::string& xml) {
  std::vector<std::string> open;
  std::size_t pos = 0;
  while ((pos = xml.find('<', pos)) != std::string::npos) {
    const std::size_t end = xml.find('>', pos);
    if (end == std::string::npos) return "unterminated tag at " + std::to_string(pos);
    const std::string tag = xml.substr(pos + 1, end - pos - 1);
    pos = end + 1;
    if (tag.empty()) return "empty tag";
    if (tag[0] == '?') continue;
    if (tag[0] == '/') {
      if (open.empty() || open.back() != tag.substr(1))
        return "unexpected </" + tag.substr(1) + ">";
      open.pop_back();
      continue;
    }
    if (tag.back() == '/') continue;
    open.push_back(tag.substr(0, tag.find(' ')));
  }
  if (!open.empty()) return "unclosed <" + open.back() + ">";
  return "";
}

std::string attribute(const std::string& xml, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const std::size_t at = xml.find(key);
  if (at == std::string::npos) return "";
  const std::size_t begin = at + key.size();
  return xml.substr(begin, xml.find('"', begin) - begin);
}

// The whitespace-separated values of the DataArray called `name`.
std::vector<std::string> array_values(const std::string& xml, const std::string& name) {
  const std::size_t at = xml.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return {};
  const std::size_t begin = xml.find('>', at) + 1;
  const std::size_t end = xml.find("</DataArray>", begin);
  std::istringstream in(xml.substr(begin, end - begin));
  std::vector<std::string> out;
  for (std::string v; in >> v;) out.push_back(v);
  return out;
}

std::size_t count(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t p = text.find(needle); p != std::string::npos; p = text.find(needle, p + 1)) ++n;
  return n;
}

class VtkOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("demcal_vtk_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Three grains above a floor and a lid disk: a tiny but complete snapshot.
  std::unique_ptr<Simulation> tiny_simulation() {
    SimulationOptions o;
    o.domain.lower_m = {0, 0, 0};
    o.domain.upper_m = {0.01, 0.01, 0.01};
    o.contact.rolling = "none";
    auto sim = std::make_unique<Simulation>(o);
    Material m;
    m.name = "grain";
    m.youngs_modulus_pa = 1e7;
    const int g = sim->add_material(m);
    sim->set_interaction(g, g, InteractionParameters{});
    sim->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), g);
    sim->add_wall(std::make_unique<DiskWall>(Vec3{0.005, 0.005, 0.009}, Vec3{0, 0, 1}, 0.004), g);
    sim->add_particle({0.002, 0.005, 0.002}, 5e-4, g, {0.1, 0, 0});
    sim->add_particle({0.005, 0.005, 0.002}, 6e-4, g);
    sim->add_particle({0.008, 0.005, 0.002}, 7e-4, g, {}, {0, 0, 3});
    return sim;
  }

  fs::path dir_;
};

TEST_F(VtkOutputTest, ParticleFileHasTheArraysAndCounts) {
  auto sim = tiny_simulation();
  fs::create_directories(dir_);
  const fs::path file = dir_ / "p.vtp";
  write_particles_vtp(file, sim->particles(), 0.25);
  const std::string xml = read(file);
  EXPECT_EQ(xml.rfind("<?xml", 0), 0u);
  EXPECT_EQ(xml_nesting_error(xml), "");
  EXPECT_NE(xml.find("<VTKFile type=\"PolyData\""), std::string::npos);
  EXPECT_EQ(attribute(xml, "NumberOfPoints"), "3");
  EXPECT_EQ(attribute(xml, "NumberOfVerts"), "3");
  EXPECT_EQ(array_values(xml, "TimeValue"), std::vector<std::string>{"0.25"});
  EXPECT_EQ(array_values(xml, "radius_m").size(), 3u);
  EXPECT_EQ(array_values(xml, "velocity_m_s").size(), 9u);
  EXPECT_EQ(array_values(xml, "omega_rad_s").size(), 9u);
  EXPECT_EQ(array_values(xml, "id"), (std::vector<std::string>{"0", "1", "2"}));
  EXPECT_EQ(array_values(xml, "material"), (std::vector<std::string>{"0", "0", "0"}));
  EXPECT_EQ(array_values(xml, "position_m").size(), 9u);
  EXPECT_EQ(array_values(xml, "offsets"), (std::vector<std::string>{"1", "2", "3"}));
  // Shortest round-trip text: the values read back exactly.
  EXPECT_EQ(std::stod(array_values(xml, "radius_m")[2]), 7e-4);
  EXPECT_EQ(std::stod(array_values(xml, "velocity_m_s")[0]), 0.1);
  EXPECT_EQ(std::stod(array_values(xml, "omega_rad_s")[8]), 3.0);
  EXPECT_EQ(count(xml, "<DataArray"), count(xml, "</DataArray>"));
  EXPECT_FALSE(fs::exists(dir_ / "p.vtp.partial"));
}

TEST_F(VtkOutputTest, EmptyParticleSetIsStillValid) {
  fs::create_directories(dir_);
  write_particles_vtp(dir_ / "empty.vtp", Particles{}, 0.0);
  const std::string xml = read(dir_ / "empty.vtp");
  EXPECT_EQ(xml_nesting_error(xml), "");
  EXPECT_EQ(attribute(xml, "NumberOfPoints"), "0");
  EXPECT_TRUE(array_values(xml, "position_m").empty());
}

TEST_F(VtkOutputTest, WallFileHasEveryPolygonOfEveryWall) {
  auto sim = tiny_simulation();
  fs::create_directories(dir_);
  const Domain& d = sim->options().domain;
  write_walls_vtp(dir_ / "w.vtp", sim->walls(), 0.0, d.lower_m, d.upper_m);
  std::size_t points = 0, polys = 0, corners = 0;
  for (const auto& w : sim->walls()) {
    const SurfaceMesh m = w->mesh(0.0, d.lower_m, d.upper_m);
    points += m.points.size();
    polys += m.polygons.size();
    for (const auto& p : m.polygons) corners += p.size();
  }
  ASSERT_GT(polys, 1u);
  const std::string xml = read(dir_ / "w.vtp");
  EXPECT_EQ(xml_nesting_error(xml), "");
  EXPECT_EQ(attribute(xml, "NumberOfPoints"), std::to_string(points));
  EXPECT_EQ(attribute(xml, "NumberOfPolys"), std::to_string(polys));
  EXPECT_EQ(array_values(xml, "position_m").size(), 3 * points);
  EXPECT_EQ(array_values(xml, "connectivity").size(), corners);
  const auto offsets = array_values(xml, "offsets");
  ASSERT_EQ(offsets.size(), polys);
  EXPECT_EQ(offsets.back(), std::to_string(corners));
  const auto owner = array_values(xml, "wall");
  ASSERT_EQ(owner.size(), polys);
  EXPECT_EQ(owner.front(), "0");
  EXPECT_EQ(owner.back(), "1");
  for (const auto& c : array_values(xml, "connectivity")) EXPECT_LT(std::stoul(c), points);
}

TEST_F(VtkOutputTest, SeriesListsEverySnapshotWithItsTime) {
  auto sim = tiny_simulation();
  VtkSeries series(dir_);
  series.write(*sim);
  sim->run_steps(5);
  series.write(*sim);
  EXPECT_EQ(series.snapshots(), 2u);
  EXPECT_DOUBLE_EQ(series.last_time_s(), sim->time_s());
  for (const char* f : {"vtk/particles_000000.vtp", "vtk/particles_000001.vtp",
                        "vtk/walls_000000.vtp", "vtk/walls_000001.vtp"})
    EXPECT_TRUE(fs::exists(dir_ / f)) << f;
  for (const auto& e : fs::recursive_directory_iterator(dir_))
    EXPECT_NE(e.path().extension(), ".partial") << "temporary file left: " << e.path();

  const std::string pvd = read(series.particles_pvd());
  EXPECT_EQ(xml_nesting_error(pvd), "");
  EXPECT_NE(pvd.find("<VTKFile type=\"Collection\""), std::string::npos);
  EXPECT_EQ(count(pvd, "<DataSet "), 2u);
  EXPECT_NE(pvd.find("timestep=\"0\" group=\"\" part=\"0\" file=\"vtk/particles_000000.vtp\""),
            std::string::npos)
      << pvd;
  const std::size_t second = pvd.find("file=\"vtk/particles_000001.vtp\"");
  ASSERT_NE(second, std::string::npos);
  const std::size_t ts = pvd.rfind("timestep=\"", second) + 10;
  EXPECT_DOUBLE_EQ(std::stod(pvd.substr(ts, pvd.find('"', ts) - ts)), sim->time_s());

  const std::string walls_pvd = read(series.walls_pvd());
  EXPECT_EQ(count(walls_pvd, "<DataSet "), 2u);
  EXPECT_NE(walls_pvd.find("vtk/walls_000001.vtp"), std::string::npos);
  EXPECT_EQ(attribute(read(dir_ / "vtk/particles_000001.vtp"), "NumberOfPoints"), "3");
}

}  // namespace
}  // namespace demcal::dem
