#include "slicer/mesh.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <string_view>
#include <system_error>
#include <vector>

#include <assimp/scene.h>
#include <fmt/format.h>
#include <Eigen/Geometry>
#include <assimp/Importer.hpp>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/memory.hpp"
#include "slicer/mesh_repair.hpp"
#include "slicer/ply.hpp"
#include "slicer/triangulate.hpp"

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

// Names assimp's loaders give nodes and meshes when the file names none.
bool is_placeholder_name(std::string_view name) {
  return name.empty() || name.front() == '<' || name == "defaultobject";
}

Eigen::Affine3d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  for (unsigned r = 0; r < 4; ++r)
    for (unsigned c = 0; c < 4; ++c) e(r, c) = static_cast<double>(m[r][c]);
  return Eigen::Affine3d(e);
}

// Gathers an assimp scene's triangles into one mesh with a body per node that holds meshes, node transforms
// baked in and coordinates scaled to mm. Nothing is repaired here.
class SceneReader {
 public:
  SceneReader(const aiScene& scene, std::string file, double scale)
      : scene_(scene), file_(std::move(file)), scale_(scale) {}

  void read_node(const aiNode& node, const Eigen::Affine3d& parent) {
    const Eigen::Affine3d transform = parent * to_eigen(node.mTransformation);
    const int body = static_cast<int>(mesh_.body_names.size());
    const std::size_t first_triangle = mesh_.triangles.size();
    std::string name = node.mName.C_Str();
    for (unsigned i = 0; i < node.mNumMeshes; ++i) {
      const aiMesh& m = mesh(node.mMeshes[i]);
      if (is_placeholder_name(name)) name = m.mName.C_Str();
      read_mesh_faces(m, transform, body);
    }
    // A node whose meshes hold no triangles (only points and lines, or nothing) is no body.
    if (mesh_.triangles.size() > first_triangle)
      mesh_.body_names.push_back(is_placeholder_name(name) ? std::string() : name);
    for (unsigned i = 0; i < node.mNumChildren; ++i) read_node(*node.mChildren[i], transform);
  }

  int ignored_primitives() const { return ignored_; }

  // The gathered mesh, its unnamed bodies named after the file and every name made unique.
  TriangleMesh take(const std::string& stem) {
    std::set<std::string> seen;
    for (std::size_t b = 0; b < mesh_.body_names.size(); ++b) {
      std::string& name = mesh_.body_names[b];
      if (name.empty()) name = mesh_.body_names.size() == 1 ? stem : fmt::format("{} {}", stem, b + 1);
      const std::string base = name;
      for (int k = 2; !seen.insert(name).second; ++k) name = fmt::format("{} #{}", base, k);
    }
    return std::move(mesh_);
  }

 private:
  const aiMesh& mesh(unsigned index) const {
    if (index >= scene_.mNumMeshes || !scene_.mMeshes[index])
      throw InputError({file_, 0, 0}, {}, fmt::format("the file refers to mesh {} it does not hold", index));
    return *scene_.mMeshes[index];
  }

