#include "slicer/mesh.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace beadtwin::slicer {

Eigen::Vector3d TriangleMesh::min_corner() const {
  Eigen::Vector3d m = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  for (const auto& v : vertices) m = m.cwiseMin(v);
  return m;
}

Eigen::Vector3d TriangleMesh::max_corner() const {
  Eigen::Vector3d m = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
  for (const auto& v : vertices) m = m.cwiseMax(v);
  return m;
}

double TriangleMesh::volume_mm3() const {
  double v6 = 0.0;
  for (const auto& t : triangles)
    v6 += vertices[static_cast<std::size_t>(t[0])].dot(
        vertices[static_cast<std::size_t>(t[1])].cross(vertices[static_cast<std::size_t>(t[2])]));
  return v6 / 6.0;
}

namespace {

// Welds equal coordinates so triangles share vertices (STL stores each triangle's corners separately).
class Welder {
 public:
  explicit Welder(TriangleMesh& mesh) : mesh_(mesh) {}
  int add(const Eigen::Vector3d& p) {
    const std::array<double, 3> key{p.x(), p.y(), p.z()};
    auto [it, inserted] = index_.try_emplace(key, static_cast<int>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(p);
    return it->second;
  }

 private:
  TriangleMesh& mesh_;
  std::map<std::array<double, 3>, int> index_;
};

void add_triangle(TriangleMesh& mesh, Welder& welder, const std::array<Eigen::Vector3d, 3>& corners,
                  const std::string& file, int line) {
  for (const auto& c : corners)
    if (!c.allFinite())
      throw InputError({file, line, 0}, {}, "triangle with a coordinate that is not a finite number");
  const std::array<int, 3> t{welder.add(corners[0]), welder.add(corners[1]), welder.add(corners[2])};
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return;  // degenerate: contributes nothing to a slice
  mesh.triangles.push_back(t);
}

TriangleMesh read_binary_stl(const std::string& bytes, const std::string& file, double scale) {
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  const std::size_t expected = 84 + static_cast<std::size_t>(count) * 50;
  if (bytes.size() < expected)
    throw InputError(
        {file, 0, 0}, {},
        fmt::format("binary STL says it holds {} triangles ({} bytes) but the file has only {} bytes", count,
                    expected, bytes.size()));
  TriangleMesh mesh;
  Welder welder(mesh);
  mesh.triangles.reserve(count);
  for (std::uint32_t i = 0; i < count; ++i) {
    const char* rec = bytes.data() + 84 + static_cast<std::size_t>(i) * 50;
    std::array<Eigen::Vector3d, 3> corners;
    for (int c = 0; c < 3; ++c) {
      float xyz[3];
      std::memcpy(xyz, rec + 12 + c * 12, 12);
      corners[static_cast<std::size_t>(c)] = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]) * scale;
    }
    add_triangle(mesh, welder, corners, file, 0);
  }
  return mesh;
}

TriangleMesh read_ascii_stl(const std::string& text, const std::string& file, double scale) {
  TriangleMesh mesh;
  Welder welder(mesh);
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  std::array<Eigen::Vector3d, 3> corners;
  int corner = 0;
  int facet_line = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream words(line);
    std::string word;
    if (!(words >> word)) continue;
    if (word == "facet") {
      corner = 0;
      facet_line = line_no;
    } else if (word == "vertex") {
      double x = 0, y = 0, z = 0;
      if (!(words >> x >> y >> z))
        throw InputError({file, line_no, 0}, {}, "expected 'vertex x y z' with three numbers");
      if (corner >= 3) throw InputError({file, line_no, 0}, {}, "a facet has more than three vertices");
      corners[static_cast<std::size_t>(corner++)] = Eigen::Vector3d(x, y, z) * scale;
    } else if (word == "endfacet") {
      if (corner != 3)
        throw InputError({file, facet_line, 0}, {},
                         fmt::format("a facet has {} vertices, expected 3", corner));
      add_triangle(mesh, welder, corners, file, facet_line);
    } else if (word != "solid" && word != "endsolid" && word != "outer" && word != "endloop") {
      throw InputError({file, line_no, 0}, {}, fmt::format("unexpected '{}' in an ASCII STL", word));
    }
  }
  return mesh;
}

}  // namespace

TriangleMesh read_stl(const std::filesystem::path& path, double unit_scale) {
  const std::string file = path.string();
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError({file, 0, 0}, {}, "cannot open the mesh file");
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (bytes.size() < 15) throw InputError({file, 0, 0}, {}, "file is too short to be an STL");
  // An ASCII STL starts with "solid" and has "facet" soon; some binary files start with "solid" too,
  // so the size check of the binary layout decides.
  bool binary = true;
  if (bytes.compare(0, 5, "solid") == 0) {
    std::uint32_t count = 0;
    if (bytes.size() >= 84) std::memcpy(&count, bytes.data() + 80, 4);
    binary = bytes.size() >= 84 && bytes.size() == 84 + static_cast<std::size_t>(count) * 50;
  }
  if (binary && bytes.size() < 84) throw InputError({file, 0, 0}, {}, "file is too short to be a binary STL");
  TriangleMesh mesh =
      binary ? read_binary_stl(bytes, file, unit_scale) : read_ascii_stl(bytes, file, unit_scale);
  if (mesh.triangles.empty()) throw InputError({file, 0, 0}, {}, "the mesh has no triangles");
  return mesh;
}

