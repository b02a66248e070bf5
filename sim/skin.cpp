#include "sim/skin.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>
#include <meshoptimizer.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/parallel_for.h>

#include "core/atomic_file.hpp"

namespace beadtwin::sim {
namespace {

static_assert(std::endian::native == std::endian::little,
              "PLY and STL are written as little-endian: the machine's bytes are copied as they are");

constexpr double kIsoFill = 0.5;  // half full: the surface between material and air

// The triangles of quad (a, b, c, d), split along its shorter diagonal (the better shaped pair), keeping
// the quad's winding.
std::array<openvdb::Vec3I, 2> split_quad(const openvdb::Vec4I& q, const std::vector<openvdb::Vec3s>& p) {
  const float ac = (p[q[2]] - p[q[0]]).lengthSqr();
  const float bd = (p[q[3]] - p[q[1]]).lengthSqr();
  if (ac <= bd) return {openvdb::Vec3I(q[0], q[1], q[2]), openvdb::Vec3I(q[0], q[2], q[3])};
  return {openvdb::Vec3I(q[0], q[1], q[3]), openvdb::Vec3I(q[1], q[2], q[3])};
}

bool degenerate(const openvdb::Vec3I& t) {
  return t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
}

// volumeToMesh winds its polygons clockwise seen from outside (Houdini's convention; for a fog volume it
// inverts its level-set test so that outside stays outside). STL and PLY take counter-clockwise: swap two
// corners. Points no triangle uses (adaptive meshing leaves some) are dropped.
SkinMesh outward_triangles(const std::vector<openvdb::Vec3s>& points,
                           const std::vector<openvdb::Vec3I>& triangles,
                           const std::vector<openvdb::Vec4I>& quads, bool swap = true) {
  constexpr auto kUnused = std::numeric_limits<openvdb::Index32>::max();
  SkinMesh mesh;
  std::vector<openvdb::Index32> new_index(points.size(), kUnused);
  const auto add = [&](const openvdb::Vec3I& t) {
    if (degenerate(t)) return;
    openvdb::Vec3I out;
    for (int c = 0; c < 3; ++c) {
      openvdb::Index32& n = new_index[t[c]];
      if (n == kUnused) {
        n = static_cast<openvdb::Index32>(mesh.points_mm.size());
        mesh.points_mm.push_back(points[t[c]]);
      }
      out[c] = n;
    }
    if (swap) {
      mesh.triangles.emplace_back(out[0], out[2], out[1]);
    } else {
      mesh.triangles.emplace_back(out[0], out[1], out[2]);
    }
  };
  mesh.triangles.reserve(triangles.size() + 2 * quads.size());
  for (const openvdb::Vec3I& t : triangles) add(t);
  for (const openvdb::Vec4I& q : quads)
    for (const openvdb::Vec3I& t : split_quad(q, points)) add(t);
  return mesh;
}

// Connected pieces of the mesh (triangles sharing a point) whose signed volume is negative face into a
// void inside the part: dropped, with the points only they used.
void drop_void_shells(SkinMesh& mesh) {
  std::vector<openvdb::Index32> parent(mesh.points_mm.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<openvdb::Index32>(i);
  const auto find = [&parent](openvdb::Index32 i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const openvdb::Vec3I& t : mesh.triangles) {
    const openvdb::Index32 a = find(t[0]);
    for (int c = 1; c < 3; ++c) {
      const openvdb::Index32 b = find(t[c]);
      if (a != b) parent[b] = a;
    }
  }
  std::vector<double> six_v(mesh.points_mm.size(), 0.0);  // by piece root
  for (const openvdb::Vec3I& t : mesh.triangles) {
    const openvdb::Vec3d a(mesh.points_mm[t[0]]), b(mesh.points_mm[t[1]]), c(mesh.points_mm[t[2]]);
    six_v[find(t[0])] += a.dot(b.cross(c));
  }
  std::vector<openvdb::Vec3I> kept;
  kept.reserve(mesh.triangles.size());
  for (const openvdb::Vec3I& t : mesh.triangles)
    if (six_v[find(t[0])] > 0.0) kept.push_back(t);
  mesh = outward_triangles(mesh.points_mm, kept, {}, false);
}

// A large mesh is simplified in slabs at once (up to kSimplifyPieces, one for every kTrianglesPerPiece
// triangles), cut across its longest side by the triangles' centroids, each with the vertices on its cut
// edges held where they are (so the slabs still meet): meshoptimizer's simplification runs on one thread,
// and on a mesh of millions of triangles it is most of the skin's time. The cuts are at fixed fractions of
// the box, so the result does not depend on the threads; a mesh below kTrianglesPerPiece is simplified
// whole. Each slab is simplified over its own vertices only: meshoptimizer builds its tables over every
// vertex it is given. Eight slabs share out evenly between the threads; more are cheaper still but hold
// more seams fixed, and so more triangles (docs/PERFORMANCE.md, the skin's simplification).
constexpr std::size_t kSimplifyPieces = 8;
constexpr std::size_t kTrianglesPerPiece = 500'000;

// Drops every pair of triangles on the same three corners wound opposite ways: a fold of no thickness, which
// encloses nothing and makes each of its edges shared by four triangles. meshoptimizer's collapses leave such
// pairs where two sheets of the surface close up and along the slabs' seams on flat faces (most of the edges
// such a mesh shares between four triangles; the rest are where two sheets touch along an edge, which is
// still a closed surface); the unsimplified mesh has none.
void drop_folds(std::vector<openvdb::Vec3I>& triangles) {
  struct Key {
    std::array<unsigned, 3> corners;  // sorted
    bool odd;                         // the winding against the sorted order
    std::size_t index;
  };
  std::vector<Key> keys(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const openvdb::Vec3I& t = triangles[i];
    // Rotated to start at its smallest corner (a rotation keeps the winding), then compared with sorted.
    const int first = t[0] < t[1] ? (t[0] < t[2] ? 0 : 2) : (t[1] < t[2] ? 1 : 2);
    const unsigned b = t[(first + 1) % 3], c = t[(first + 2) % 3];
    keys[i] = {{t[first], std::min(b, c), std::max(b, c)}, b > c, i};
  }
  std::sort(keys.begin(), keys.end(), [](const Key& x, const Key& y) {
    return std::tie(x.corners, x.odd, x.index) < std::tie(y.corners, y.odd, y.index);
  });
  std::vector<char> dropped(triangles.size(), 0);
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i;
    while (j < keys.size() && keys[j].corners == keys[i].corners) ++j;
    // Within a run of one corner set, the even windings come first: pair them off with the odd ones.
    std::size_t even = i, odd = i;
    while (odd < j && !keys[odd].odd) ++odd;
    for (std::size_t k = odd; even < odd && k < j; ++even, ++k)
      dropped[keys[even].index] = dropped[keys[k].index] = 1;
    i = j;
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < triangles.size(); ++i)
    if (!dropped[i]) triangles[kept++] = triangles[i];
  triangles.resize(kept);
}

// Collapses edges (quadric error metric, meshoptimizer) while the surface moves less than `tolerance_mm`:
// flat and gently curved stretches become a few long triangles, the ridges between beads stay.
void simplify(SkinMesh& mesh, double tolerance_mm) {
  if (mesh.triangles.empty()) return;
  static_assert(sizeof(openvdb::Vec3s) == 3 * sizeof(float) &&
                sizeof(openvdb::Vec3I) == 3 * sizeof(unsigned));
  const std::size_t count =
      std::clamp<std::size_t>(mesh.triangles.size() / kTrianglesPerPiece, 1, kSimplifyPieces);
  openvdb::BBoxd box;
  if (count > 1)
    for (const openvdb::Vec3s& p : mesh.points_mm) box.expand(openvdb::Vec3d(p));
  const std::size_t axis = count > 1 ? box.maxExtent() : 0;
  const double low = box.min()[axis], extent = count > 1 ? box.extents()[axis] : 0.0;
  std::vector<std::vector<unsigned>> pieces(count);
  for (const openvdb::Vec3I& t : mesh.triangles) {
    const double centre =
        (mesh.points_mm[t[0]][axis] + mesh.points_mm[t[1]][axis] + mesh.points_mm[t[2]][axis]) / 3.0;
    const double at = extent > 0 ? (centre - low) / extent * static_cast<double>(count) : 0.0;
    std::vector<unsigned>& piece = pieces[std::min(count - 1, static_cast<std::size_t>(std::max(0.0, at)))];
    piece.insert(piece.end(), {t[0], t[1], t[2]});
  }
  const unsigned options = count > 1 ? meshopt_SimplifyLockBorder : 0;
  tbb::parallel_for(std::size_t{0}, count, [&](std::size_t k) {
    std::vector<unsigned>& indices = pieces[k];
    if (indices.empty()) return;
    // The slab's vertices, in the mesh's order, and its triangles renumbered to them.
    std::vector<unsigned> own(indices);
    std::sort(own.begin(), own.end());
    own.erase(std::unique(own.begin(), own.end()), own.end());
    std::vector<openvdb::Vec3s> points(own.size());
    for (std::size_t i = 0; i < own.size(); ++i) points[i] = mesh.points_mm[own[i]];
    for (unsigned& v : indices)
      v = static_cast<unsigned>(std::lower_bound(own.begin(), own.end(), v) - own.begin());
    // meshoptimizer takes the error relative to the extent of the vertices it is given; a slab of no
    // extent is left as it is.
    const float reach = meshopt_simplifyScale(points[0].asPointer(), points.size(), sizeof(openvdb::Vec3s));
    if (!(reach > 0.0f)) {
      for (unsigned& v : indices) v = own[v];
      return;
    }
    std::vector<unsigned> out(indices.size());
    out.resize(meshopt_simplify(out.data(), indices.data(), indices.size(), points[0].asPointer(),
                                points.size(), sizeof(openvdb::Vec3s), 0,
                                static_cast<float>(tolerance_mm) / reach, options));
    for (unsigned& v : out) v = own[v];
    indices.swap(out);
  });
  std::vector<openvdb::Vec3I> triangles;
  for (const std::vector<unsigned>& indices : pieces)
    for (std::size_t i = 0; i + 2 < indices.size(); i += 3)
      triangles.emplace_back(indices[i], indices[i + 1], indices[i + 2]);
  drop_folds(triangles);
  mesh = outward_triangles(mesh.points_mm, triangles, {}, false);
}

template <class T>
void put(std::ostream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof value);
}

void write_ply(const SkinMesh& mesh, std::ostream& out) {
  out << "ply\nformat binary_little_endian 1.0\n"
      << "comment beadtwin as-printed skin: the iso-surface fill = 0.5 of the deposit, lengths in mm\n"
      << "element vertex " << mesh.points_mm.size()
      << "\nproperty float x\nproperty float y\nproperty float z\n"
      << "element face " << mesh.triangles.size()
      << "\nproperty list uchar uint vertex_indices\nend_header\n";
  for (const openvdb::Vec3s& p : mesh.points_mm) out.write(reinterpret_cast<const char*>(p.asPointer()), 12);
  for (const openvdb::Vec3I& t : mesh.triangles) {
    put(out, std::uint8_t{3});
    out.write(reinterpret_cast<const char*>(t.asPointer()), 12);
  }
}

void write_stl(const SkinMesh& mesh, std::ostream& out, const std::filesystem::path& path) {
  if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument(
        fmt::format("cannot write {}: {} triangles are more than binary STL can count", path.string(),
                    mesh.triangles.size()));
  // An ASCII STL starts with "solid"; this header must not.
  std::array<char, 80> header{};
  const std::string_view text = "beadtwin as-printed skin (iso-surface fill = 0.5 of the deposit), mm";
  std::memcpy(header.data(), text.data(), text.size());
  out.write(header.data(), header.size());
  put(out, static_cast<std::uint32_t>(mesh.triangles.size()));
  std::array<char, 50> facet{};  // normal, three corners (float32 x 3 each), attribute count (uint16 0)
  for (const openvdb::Vec3I& t : mesh.triangles) {
    const openvdb::Vec3s& a = mesh.points_mm[t[0]];
    const openvdb::Vec3s& b = mesh.points_mm[t[1]];
    const openvdb::Vec3s& c = mesh.points_mm[t[2]];
    openvdb::Vec3s n = (b - a).cross(c - a);
    n.normalize();  // leaves a zero normal as it is
    std::memcpy(facet.data(), n.asPointer(), 12);
    std::memcpy(facet.data() + 12, a.asPointer(), 12);
    std::memcpy(facet.data() + 24, b.asPointer(), 12);
    std::memcpy(facet.data() + 36, c.asPointer(), 12);
    out.write(facet.data(), facet.size());
  }
}

}  // namespace