  void read_mesh_faces(const aiMesh& m, const Eigen::Affine3d& transform, int body) {
    const int base = static_cast<int>(mesh_.vertices.size());
    for (unsigned v = 0; v < m.mNumVertices; ++v) {
      const aiVector3D& p = m.mVertices[v];
      mesh_.vertices.push_back(
          transform *
          Eigen::Vector3d(static_cast<double>(p.x), static_cast<double>(p.y), static_cast<double>(p.z)) *
          scale_);
    }
    used_.assign(m.mNumVertices, false);
    std::vector<Eigen::Vector3d> corners;
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
      const aiFace& face = m.mFaces[f];
      if (face.mNumIndices < 3 || !face.mIndices) {  // points and lines bound no solid
        ++ignored_;
        continue;
      }
      corners.clear();
      for (unsigned c = 0; c < face.mNumIndices; ++c) {
        const unsigned v = face.mIndices[c];
        if (v >= m.mNumVertices)
          throw InputError(
              {file_, 0, 0}, {},
              fmt::format("a face of mesh '{}' refers to vertex {}, but the mesh has {} vertices",
                          m.mName.C_Str(), v, m.mNumVertices));
        if (!used_[v]) check_finite(m, v, mesh_.vertices[static_cast<std::size_t>(base) + v]);
        used_[v] = true;
        if (face.mNumIndices > 3) corners.push_back(mesh_.vertices[static_cast<std::size_t>(base) + v]);
      }
      const auto corner = [&](int c) { return base + static_cast<int>(face.mIndices[c]); };
      if (face.mNumIndices == 3) {
        mesh_.triangles.push_back({corner(0), corner(1), corner(2)});
        mesh_.body.push_back(body);
        continue;
      }
      for (const auto& t : triangulate_polygon(corners)) {
        mesh_.triangles.push_back({corner(t[0]), corner(t[1]), corner(t[2])});
        mesh_.body.push_back(body);
      }
    }
  }

  // Checks the coordinates as the file gives them (a transform would spread a NaN to all three) and as
  // placed and scaled.
  void check_finite(const aiMesh& m, unsigned v, const Eigen::Vector3d& placed) const {
    const aiVector3D& p = m.mVertices[v];
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && placed.allFinite()) return;
    const std::string where =
        is_placeholder_name(m.mName.C_Str()) ? "" : fmt::format(" in mesh '{}'", m.mName.C_Str());
    throw InputError({file_, 0, 0}, {},
                     fmt::format("a vertex{} has a coordinate that is not a finite number: ({}, {}, {})",
                                 where, p.x, p.y, p.z));
  }

  const aiScene& scene_;
  std::string file_;
  double scale_;
  TriangleMesh mesh_;
  std::vector<bool> used_;  // per vertex of the mesh being read: checked already
  int ignored_ = 0;
};

// assimp's message, cut short: some quote the rest of the file.
std::string assimp_message(const Assimp::Importer& importer) {
  constexpr std::size_t kMaxChars = 200;
  std::string message = importer.GetErrorString();
  if (message.size() > kMaxChars) message = message.substr(0, kMaxChars) + "...";
  return message;
}

// The file's extension in lower case, with its dot: ".stl".
std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// The first `bytes` bytes of the file (fewer if it is shorter).
std::string read_start(const std::filesystem::path& path, std::uintmax_t bytes) {
  std::ifstream in(path, std::ios::binary);
  std::string data(bytes, '\0');
  in.read(data.data(), static_cast<std::streamsize>(data.size()));
  data.resize(static_cast<std::size_t>(in.gcount()));
  return data;
}

// The triangle count of a binary STL: the little-endian 32-bit word after the 80-byte header in `head`
// (at least 84 bytes).
std::uint32_t binary_stl_count(const std::string& head) {
  std::uint32_t count = 0;
  for (int i = 0; i < 4; ++i) count |= std::uint32_t{static_cast<unsigned char>(head[80 + i])} << (8 * i);
  return count;
}

// An STL file's own account of itself, checked before assimp reads it (whose messages for a broken STL
// speak of its "storage representation"): ASCII begins "solid" and has facets; binary is an 80-byte
// header, a triangle count and 50 bytes per triangle.
void check_stl(const std::filesystem::path& path, std::uintmax_t bytes, const std::string& head) {
  if (lower_extension(path) != ".stl") return;
  if (head.starts_with("solid") && head.find("facet") != std::string::npos) return;  // ASCII
  const std::string file = path.string();
  if (bytes < 84)
    throw InputError({file, 0, 0}, {},
                     fmt::format("not an STL: {} bytes, shorter than a binary STL's 84-byte header, and not "
                                 "ASCII STL (\"solid\" and facets)",
                                 bytes));
  const std::uint32_t count = binary_stl_count(head);
  const std::uintmax_t expected = 84 + 50 * std::uintmax_t{count};
  if (count == 0) throw InputError({file, 0, 0}, {}, "the binary STL holds no triangles");
  if (bytes < expected && expected / 64 > bytes)  // far beyond the file: a count read from other data
    throw InputError(
        {file, 0, 0}, {},
        fmt::format("not an STL: as binary STL its header would count {} triangles ({} bytes) in a "
                    "file of {} bytes; and it is not ASCII STL (\"solid\" and facets)",
                    count, expected, bytes));
  if (bytes < expected)
    throw InputError(
        {file, 0, 0}, {},
        fmt::format("truncated binary STL: its header counts {} triangles ({} bytes), the file has {} bytes "
                    "({} whole triangles)",
                    count, expected, bytes, (bytes - 84) / 50));
  if (bytes > expected + 1024)  // some writers pad; more than that is not this format
    throw InputError(
        {file, 0, 0}, {},
        fmt::format("not an STL: as binary STL its header counts {} triangles ({} bytes) but the "
                    "file has {} bytes; and it is not ASCII STL (\"solid\" and facets)",
                    count, expected, bytes));
}