void write_stl(const TriangleMesh& mesh, const std::filesystem::path& path) {
  std::string out(80, '\0');
  const std::string header = "beadtwin binary STL";
  out.replace(0, header.size(), header);
  const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
  out.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d& b = mesh.vertices[static_cast<std::size_t>(t[1])];
    const Eigen::Vector3d& c = mesh.vertices[static_cast<std::size_t>(t[2])];
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    float rec[12] = {float(n.x()), float(n.y()), float(n.z()), float(a.x()), float(a.y()), float(a.z()),
                     float(b.x()), float(b.y()), float(b.z()), float(c.x()), float(c.y()), float(c.z())};
    out.append(reinterpret_cast<const char*>(rec), sizeof rec);
    out.append(2, '\0');
  }
  write_file_atomic(path, out);
}

namespace {

// Adds an axis-aligned quad (CCW seen from outside) as two triangles.
void add_quad(TriangleMesh& m, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
              const Eigen::Vector3d& d) {
  const int base = static_cast<int>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), {a, b, c, d});
  m.triangles.push_back({base, base + 1, base + 2});
  m.triangles.push_back({base, base + 2, base + 3});
}

// Adds the closed, outward-facing surface of the box [lo, hi].
void add_box(TriangleMesh& m, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, bool inward) {
  const double x0 = lo.x(), y0 = lo.y(), z0 = lo.z(), x1 = hi.x(), y1 = hi.y(), z1 = hi.z();
  using V = Eigen::Vector3d;
  const std::size_t first = m.triangles.size();
  add_quad(m, V(x0, y0, z0), V(x0, y1, z0), V(x1, y1, z0), V(x1, y0, z0));  // bottom (-z)
  add_quad(m, V(x0, y0, z1), V(x1, y0, z1), V(x1, y1, z1), V(x0, y1, z1));  // top (+z)
  add_quad(m, V(x0, y0, z0), V(x1, y0, z0), V(x1, y0, z1), V(x0, y0, z1));  // -y
  add_quad(m, V(x0, y1, z0), V(x0, y1, z1), V(x1, y1, z1), V(x1, y1, z0));  // +y
  add_quad(m, V(x0, y0, z0), V(x0, y0, z1), V(x0, y1, z1), V(x0, y1, z0));  // -x
  add_quad(m, V(x1, y0, z0), V(x1, y1, z0), V(x1, y1, z1), V(x1, y0, z1));  // +x
  if (inward)
    for (std::size_t i = first; i < m.triangles.size(); ++i) std::swap(m.triangles[i][1], m.triangles[i][2]);
}

// Merges vertices with equal coordinates so triangles share edges, as slicing needs.
TriangleMesh weld(const TriangleMesh& m) {
  TriangleMesh welded;
  Welder welder(welded);
  for (const auto& t : m.triangles) {
    std::array<int, 3> nt{};
    for (std::size_t c = 0; c < 3; ++c) nt[c] = welder.add(m.vertices[static_cast<std::size_t>(t[c])]);
    welded.triangles.push_back(nt);
  }
  return welded;
}

}  // namespace

TriangleMesh make_box(const Eigen::Vector3d& size, const Eigen::Vector3d& origin) {
  TriangleMesh m;
  add_box(m, origin, origin + size, false);
  return weld(m);
}

TriangleMesh make_open_box(const Eigen::Vector3d& size, double wall_mm, double floor_mm,
                           const Eigen::Vector3d& origin) {
  // The solid is the outer box minus the cavity box that pokes out through the top. Built as the outer
  // box's faces except its top, the cavity's faces (inward) except its top, and the rim ring on top.
  using V = Eigen::Vector3d;
  const V lo = origin, hi = origin + size;
  const V clo(lo.x() + wall_mm, lo.y() + wall_mm, lo.z() + floor_mm);
  const V chi(hi.x() - wall_mm, hi.y() - wall_mm, hi.z());
  TriangleMesh outer, cavity;
  add_box(outer, lo, hi, false);
  add_box(cavity, clo, chi, true);
  TriangleMesh m;
  auto copy_except_top = [&m](const TriangleMesh& src) {
    for (std::size_t t = 0; t < src.triangles.size(); ++t) {
      if (t == 2 || t == 3) continue;  // the top quad is the second one added
      const int base = static_cast<int>(m.vertices.size());
      for (int c = 0; c < 3; ++c)
        m.vertices.push_back(
            src.vertices[static_cast<std::size_t>(src.triangles[t][static_cast<std::size_t>(c)])]);
      m.triangles.push_back({base, base + 1, base + 2});
    }
  };
  copy_except_top(outer);
  copy_except_top(cavity);
  const double z = hi.z();
  // Rim: four quads between the outer and inner top outlines, facing +z.
  add_quad(m, V(lo.x(), lo.y(), z), V(hi.x(), lo.y(), z), V(chi.x(), clo.y(), z), V(clo.x(), clo.y(), z));
  add_quad(m, V(hi.x(), lo.y(), z), V(hi.x(), hi.y(), z), V(chi.x(), chi.y(), z), V(chi.x(), clo.y(), z));
  add_quad(m, V(hi.x(), hi.y(), z), V(lo.x(), hi.y(), z), V(clo.x(), chi.y(), z), V(chi.x(), chi.y(), z));
  add_quad(m, V(lo.x(), hi.y(), z), V(lo.x(), lo.y(), z), V(clo.x(), clo.y(), z), V(clo.x(), chi.y(), z));
  return weld(m);
}

}  // namespace beadtwin::slicer
