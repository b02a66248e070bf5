// The as-printed skin of a deposited box: a closed mesh facing outwards that encloses the deposited volume,
// written as PLY and STL that read back as written.
#include "sim/skin.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "tests/read_file.hpp"
#include "tests/sim/ring_deposit.hpp"

namespace beadtwin::sim {
namespace {

using beadtwin::testing::read_file;
using testing::fresh_dir;
using testing::get;
using testing::ring;

// The edges of `mesh`'s triangles, each direction apart, with the triangles that run along each.
std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed_edges(const SkinMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : mesh.triangles)
    for (int c = 0; c < 3; ++c) ++directed[{t[c], t[(c + 1) % 3]}];
  return directed;
}

// The edges whose count `fits` does not accept along with the count of their reverse (0 if none).
template <class Fits>
std::size_t edges_not_fitting(const SkinMesh& mesh, const Fits& fits) {
  const auto directed = directed_edges(mesh);
  std::size_t bad = 0;
  for (const auto& [edge, count] : directed) {
    const auto back = directed.find({edge.second, edge.first});
    bad += !fits(count, back == directed.end() ? 0 : back->second);
  }
  return bad;
}

// Every directed edge of a closed, consistently oriented manifold mesh appears once, and so does its reverse.
// Returns the number of edges that break this.
std::size_t open_or_misoriented_edges(const SkinMesh& mesh) {
  return edges_not_fitting(mesh, [](int count, int back) { return count == 1 && back == 1; });
}

// A closed, consistently oriented surface that may touch itself: every directed edge appears as often as
// its reverse (an edge may be shared by four triangles, where two sheets of the surface meet along it).
// Returns the number of edges that break this.
std::size_t unmatched_edges(const SkinMesh& mesh) {
  return edges_not_fitting(mesh, [](int count, int back) { return count == back; });
}

// Triangles on the same three corners as another one.
std::size_t repeated_triangles(const SkinMesh& mesh) {
  std::map<std::array<std::uint32_t, 3>, int> seen;
  for (const auto& t : mesh.triangles) {
    std::array<std::uint32_t, 3> corners{t[0], t[1], t[2]};
    std::sort(corners.begin(), corners.end());
    ++seen[corners];
  }
  std::size_t repeated = 0;
  for (const auto& [corners, count] : seen) repeated += count > 1 ? count : 0;
  return repeated;
}

TEST(Skin, BoxIsClosedFacesOutwardsAndEnclosesTheDepositedVolume) {
  const Deposit& d = ring();
  ASSERT_GT(d.deposited_volume_mm3, 0.0);
  const SkinMesh mesh = extract_skin(d, 0.0);
  ASSERT_GT(mesh.triangles.size(), 1000u);
  EXPECT_EQ(open_or_misoriented_edges(mesh), 0u);
  // A ring is a torus: V - E + F = 0, with E = 3F/2 for a closed triangle mesh.
  EXPECT_EQ(static_cast<long>(mesh.points_mm.size()) - static_cast<long>(mesh.triangles.size()) / 2, 0);
  // Positive: the triangles face outwards. The iso-surface fill = 0.5 holds what the voxels hold.
  const double v = enclosed_volume_mm3(mesh);
  EXPECT_NEAR(v / d.deposited_volume_mm3, 1.0, 0.03) << v << " vs " << d.deposited_volume_mm3;
}

TEST(Skin, NormalsPointAwayFromTheWallsCentreline) {
  // Beside the middle of each wall, outside the ring's centreline the normal points out of the box, inside it
  // into the hole: checks orientation locally, not only in total.
  const SkinMesh mesh = extract_skin(ring(), 0.0);
  int checked = 0;
  for (const auto& t : mesh.triangles) {
    const openvdb::Vec3s a = mesh.points_mm[t[0]], b = mesh.points_mm[t[1]], c = mesh.points_mm[t[2]];
    const openvdb::Vec3s centre = (a + b + c) / 3.0f;
    openvdb::Vec3s n = (b - a).cross(c - a);
    n.normalize();
    // The wall along y = 0, away from the corners and half way up.
    if (centre.x() < 40 || centre.x() > 80 || std::abs(centre.y()) > 15 || std::abs(centre.z() - 10) > 3 ||
        std::abs(n.y()) < 0.9)
      continue;
    EXPECT_EQ(n.y() < 0, centre.y() < 0) << centre << " normal " << n;
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

TEST(Skin, AdaptivityMergesFlatFacesAndKeepsTheVolume) {
  // Measured on this ring (20 mm beads in 2.5 mm voxels, four layers): 12208, 4266 and 2578 triangles
  // enclosing 99.9 %, 97.3 % and 94.1 % of the deposited volume; merged faces cut across the beads' round
  // sides. At adaptivity 1 the walls, eight voxels thick, lose half their volume.
  const Deposit& d = ring();
  std::size_t previous = 0;
  for (const auto& [adaptivity, volume_tolerance] : {std::pair{0.0, 0.01}, {0.2, 0.04}, {0.5, 0.07}}) {
    const SkinMesh mesh = extract_skin(d, adaptivity);
    EXPECT_EQ(open_or_misoriented_edges(mesh), 0u) << "adaptivity " << adaptivity;
    if (previous > 0) {
      EXPECT_LT(mesh.triangles.size(), previous) << "adaptivity " << adaptivity;
    }
    previous = mesh.triangles.size();
    EXPECT_NEAR(enclosed_volume_mm3(mesh) / d.deposited_volume_mm3, 1.0, volume_tolerance)
        << "adaptivity " << adaptivity;
  }
  EXPECT_LT(extract_skin(d, 0.2).triangles.size(), extract_skin(d, 0.0).triangles.size() / 2);
  EXPECT_THROW((void)extract_skin(d, 1.5), std::invalid_argument);
  EXPECT_THROW((void)extract_skin(d, -0.1), std::invalid_argument);
}

// A minimal binary PLY reader: the header as written by write_mesh, then the vertices and the faces.
SkinMesh read_ply(const std::string& bytes) {
  const std::size_t end = bytes.find("end_header\n");
  if (bytes.rfind("ply\nformat binary_little_endian 1.0\n", 0) != 0 || end == std::string::npos)
    throw std::runtime_error("not a binary little-endian PLY");
  std::istringstream header(bytes.substr(0, end));
  std::size_t vertices = 0, faces = 0;
  std::string line;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string word, element;
    std::size_t count = 0;
    words >> word >> element >> count;
    if (word == "element") (element == "vertex" ? vertices : faces) = count;
  }
  EXPECT_NE(bytes.find("property list uchar uint vertex_indices"), std::string::npos);
  std::size_t at = end + std::strlen("end_header\n");
  if (bytes.size() != at + 12 * vertices + 13 * faces) throw std::runtime_error("PLY size does not add up");
  SkinMesh mesh;
  for (std::size_t i = 0; i < vertices; ++i, at += 12)
    mesh.points_mm.emplace_back(get<float>(bytes, at), get<float>(bytes, at + 4), get<float>(bytes, at + 8));
  for (std::size_t i = 0; i < faces; ++i, at += 13) {
    if (get<std::uint8_t>(bytes, at) != 3) throw std::runtime_error("a face is not a triangle");
    mesh.triangles.emplace_back(get<std::uint32_t>(bytes, at + 1), get<std::uint32_t>(bytes, at + 5),
                                get<std::uint32_t>(bytes, at + 9));
  }
  return mesh;
}

TEST(Skin, PlyReadsBackAsWritten) {
  const SkinMesh mesh = extract_skin(ring(), 0.2);
  const auto path = fresh_dir("skin_ply") / "skin.ply";
  write_mesh(mesh, path, MeshFormat::kPly);
  const SkinMesh back = read_ply(read_file(path));
  ASSERT_EQ(back.points_mm.size(), mesh.points_mm.size());
  ASSERT_EQ(back.triangles.size(), mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.points_mm.size(); ++i) EXPECT_EQ(back.points_mm[i], mesh.points_mm[i]);
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) EXPECT_EQ(back.triangles[i], mesh.triangles[i]);
  EXPECT_DOUBLE_EQ(enclosed_volume_mm3(back), enclosed_volume_mm3(mesh));
}

TEST(Skin, StlReadsBackWithOutwardNormals) {
  const SkinMesh mesh = extract_skin(ring(), 0.2);
  const auto path = fresh_dir("skin_stl") / "skin.stl";
  write_mesh(mesh, path, MeshFormat::kStl);
  const std::string bytes = read_file(path);
  ASSERT_GE(bytes.size(), 84u);
  EXPECT_NE(bytes.rfind("solid", 0), 0u) << "a binary STL must not start like an ASCII one";
  const auto n = get<std::uint32_t>(bytes, 80);
  ASSERT_EQ(n, mesh.triangles.size());
  ASSERT_EQ(bytes.size(), 84 + 50 * std::size_t{n});
  double six_v = 0.0;
  for (std::size_t i = 0, at = 84; i < n; ++i, at += 50) {
    openvdb::Vec3f v[4];
    for (int k = 0; k < 4; ++k)
      v[k] = {get<float>(bytes, at + 12 * k), get<float>(bytes, at + 12 * k + 4),
              get<float>(bytes, at + 12 * k + 8)};
    const auto& t = mesh.triangles[i];
    EXPECT_EQ(v[1], mesh.points_mm[t[0]]);
    EXPECT_EQ(v[3], mesh.points_mm[t[2]]);
    // The stored normal agrees with the corners' order (right-hand rule).
    const openvdb::Vec3f cross = (v[2] - v[1]).cross(v[3] - v[1]);
    if (cross.length() > 1e-3f) {
      EXPECT_GT(cross.dot(v[0]), 0.0f) << "triangle " << i;
    }
    EXPECT_EQ(get<std::uint16_t>(bytes, at + 48), 0u);
    six_v += openvdb::Vec3d(v[1]).dot(openvdb::Vec3d(v[2]).cross(openvdb::Vec3d(v[3])));
  }
  EXPECT_NEAR(six_v / 6.0 / ring().deposited_volume_mm3, 1.0, 0.05);
}

TEST(Skin, EmptyDepositHasNoSkinAndWritesNoFile) {
  const SkinMesh mesh = extract_skin(testing::empty_deposit(), 0.2);
  EXPECT_TRUE(mesh.triangles.empty());
  const auto path = fresh_dir("skin_empty") / "skin.ply";
  try {
    write_mesh(mesh, path, MeshFormat::kPly);
    FAIL() << "an empty skin was written";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no material"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(std::filesystem::is_empty(path.parent_path()));
}

TEST(Skin, UnwritablePlaceIsAnErrorNamingThePathAndLeavesNothing) {
  const SkinMesh mesh = extract_skin(ring(), 0.5);
  const auto dir = fresh_dir("skin_unwritable");
  const auto missing = dir / "no-such-folder" / "skin.stl";
  std::ofstream(dir / "a-file") << "x";
  const auto under_a_file = dir / "a-file" / "skin.ply";
  for (const auto& path : {missing, under_a_file}) {
    try {
      write_mesh(mesh, path, path.extension() == ".stl" ? MeshFormat::kStl : MeshFormat::kPly);
      FAIL() << "wrote " << path;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "no-such-folder"));
  // Only the file the test made.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()),
            1);
}

TEST(Skin, BeadByBeadStlSizeFollowsItsAssumptions) {
  const Toolpath tp = testing::ring_toolpath();  // 4 layers of 4 beads
  Toolpath with_travel = tp;
  Move travel;
  travel.kind = MoveKind::kTravel;
  travel.end = {0, 0, 50};
  with_travel.moves.push_back(travel);  // carries no material: not a bead
  for (const Toolpath* t : {&tp, static_cast<const Toolpath*>(&with_travel)}) {
    const BeadStlEstimate e = bead_by_bead_stl(*t);
    EXPECT_EQ(e.moves, 16u);
    EXPECT_EQ(e.triangles, 16u * (2 * 16 + 2 * 14));  // 16 sides of 2 triangles, two caps of 14
    EXPECT_EQ(e.bytes, 84u + 50u * e.triangles);
  }
  EXPECT_EQ(bead_by_bead_stl(tp, 8).triangles, 16u * 28);
  EXPECT_THROW((void)bead_by_bead_stl(tp, 2), std::invalid_argument);
}

}  // namespace
}  // namespace beadtwin::sim