// Stops before reading a mesh that would not fit in memory (read_mesh_cost says how it is estimated).
void check_memory(const std::filesystem::path& path, std::uintmax_t bytes, const std::string& head,
                  double budget_bytes) {
  const double estimate = read_mesh_cost(path, bytes, head).bytes();
  const double budget = memory_budget_bytes(budget_bytes);
  if (estimate <= budget) return;
  throw InputError(
      {path.string(), 0, 0}, {},
      fmt::format(
          "the mesh file is {:.3g} MB; reading it would take about {:.3g} GB of memory, more than the "
          "{:.3g} GB budget (output.memory_budget, or three quarters of this machine's memory). "
          "Decimate it first (for example MeshLab's quadric edge collapse): beads millimetres wide "
          "need no triangles smaller than a millimetre",
          static_cast<double>(bytes) / 1e6, estimate / 1e9, budget / 1e9));
}

// The file's triangles as it gives them, polygons triangulated, before any repair: PLY by read_ply, every
// other format by assimp.
TriangleMesh import_scene(const std::filesystem::path& path, double unit_scale, double budget_bytes,
                          MeshReport& report) {
  const std::string file = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError({file, 0, 0}, {},
                     std::filesystem::exists(path, ec) ? "not a regular file" : "no such mesh file");
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (bytes == 0) throw InputError({file, 0, 0}, {}, "the mesh file is empty");
  // The file's start, read once for the checks: STL's header, and PLY's signature.
  const std::string head = read_start(path, std::min<std::uintmax_t>(bytes, 4096));
  check_stl(path, bytes, head);
  check_memory(path, bytes, head, budget_bytes);
  // PLY by its name or its first line (as assimp would also take it), read by our own reader.
  if (lower_extension(path) == ".ply" || head.starts_with("ply")) {
    PlyMesh ply = read_ply(file, read_start(path, bytes), unit_scale);
    report.ignored_primitives = ply.ignored_faces;
    if (!ply.mesh.body_names.empty()) ply.mesh.body_names[0] = path.stem().string();
    return std::move(ply.mesh);
  }
  // No post-processing: polygons are cut by SceneReader (triangulate_polygon says why), and joining
  // vertices, dropping degenerates and fixing normals are done (and counted) by repair_mesh, which assimp's
  // own steps would do silently.
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(file, 0);
  if (!scene || !scene->mRootNode)
    throw InputError({file, 0, 0}, {}, fmt::format("cannot read the mesh: {}", assimp_message(importer)));
  SceneReader reader(*scene, file, unit_scale);
  reader.read_node(*scene->mRootNode, Eigen::Affine3d::Identity());
  report.ignored_primitives = reader.ignored_primitives();
  return reader.take(path.stem().string());
}

void check_size(const TriangleMesh& mesh, const std::string& file) {
  const Eigen::Vector3d size = mesh.max_corner() - mesh.min_corner();
  if (size.maxCoeff() > kMaxPartSizeMm)
    throw InputError(
        {file, 0, 0}, {},
        fmt::format("the part is {:.4g} x {:.4g} x {:.4g} m, larger than {:g} m; are the mesh units right?",
                    size.x() / 1000, size.y() / 1000, size.z() / 1000, kMaxPartSizeMm / 1000));
}

}  // namespace