FillSurface mesh_fill(const Deposit& deposit, double adaptivity) {
  if (!(adaptivity >= 0.0 && adaptivity <= 1.0))
    throw std::invalid_argument(fmt::format("skin adaptivity must be between 0 and 1, got {}", adaptivity));
  FillSurface out;
  if (!deposit.fill || deposit.fill->activeVoxelCount() == 0) return out;
  // The mesher treats grids that are not level sets as fog volumes (inside above the iso value); say so
  // whatever the caller's grid claims.
  openvdb::FloatGrid::ConstPtr fill = deposit.fill;
  if (fill->getGridClass() != openvdb::GRID_FOG_VOLUME) {
    openvdb::FloatGrid::Ptr fog = deposit.fill->copy();  // shares the tree
    fog->setGridClass(openvdb::GRID_FOG_VOLUME);
    fill = fog;
  }
  openvdb::tools::volumeToMesh(*fill, out.points_mm, out.triangles, out.quads, kIsoFill, adaptivity);
  return out;
}

SkinMesh extract_skin(const FillSurface& surface, bool outer_only, double tolerance_mm) {
  SkinMesh mesh = outward_triangles(surface.points_mm, surface.triangles, surface.quads);
  if (outer_only) drop_void_shells(mesh);
  if (tolerance_mm > 0.0) simplify(mesh, tolerance_mm);
  return mesh;
}

