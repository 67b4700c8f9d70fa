#include "dem/output/vtk_writer.hpp"

#include "dem/output/atomic_file.hpp"
#include "dem/simulation.hpp"

#include <charconv>
#include <cstdint>
#include <cstdio>
#include <string>

namespace demcal::dem {
namespace {

// Shortest text that reads back to the same double: exact snapshots at the
// smallest size ASCII allows.
void append(std::string& s, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}

void append(std::string& s, std::int64_t v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}

void append(std::string& s, const Vec3& v) {
  append(s, v.x);
  s += ' ';
  append(s, v.y);
  s += ' ';
  append(s, v.z);
}

// Appends one DataArray; `each(i)` appends the i-th tuple.
template <class Each>
void data_array(std::string& s, const char* type, const char* name, int components,
                std::size_t count, Each&& each) {
  s += "        <DataArray type=\"";
  s += type;
  s += "\" Name=\"";
  s += name;
  s += "\" NumberOfComponents=\"";
  s += std::to_string(components);
  s += "\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < count; ++i) {
    s += (i % 8 == 0) ? "          " : " ";
    each(i);
    if (i % 8 == 7 || i + 1 == count) s += '\n';
  }
  s += "        </DataArray>\n";
}

void header(std::string& s, double time_s) {
  s += "<?xml version=\"1.0\"?>\n";
  s += "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  s += "  <PolyData>\n";
  // ParaView reads TimeValue as the dataset's time when a file is opened alone.
  s += "    <FieldData>\n";
  s +=
      "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">";
  append(s, time_s);
  s += "</DataArray>\n";
  s += "    </FieldData>\n";
}

void footer(std::string& s) {
  s += "    </Piece>\n";
  s += "  </PolyData>\n";
  s += "</VTKFile>\n";
}

std::string numbered(const char* stem, std::size_t k) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s_%06zu.vtp", stem, k);
  return buf;
}

}  // namespace

void write_particles_vtp(const std::filesystem::path& file, const Particles& p, double time_s) {
  const std::size_t n = p.size();
  std::string s;
  s.reserve(256 + n * 200);
  header(s, time_s);
  s += "    <Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfVerts=\"" +
       std::to_string(n) + "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
  s += "      <PointData Scalars=\"radius_m\" Vectors=\"velocity_m_s\">\n";
  data_array(s, "Float64", "radius_m", 1, n, [&](std::size_t i) { append(s, p.radius_m[i]); });
  data_array(s, "Float64", "velocity_m_s", 3, n,
             [&](std::size_t i) { append(s, p.velocity_m_s[i]); });
  data_array(s, "Float64", "omega_rad_s", 3, n,
             [&](std::size_t i) { append(s, p.omega_rad_s[i]); });
  data_array(s, "Int64", "id", 1, n, [&](std::size_t i) { append(s, p.id[i]); });
  data_array(s, "Int32", "material", 1, n,
             [&](std::size_t i) { append(s, static_cast<std::int64_t>(p.material[i])); });
  s += "      </PointData>\n";
  s += "      <Points>\n";
  data_array(s, "Float64", "position_m", 3, n, [&](std::size_t i) { append(s, p.position_m[i]); });
  s += "      </Points>\n";
  s += "      <Verts>\n";
  data_array(s, "Int64", "connectivity", 1, n,
             [&](std::size_t i) { append(s, static_cast<std::int64_t>(i)); });
  data_array(s, "Int64", "offsets", 1, n,
             [&](std::size_t i) { append(s, static_cast<std::int64_t>(i + 1)); });
  s += "      </Verts>\n";
  footer(s);
  write_file_atomically(file, s);
}

void write_walls_vtp(const std::filesystem::path& file,
                     const std::vector<std::unique_ptr<Wall>>& walls, double time_s,
                     const Vec3& lo_m, const Vec3& hi_m) {
  std::vector<Vec3> points;
  std::vector<std::int64_t> connectivity;
  std::vector<std::int64_t> offsets;
  std::vector<std::int64_t> owner;
  for (std::size_t w = 0; w < walls.size(); ++w) {
    const SurfaceMesh mesh = walls[w]->mesh(time_s, lo_m, hi_m);
    const auto base = static_cast<std::int64_t>(points.size());
    points.insert(points.end(), mesh.points.begin(), mesh.points.end());
    for (const auto& poly : mesh.polygons) {
      for (int v : poly) connectivity.push_back(base + v);
      offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
      owner.push_back(static_cast<std::int64_t>(w));
    }
  }
  std::string s;
  header(s, time_s);
  s += "    <Piece NumberOfPoints=\"" + std::to_string(points.size()) +
       "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
       std::to_string(offsets.size()) + "\">\n";
  s += "      <CellData Scalars=\"wall\">\n";
  data_array(s, "Int32", "wall", 1, owner.size(), [&](std::size_t i) { append(s, owner[i]); });
  s += "      </CellData>\n";
  s += "      <Points>\n";
  data_array(s, "Float64", "position_m", 3, points.size(),
             [&](std::size_t i) { append(s, points[i]); });
  s += "      </Points>\n";
  s += "      <Polys>\n";
  data_array(s, "Int64", "connectivity", 1, connectivity.size(),
             [&](std::size_t i) { append(s, connectivity[i]); });
  data_array(s, "Int64", "offsets", 1, offsets.size(),
             [&](std::size_t i) { append(s, offsets[i]); });
  s += "      </Polys>\n";
  footer(s);
  write_file_atomically(file, s);
}

void write_pvd(const std::filesystem::path& file,
               const std::vector<std::pair<double, std::string>>& entries) {
  std::string s;
  s += "<?xml version=\"1.0\"?>\n";
  s += "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  s += "  <Collection>\n";
  for (const auto& [t, name] : entries) {
    s += "    <DataSet timestep=\"";
    append(s, t);
    s += "\" group=\"\" part=\"0\" file=\"" + name + "\"/>\n";
  }
  s += "  </Collection>\n";
  s += "</VTKFile>\n";
  write_file_atomically(file, s);
}

VtkSeries::VtkSeries(std::filesystem::path directory) : directory_(std::move(directory)) {
  std::filesystem::create_directories(directory_ / "vtk");
}

void VtkSeries::write(const Simulation& sim) {
  const std::size_t k = times_.size();
  const double t = sim.time_s();
  const Domain& dom = sim.options().domain;
  write_particles_vtp(directory_ / "vtk" / numbered("particles", k), sim.particles(), t);
  write_walls_vtp(directory_ / "vtk" / numbered("walls", k), sim.walls(), t, dom.lower_m,
                  dom.upper_m);
  times_.push_back(t);
  std::vector<std::pair<double, std::string>> particles, walls;
  for (std::size_t i = 0; i < times_.size(); ++i) {
    particles.emplace_back(times_[i], "vtk/" + numbered("particles", i));
    walls.emplace_back(times_[i], "vtk/" + numbered("walls", i));
  }
  write_pvd(particles_pvd(), particles);
  write_pvd(walls_pvd(), walls);
}

}  // namespace demcal::dem