MemoryCost read_mesh_cost(const std::filesystem::path& path, std::uintmax_t file_bytes,
                          const std::string& head) {
  // Measured (docs/RELIABILITY.md): a peak of 232 bytes a triangle reading a 2-million-triangle sphere as
  // binary STL, and 7.7 bytes a byte of file for the same sphere as OBJ; denser files hold more triangles a
  // byte.
  constexpr double kBytesPerStlTriangle = 300.0, kBytesPerFileByte = 24.0;
  if (lower_extension(path) == ".stl" && head.size() >= 84 && !head.starts_with("solid"))
    return {.fixed_bytes = binary_stl_count(head) * kBytesPerStlTriangle};
  return {.fixed_bytes = static_cast<double>(file_bytes) * kBytesPerFileByte};
}

TriangleMesh read_mesh(const std::filesystem::path& path, double unit_scale, MeshReport* report,
                       double budget_bytes) {
  const std::string file = path.string();
  if (!(unit_scale > 0) || !std::isfinite(unit_scale))
    throw InputError({file, 0, 0}, {},
                     fmt::format("the mesh unit scale must be positive, got {}", unit_scale));
  MeshReport local;
  MeshReport& r = report ? *report : local;
  r = MeshReport{};
  const TriangleMesh raw = import_scene(path, unit_scale, budget_bytes, r);
  if (raw.triangles.empty())
    throw InputError({file, 0, 0}, {},
                     r.ignored_primitives > 0 ? "the file holds points or lines but no triangles"
                                              : "the file holds no triangles");
  check_size(raw, file);
  TriangleMesh mesh = repair_mesh(raw, r);
  if (mesh.triangles.empty())
    throw InputError({file, 0, 0}, {},
                     fmt::format("no triangles are left after repair: all {} were degenerate or duplicates",
                                 raw.triangles.size()));
  add_repair_warnings(r, file);
  for (const std::string& name : raw.body_names)
    if (find_body(mesh, name) < 0)
      r.warnings.push_back(
          fmt::format("{}: body '{}' has no triangles left after repair and was dropped", file, name));
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

TriangleMesh select_body(const TriangleMesh& mesh, int body) {
  const bool tagged = !mesh.body.empty();
  BT_CHECK(!tagged || mesh.body.size() == mesh.triangles.size());
  BT_CHECK(body >= 0 && static_cast<std::size_t>(body) < std::max<std::size_t>(mesh.body_names.size(), 1));
  TriangleMesh out;
  out.body_names = {mesh.body_names.empty() ? std::string("part")
                                            : mesh.body_names[static_cast<std::size_t>(body)]};
  std::vector<int> index(mesh.vertices.size(), -1);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    if (tagged && mesh.body[f] != body) continue;
    std::array<int, 3> t{};
    for (std::size_t c = 0; c < 3; ++c) {
      int& v = index[static_cast<std::size_t>(mesh.triangles[f][c])];
      if (v < 0) {
        v = static_cast<int>(out.vertices.size());
        out.vertices.push_back(mesh.vertices[static_cast<std::size_t>(mesh.triangles[f][c])]);
      }
      t[c] = v;
    }
    out.triangles.push_back(t);
    out.body.push_back(0);
  }
  return out;
}

TriangleMesh lay_down(const TriangleMesh& mesh, SlicePlane plane) {
  if (plane == SlicePlane::kTop || mesh.vertices.empty()) return mesh;
  const Eigen::Vector3d before = mesh.min_corner();
  TriangleMesh out = mesh;
  for (Eigen::Vector3d& v : out.vertices)
    v = plane == SlicePlane::kFront ? Eigen::Vector3d(v.x(), -v.z(), v.y())   // +90° about X
                                    : Eigen::Vector3d(-v.z(), v.y(), v.x());  // −90° about Y
  const Eigen::Vector3d shift = before - out.min_corner();
  for (Eigen::Vector3d& v : out.vertices) v += shift;
  return out;
}