namespace beadtwin::sim {
namespace {

// A block of beads with a closed hole in its middle layer (one bead broken for 60 mm, sealed by the layers
// above and below and the beads beside it; laid without following the substrate, so the layer above does
// not sink into it): the outer skin leaves the void's shell out, the full skin keeps it, facing inwards.
TEST(Skin, OuterSkinLeavesVoidShellsOut) {
  testing::Ring r;
  std::vector<Move> moves;
  const double pitch = bead_area_mm2(r.bead_width_mm, r.layer_height_mm) / r.layer_height_mm;
  for (int l = 0; l < 3; ++l) {
    const double z = (l + 1) * r.layer_height_mm;
    for (int n = 0; n < 5; ++n) {
      const double y = n * pitch;
      if (l == 1 && n == 2) {
        moves.push_back(testing::ring_bead({0, y, z}, {70, y, z}, l, r));
        moves.push_back(testing::ring_bead({130, y, z}, {200, y, z}, l, r));
      } else {
        moves.push_back(testing::ring_bead({0, y, z}, {200, y, z}, l, r));
      }
    }
  }
  Toolpath tp;
  tp.moves = moves;
  tp.layers.resize(3);
  time_toolpath(tp, MotionLimits{});
  DepositOptions o;
  o.voxel_size_mm = r.voxel_mm;
  o.follow_substrate = false;
  const Deposit d = deposit(tp, o);
  const SkinMesh outer = extract_skin(d, 0.0);
  const SkinMesh full = extract_skin(d, 0.0, false);
  EXPECT_LT(outer.triangles.size(), full.triangles.size());
  // The void's shell subtracts its volume from the full skin's; the outer skin encloses the void too.
  const double hole = 60.0 * bead_area_mm2(r.bead_width_mm, r.layer_height_mm);
  EXPECT_NEAR(enclosed_volume_mm3(outer) - enclosed_volume_mm3(full), hole, 0.3 * hole);
  EXPECT_GT(enclosed_volume_mm3(outer), d.deposited_volume_mm3);
}

}  // namespace
}  // namespace beadtwin::sim