SkinMesh extract_skin(const Deposit& deposit, double adaptivity, bool outer_only, double tolerance_mm) {
  return extract_skin(mesh_fill(deposit, adaptivity), outer_only, tolerance_mm);
}

double enclosed_volume_mm3(const SkinMesh& mesh) {
  // Sum of the signed tetrahedra between the origin and each triangle.
  double six_v = 0.0;
  for (const openvdb::Vec3I& t : mesh.triangles) {
    const openvdb::Vec3d a(mesh.points_mm[t[0]]), b(mesh.points_mm[t[1]]), c(mesh.points_mm[t[2]]);
    six_v += a.dot(b.cross(c));
  }
  return six_v / 6.0;
}

std::string_view to_string(MeshFormat format) {
  switch (format) {
    case MeshFormat::kPly:
      return "ply";
    case MeshFormat::kStl:
      return "stl";
  }
  return "?";
}

void write_mesh(const SkinMesh& mesh, const std::filesystem::path& path, MeshFormat format) {
  if (mesh.triangles.empty())
    throw std::invalid_argument(fmt::format(
        "cannot write {}: the skin has no triangles (the deposit holds no material)", path.string()));
  AtomicStream file(path);
  if (format == MeshFormat::kPly)
    write_ply(mesh, file.stream());
  else
    write_stl(mesh, file.stream(), path);
  file.commit();
}

BeadStlEstimate bead_by_bead_stl(const Toolpath& toolpath, int facets_around) {
  if (facets_around < 3)
    throw std::invalid_argument(fmt::format("a tube needs at least 3 facets around, got {}", facets_around));
  BeadStlEstimate e;
  for (const Move& m : toolpath.moves) e.moves += m.deposits() ? 1 : 0;
  const auto per_move = static_cast<std::size_t>(2 * facets_around + 2 * (facets_around - 2));
  e.triangles = e.moves * per_move;
  e.bytes = 84 + 50 * static_cast<std::uintmax_t>(e.triangles);
  return e;
}

}  // namespace beadtwin::sim