int find_body(const TriangleMesh& mesh, std::string_view name) {
  const auto it = std::find(mesh.body_names.begin(), mesh.body_names.end(), name);
  return it == mesh.body_names.end() ? -1 : static_cast<int>(it - mesh.body_names.begin());
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

// Merges vertices with equal coordinates so triangles share edges, as slicing needs; one body, "part".
TriangleMesh weld(const TriangleMesh& m) {
  TriangleMesh welded;
  std::map<std::array<double, 3>, int> index;
  for (const auto& t : m.triangles) {
    std::array<int, 3> nt{};
    for (std::size_t c = 0; c < 3; ++c) {
      const Eigen::Vector3d& p = m.vertices[static_cast<std::size_t>(t[c])];
      auto [it, inserted] =
          index.try_emplace({p.x(), p.y(), p.z()}, static_cast<int>(welded.vertices.size()));
      if (inserted) welded.vertices.push_back(p);
      nt[c] = it->second;
    }
    welded.triangles.push_back(nt);
  }
  welded.body.assign(welded.triangles.size(), 0);
  welded.body_names = {"part"};
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
  return make_open_box(size, std::vector<WallTier>{{size.z(), wall_mm}}, floor_mm, origin);
}

TriangleMesh make_open_box(const Eigen::Vector3d& size, const std::vector<WallTier>& tiers, double floor_mm,
                           const Eigen::Vector3d& origin) {
  // The outer box's faces except its top; for each tier the cavity's side faces (facing in); the cavity's
  // floor; between tiers the ledge ring (facing up where the wall above is thinner, down where it is
  // thicker: an overhang); and the rim ring on top.
  using V = Eigen::Vector3d;
  const V lo = origin, hi = origin + size;
  TriangleMesh m;
  {
    TriangleMesh outer;
    add_box(outer, lo, hi, false);
    for (std::size_t t = 0; t < outer.triangles.size(); ++t) {
      if (t == 2 || t == 3) continue;  // the top quad is the second one added
      const int base = static_cast<int>(m.vertices.size());
      for (std::size_t c = 0; c < 3; ++c)
        m.vertices.push_back(outer.vertices[static_cast<std::size_t>(outer.triangles[t][c])]);
      m.triangles.push_back({base, base + 1, base + 2});
    }
  }
  // Rectangle inset by `w` at height z, corners counter-clockwise from the minimum corner.
  const auto rect = [&](double w, double z) {
    return std::array<V, 4>{V(lo.x() + w, lo.y() + w, z), V(hi.x() - w, lo.y() + w, z),
                            V(hi.x() - w, hi.y() - w, z), V(lo.x() + w, hi.y() - w, z)};
  };
  // The ring between rectangles `a` (outer) and `b` (inner) at one height, facing up or down.
  const auto ring = [&](const std::array<V, 4>& a, const std::array<V, 4>& b, bool up) {
    for (std::size_t i = 0; i < 4; ++i) {
      const std::size_t j = (i + 1) % 4;
      if (up)
        add_quad(m, a[i], a[j], b[j], b[i]);
      else
        add_quad(m, a[i], b[i], b[j], a[j]);
    }
  };
  double z0 = lo.z() + floor_mm;
  {
    const auto f = rect(tiers.front().wall_mm, z0);
    add_quad(m, f[0], f[1], f[2], f[3]);  // cavity floor, facing up
  }
  for (std::size_t k = 0; k < tiers.size(); ++k) {
    const double w = tiers[k].wall_mm;
    const double z1 = k + 1 == tiers.size() ? hi.z() : lo.z() + tiers[k].z_top_mm;
    const auto b = rect(w, z0), t = rect(w, z1);
    for (std::size_t i = 0; i < 4; ++i)
      add_quad(m, b[i], t[i], t[(i + 1) % 4], b[(i + 1) % 4]);  // faces the cavity
    if (k + 1 < tiers.size() && tiers[k + 1].wall_mm != w) {
      const double w_next = tiers[k + 1].wall_mm;
      if (w_next < w)
        ring(rect(w_next, z1), t, true);  // a ledge on the wall below
      else
        ring(t, rect(w_next, z1), false);  // the underside of a thicker wall above
    }
    z0 = z1;
  }
  ring(rect(0.0, hi.z()), rect(tiers.back().wall_mm, hi.z()), true);  // the rim
  return weld(m);
}

std::string body_list(const TriangleMesh& mesh) {
  std::string names;
  for (const auto& n : mesh.body_names) names += (names.empty() ? "" : ", ") + n;
  return names.empty() ? std::string("part") : names;
}

}  // namespace beadtwin::slicer