namespace beadtwin::sim {
namespace {

// Simplified to a tolerance (edge collapse), the skin keeps its volume and every point stays within the
// tolerance of the surface it came from, with far fewer triangles.
TEST(Skin, SimplifiedToAToleranceKeepsItsShape) {
  const Deposit d = testing::ring_deposit();
  const SkinMesh exact = extract_skin(d, 0.0);
  const SkinMesh simple = extract_skin(d, 0.0, true, 0.3);
  EXPECT_LT(simple.triangles.size(), exact.triangles.size() / 2);
  EXPECT_NEAR(enclosed_volume_mm3(simple) / enclosed_volume_mm3(exact), 1.0, 0.01);
  // Simplification keeps a subset of the points, so each stays on the exact mesh's surface; the check is
  // that the surface it spans stays near: every simplified triangle's centre lies within the tolerance
  // (and a voxel's rounding) of the fill = 0.5 surface, judged by the fill interpolated there.
  const auto fill = d.fill->getConstAccessor();
  int far = 0;
  for (const openvdb::Vec3I& t : simple.triangles) {
    const openvdb::Vec3s c =
        (simple.points_mm[t[0]] + simple.points_mm[t[1]] + simple.points_mm[t[2]]) / 3.0f;
    const openvdb::Coord ijk = d.fill->transform().worldToIndexCellCentered(openvdb::Vec3d(c));
    // Within a voxel of the surface: the voxel holds some material or a face neighbour does.
    bool near = fill.getValue(ijk) > 0.0f;
    for (int a = 0; a < 3 && !near; ++a)
      for (const int s : {-1, 1}) {
        openvdb::Coord n = ijk;
        n[a] += s;
        near = near || fill.getValue(n) > 0.0f;
      }
    far += !near;
  }
  EXPECT_EQ(far, 0);
}

// A mesh of a million triangles or more is simplified in slabs side by side, each over its own vertices,
// with the vertices on the cuts held: the slabs must still meet in one closed surface facing outwards, with
// no folds (pairs of triangles on the same corners wound opposite ways, which the simplification leaves
// along the cut on this plate unless they are dropped). A plate of 520 x 520 voxels with ridges across it:
// 1.16 million triangles unsimplified, so two slabs.
TEST(Skin, ALargeMeshIsSimplifiedInSlabsThatStillMeet) {
  Deposit d;
  d.voxel_size_mm = 1.0;
  d.fill = openvdb::FloatGrid::create(0.0f);
  d.fill->setTransform(deposit_transform(d.voxel_size_mm));
  d.fill->setGridClass(openvdb::GRID_FOG_VOLUME);
  auto fill = d.fill->getAccessor();
  constexpr int kSide = 520;
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j)
      for (int k = 0; k < 3 + (i / 8) % 2; ++k) fill.setValue({i, j, k}, 1.0f);
  const SkinMesh exact = extract_skin(d, 0.0);
  ASSERT_GE(exact.triangles.size(), 1'000'000u);
  EXPECT_EQ(open_or_misoriented_edges(exact), 0u);
  const SkinMesh simple = extract_skin(d, 0.0, true, 0.3);
  EXPECT_LT(simple.triangles.size(), exact.triangles.size() / 20);
  EXPECT_EQ(unmatched_edges(simple), 0u);
  EXPECT_EQ(repeated_triangles(simple), 0u);
  // The plate is 3.5 mm thick on average: a surface moved by up to 0.3 mm could change its volume by 9 %.
  EXPECT_NEAR(enclosed_volume_mm3(simple) / enclosed_volume_mm3(exact), 1.0, 0.02);
}

}  // namespace
}  // namespace beadtwin::sim
