#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "slicer/mesh.hpp"
#include "slicer/mesh_repair.hpp"
#include "slicer/polygons.hpp"
#include "slicer/slice.hpp"

namespace beadtwin::slicer {
namespace {

// A file in the temporary folder, named after the running test so tests may run in parallel.
std::filesystem::path temp_file(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return std::filesystem::temp_directory_path() /
         fmt::format("bt_mesh_{}_{}_{}", info->test_suite_name(), info->name(), name);
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

const Eigen::Vector3d& corner(const TriangleMesh& m, const std::array<int, 3>& t, std::size_t c) {
  return m.vertices[static_cast<std::size_t>(t[c])];
}

std::string ascii_stl(const TriangleMesh& m) {
  std::string s = "solid part\n";
  for (const auto& t : m.triangles) {
    s += " facet normal 0 0 0\n  outer loop\n";
    for (std::size_t c = 0; c < 3; ++c) {
      const Eigen::Vector3d& p = corner(m, t, c);
      s += fmt::format("   vertex {} {} {}\n", p.x(), p.y(), p.z());
    }
    s += "  endloop\n endfacet\n";
  }
  return s + "endsolid part\n";
}

// An OBJ with one object (`o name`) per mesh.
std::string obj(const std::vector<std::pair<std::string, TriangleMesh>>& objects) {
  std::string s = "# beadtwin test\n";
  std::size_t base = 1;
  for (const auto& [name, m] : objects) {
    s += fmt::format("o {}\n", name);
    for (const auto& p : m.vertices) s += fmt::format("v {} {} {}\n", p.x(), p.y(), p.z());
    for (const auto& t : m.triangles)
      s += fmt::format("f {} {} {}\n", base + static_cast<std::size_t>(t[0]),
                       base + static_cast<std::size_t>(t[1]), base + static_cast<std::size_t>(t[2]));
    base += m.vertices.size();
  }
  return s;
}

std::string ascii_ply(const TriangleMesh& m) {
  std::string s = fmt::format(
      "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n"
      "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
      m.vertices.size(), m.triangles.size());
  for (const auto& p : m.vertices) s += fmt::format("{} {} {}\n", p.x(), p.y(), p.z());
  for (const auto& t : m.triangles) s += fmt::format("3 {} {} {}\n", t[0], t[1], t[2]);
  return s;
}

std::string amf(const TriangleMesh& m) {
  std::string s =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<amf unit=\"millimeter\">\n <object id=\"0\">\n";
  s += "  <mesh>\n   <vertices>\n";
  for (const auto& p : m.vertices)
    s += fmt::format("    <vertex><coordinates><x>{}</x><y>{}</y><z>{}</z></coordinates></vertex>\n", p.x(),
                     p.y(), p.z());
  s += "   </vertices>\n   <volume>\n";
  for (const auto& t : m.triangles)
    s += fmt::format("    <triangle><v1>{}</v1><v2>{}</v2><v3>{}</v3></triangle>\n", t[0], t[1], t[2]);
  return s + "   </volume>\n  </mesh>\n </object>\n</amf>\n";
}

// --- A minimal 3MF package: a zip archive with its three files stored uncompressed. ---

std::uint32_t crc32(const std::string& data) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (const char ch : data) {
    crc ^= static_cast<unsigned char>(ch);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void put16(std::string& s, std::size_t v) {
  s.push_back(static_cast<char>(v & 0xFF));
  s.push_back(static_cast<char>((v >> 8) & 0xFF));
}

void put32(std::string& s, std::size_t v) {
  put16(s, v & 0xFFFF);
  put16(s, (v >> 16) & 0xFFFF);
}

std::string zip_stored(const std::vector<std::pair<std::string, std::string>>& files) {
  std::string out, central;
  for (const auto& [name, data] : files) {
    const std::size_t offset = out.size();
    // Shared by the local and the central header: version needed, flags, method (stored), time, date
    // (1980-01-01), CRC, compressed and uncompressed sizes, name length, extra length.
    std::string common;
    for (std::size_t v : {20, 0, 0, 0, 0x21}) put16(common, v);
    put32(common, crc32(data));
    put32(common, data.size());
    put32(common, data.size());
    put16(common, name.size());
    put16(common, 0);
    put32(out, 0x04034B50);
    out += common + name + data;
    put32(central, 0x02014B50);
    put16(central, 20);  // made by
    central += common;
    for (std::size_t v : {0, 0, 0}) put16(central, v);  // comment length, disk, internal attributes
    put32(central, 0);                                  // external attributes
    put32(central, offset);
    central += name;
  }
  const std::size_t central_offset = out.size();
  out += central;
  put32(out, 0x06054B50);
  for (std::size_t v : {std::size_t{0}, std::size_t{0}, files.size(), files.size()}) put16(out, v);
  put32(out, central.size());
  put32(out, central_offset);
  put16(out, 0);
  return out;
}

// A 3MF with one object per mesh, each placed by a build item with `transform` ("" for none).
std::string three_mf(const std::vector<std::pair<std::string, TriangleMesh>>& objects,
                     const std::string& transform) {
  std::string model =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" "
      "xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n<resources>\n";
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const auto& [name, m] = objects[o];
    model += fmt::format("<object id=\"{}\" name=\"{}\" type=\"model\">\n<mesh>\n<vertices>\n", o + 1, name);
    for (const auto& p : m.vertices)
      model += fmt::format("<vertex x=\"{}\" y=\"{}\" z=\"{}\"/>\n", p.x(), p.y(), p.z());
    model += "</vertices>\n<triangles>\n";
    for (const auto& t : m.triangles)
      model += fmt::format("<triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>\n", t[0], t[1], t[2]);
    model += "</triangles>\n</mesh>\n</object>\n";
  }
  model += "</resources>\n<build>\n";
  for (std::size_t o = 0; o < objects.size(); ++o)
    model += transform.empty() ? fmt::format("<item objectid=\"{}\"/>\n", o + 1)
                               : fmt::format("<item objectid=\"{}\" transform=\"{}\"/>\n", o + 1, transform);
  model += "</build>\n</model>\n";
  const std::string types =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Types "
      "xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\">"
      "<Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/>"
      "<Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>"
      "</Types>\n";
  const std::string rels =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Relationships "
      "xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">"
      "<Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" "
      "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>\n";
  return zip_stored({{"[Content_Types].xml", types}, {"_rels/.rels", rels}, {"3D/3dmodel.model", model}});
}

// --- Meshes ---

const Eigen::Vector3d kSize{10, 20, 30}, kOrigin{1, 2, 3};
constexpr double kVolume = 6000.0;

TriangleMesh test_box() {
  return make_box(kSize, kOrigin);
}

TriangleMesh without_faces(TriangleMesh m, std::vector<std::size_t> faces) {
  std::sort(faces.rbegin(), faces.rend());
  for (std::size_t f : faces) {
    m.triangles.erase(m.triangles.begin() + static_cast<std::ptrdiff_t>(f));
    m.body.erase(m.body.begin() + static_cast<std::ptrdiff_t>(f));
  }
  return m;
}

bool has_warning(const MeshReport& r, const std::string& text) {
  for (const auto& w : r.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

std::string all_warnings(const MeshReport& r) {
  std::string s;
  for (const auto& w : r.warnings) s += w + "\n";
  return s;
}

void expect_clean(const MeshReport& r, const std::string& what) {
  EXPECT_TRUE(r.warnings.empty()) << what << ":\n" << all_warnings(r);
  EXPECT_EQ(r.open_edges, 0) << what;
  EXPECT_EQ(r.shells, 1) << what;
  EXPECT_EQ(r.bodies, 1) << what;
}

// The message of the InputError that reading `path` throws ("" and a test failure when it reads).
std::string read_error(const std::filesystem::path& path, double scale = 1.0) {
  try {
    (void)read_mesh(path, scale);
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, path.string());
    EXPECT_NE(std::string(e.what()).find(path.filename().string()), std::string::npos) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "reading " << path << " did not fail";
  return {};
}

double area_at(const TriangleMesh& m, double z, SliceStats* stats = nullptr) {
  return area_mm2(slice_mesh(m, z, stats));
}

TEST(Mesh, BoxIsClosedWithTheRightVolume) {
  const TriangleMesh box = make_box({100, 50, 20});
  EXPECT_NEAR(box.volume_mm3(), 100.0 * 50 * 20, 1e-6);
  EXPECT_EQ(box.body, std::vector<int>(12, 0));
  EXPECT_EQ(box.body_names, std::vector<std::string>{"part"});
  const TriangleMesh open = make_open_box({100, 80, 50}, 10, 5);
  EXPECT_NEAR(open.volume_mm3(), 100.0 * 80 * 50 - 80.0 * 60 * 45, 1e-6);
  EXPECT_EQ(open.body.size(), open.triangles.size());
  EXPECT_EQ(open.body_names, std::vector<std::string>{"part"});
}

TEST(Mesh, TheSameBoxInEveryFormatHasTheSameVolume) {
  const TriangleMesh box = test_box();
  write_stl(box, temp_file("box_binary.stl"));
  write_text(temp_file("box_ascii.stl"), ascii_stl(box));
  write_text(temp_file("box.obj"), obj({{"box", box}}));
  write_text(temp_file("box.ply"), ascii_ply(box));
  write_text(temp_file("box.amf"), amf(box));
  write_text(temp_file("box.3mf"), three_mf({{"box", box}}, ""));
  for (const char* name : {"box_binary.stl", "box_ascii.stl", "box.obj", "box.ply", "box.amf", "box.3mf"}) {
    MeshReport report;
    const TriangleMesh m = read_mesh(temp_file(name), 1.0, &report);
    EXPECT_NEAR(m.volume_mm3(), kVolume, 1e-6) << name;
    EXPECT_EQ(m.triangles.size(), 12u) << name;
    EXPECT_EQ(m.vertices.size(), 8u) << name;  // welded
    EXPECT_TRUE(m.min_corner().isApprox(kOrigin)) << name;
    EXPECT_EQ(m.body, std::vector<int>(12, 0)) << name;
    expect_clean(report, name);
  }
}

TEST(Mesh, UnitScaleConvertsInches) {
  write_text(temp_file("inch.obj"), obj({{"box", make_box({1, 2, 3})}}));
  const TriangleMesh m = read_mesh(temp_file("inch.obj"), 25.4);
  EXPECT_NEAR(m.volume_mm3(), 6.0 * 25.4 * 25.4 * 25.4, 1e-6);
  EXPECT_NEAR(m.max_corner().z(), 3 * 25.4, 1e-9);
  write_text(temp_file("tri.stl"),
             "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
             "endfacet\nendsolid t\n");
  const TriangleMesh tri = read_mesh(temp_file("tri.stl"), 25.4);
  ASSERT_EQ(tri.triangles.size(), 1u);
  EXPECT_DOUBLE_EQ(tri.max_corner().x(), 25.4);
}

TEST(Mesh, FlippedFacesAreTurnedBackAndCounted) {
  TriangleMesh box = test_box();
  for (std::size_t f : {0, 5, 7}) std::swap(box.triangles[f][1], box.triangles[f][2]);
  write_stl(box, temp_file("flipped.stl"));
  MeshReport report;
  const TriangleMesh m = read_mesh(temp_file("flipped.stl"), 1.0, &report);
  EXPECT_EQ(report.flipped_faces, 3);
  EXPECT_EQ(report.reversed_shells, 0);
  EXPECT_NEAR(m.volume_mm3(), kVolume, 1e-6);
  EXPECT_TRUE(has_warning(report, "flipped.stl: 3 faces were flipped to match their neighbours"))
      << all_warnings(report);
  // Slices to the footprint at mid-height (the flipped faces would have cancelled parts of the contour).
  SliceStats stats;
  EXPECT_NEAR(area_at(m, kOrigin.z() + 15, &stats), 200.0, 1e-6);
  EXPECT_EQ(stats.open_chains, 0);
}

TEST(Mesh, AnInsideOutShellIsTurnedAround) {
  TriangleMesh box = test_box();
  for (auto& t : box.triangles) std::swap(t[1], t[2]);
  // A few faces flipped back as well: the majority's winding wins before the shell is turned out.
  for (std::size_t f : {3, 8}) std::swap(box.triangles[f][1], box.triangles[f][2]);
  write_text(temp_file("inside_out.obj"), obj({{"box", box}}));
  MeshReport report;
  const TriangleMesh m = read_mesh(temp_file("inside_out.obj"), 1.0, &report);
  EXPECT_EQ(report.flipped_faces, 2);
  EXPECT_EQ(report.reversed_shells, 1);
  EXPECT_EQ(report.cavities, 0);
  EXPECT_NEAR(m.volume_mm3(), kVolume, 1e-6);
  EXPECT_TRUE(has_warning(report, "1 closed shell was inside out")) << all_warnings(report);
}

TEST(Mesh, DuplicateFacesAreDropped) {
  TriangleMesh box = test_box();
  box.triangles.push_back(box.triangles[0]);
  box.triangles.push_back({box.triangles[4][1], box.triangles[4][2], box.triangles[4][0]});  // rotated copy
  box.triangles.push_back(box.triangles[0]);
  box.body.resize(box.triangles.size(), 0);
  write_stl(box, temp_file("dup.stl"));
  MeshReport report;
  const TriangleMesh m = read_mesh(temp_file("dup.stl"), 1.0, &report);
  EXPECT_EQ(report.duplicate_faces, 3);
  EXPECT_EQ(m.triangles.size(), 12u);
  EXPECT_EQ(report.non_manifold_edges, 0);
  EXPECT_NEAR(m.volume_mm3(), kVolume, 1e-6);
  EXPECT_TRUE(has_warning(report, "3 duplicate faces were dropped")) << all_warnings(report);
}

TEST(Mesh, AnInternalSheetBetweenTouchingBoxesIsDropped) {
  // Two boxes sharing their x = 11 face, in one body: the shared face appears twice, wound oppositely.
  const TriangleMesh a = test_box(), b = make_box(kSize, kOrigin + Eigen::Vector3d(10, 0, 0));
  TriangleMesh both = a;
  for (auto t : b.triangles) {
    for (int& v : t) v += static_cast<int>(a.vertices.size());
    both.triangles.push_back(t);
  }
  both.vertices.insert(both.vertices.end(), b.vertices.begin(), b.vertices.end());
  write_stl(both, temp_file("touching.stl"));
  MeshReport report;
  const TriangleMesh m = read_mesh(temp_file("touching.stl"), 1.0, &report);
  EXPECT_EQ(report.duplicate_faces, 4);  // two triangles on each side
  EXPECT_EQ(report.open_edges, 0);
  EXPECT_EQ(report.non_manifold_edges, 0);
  EXPECT_EQ(report.shells, 1);
  EXPECT_NEAR(m.volume_mm3(), 2 * kVolume, 1e-6);
  EXPECT_NEAR(area_at(m, 18), 400.0, 1e-6);
}

TEST(Mesh, ABoxWithMissingFacesIsReportedAndStillSlices) {
  // The +x side is the last quad of make_box: triangles 10 and 11.
  const TriangleMesh box = test_box();
  ASSERT_NEAR(corner(box, box.triangles[10], 0).x(), kOrigin.x() + kSize.x(), 0);
  ASSERT_NEAR(corner(box, box.triangles[11], 2).x(), kOrigin.x() + kSize.x(), 0);
  struct Case {
    std::vector<std::size_t> missing;
    int open_edges;
  };
  // One triangle missing leaves its three edges open; the whole quad, its four outer edges.
  for (const Case& c : {Case{{11}, 3}, Case{{10, 11}, 4}}) {
    const auto file = temp_file(fmt::format("open{}.stl", c.missing.size()));
    write_stl(without_faces(box, c.missing), file);
    MeshReport report;
    const TriangleMesh m = read_mesh(file, 1.0, &report);
    EXPECT_EQ(report.open_edges, c.open_edges);
    EXPECT_EQ(report.flipped_faces, 0);
    EXPECT_EQ(report.reversed_shells, 0);
    EXPECT_TRUE(has_warning(report, fmt::format("{} open edges", c.open_edges))) << all_warnings(report);
    SliceStats stats;
    EXPECT_NEAR(area_at(m, kOrigin.z() + 15, &stats), 200.0, 1e-6);
    EXPECT_EQ(stats.open_chains, 1);
  }
}

TEST(Mesh, NearlyCoincidentVerticesAreWelded) {
  // Triangle 0 gets a copy of its first corner, 1e-6 mm off (the tolerance is 1e-6 of the 37 mm diagonal).
  TriangleMesh box = test_box();
  box.vertices.push_back(box.vertices[static_cast<std::size_t>(box.triangles[0][0])] +
                         Eigen::Vector3d(1e-6, 0, 0));
  box.triangles[0][0] = static_cast<int>(box.vertices.size()) - 1;
  write_text(temp_file("near.obj"), obj({{"box", box}}));
  MeshReport report;
  const TriangleMesh m = read_mesh(temp_file("near.obj"), 1.0, &report);
  EXPECT_EQ(report.welded_vertices, 1);
  EXPECT_EQ(report.open_edges, 0);
  EXPECT_EQ(m.vertices.size(), 8u);
  EXPECT_NEAR(report.weld_tolerance_mm, 1e-6 * kSize.norm(), 1e-12);
  // 1e-3 mm off is a real gap, left open.
  box.vertices.back() += Eigen::Vector3d(1e-3, 0, 0);
  write_text(temp_file("gap.obj"), obj({{"box", box}}));
  const TriangleMesh gap = read_mesh(temp_file("gap.obj"), 1.0, &report);
  EXPECT_EQ(report.welded_vertices, 0);
  EXPECT_EQ(report.open_edges, 4);  // the lone triangle's two edges at the moved corner, and the holes'
  EXPECT_EQ(gap.vertices.size(), 9u);
}

TEST(Mesh, DegenerateFacesAreDropped) {
  TriangleMesh box = test_box();
  box.triangles.push_back({0, 0, 1});
  box.triangles.push_back({2, 3, 3});
  write_text(temp_file("degenerate.obj"), obj({{"box", box}}));
  MeshReport report;
  const TriangleMesh m = read_mesh(temp_file("degenerate.obj"), 1.0, &report);
  EXPECT_EQ(report.degenerate_faces, 2);
  EXPECT_EQ(m.triangles.size(), 12u);
  EXPECT_NEAR(m.volume_mm3(), kVolume, 1e-6);
}

TEST(Mesh, TwoObjectsInAnObjAreTwoBodies) {
  const TriangleMesh shell = make_box({100, 100, 50}), rib = make_box({10, 80, 40}, {45, 10, 5});
  write_text(temp_file("bodies.obj"), obj({{"shell", shell}, {"rib", rib}}));
  MeshReport report;
  const TriangleMesh m = read_mesh(temp_file("bodies.obj"), 1.0, &report);
  EXPECT_EQ(report.bodies, 2);
  EXPECT_EQ(report.cavities, 0);  // a body inside another body is a body, not a hole
  ASSERT_EQ(m.body_names, (std::vector<std::string>{"shell", "rib"}));
  ASSERT_EQ(m.body.size(), m.triangles.size());
  EXPECT_EQ(std::count(m.body.begin(), m.body.end(), 1), 12);
  EXPECT_EQ(find_body(m, "rib"), 1);
  EXPECT_EQ(find_body(m, "lid"), -1);
  const TriangleMesh r = select_body(m, find_body(m, "rib"));
  EXPECT_EQ(r.body_names, std::vector<std::string>{"rib"});
  EXPECT_EQ(r.vertices.size(), 8u);
  EXPECT_NEAR(r.volume_mm3(), 10.0 * 80 * 40, 1e-6);
  EXPECT_NEAR(select_body(m, 0).volume_mm3(), 100.0 * 100 * 50, 1e-6);
  // Both are solid: the slice is the shell's footprint.
  EXPECT_NEAR(area_at(m, 20), 10000.0, 1e-6);
}

TEST(Mesh, PointsAndLinesAreIgnored) {
  const std::string text = obj({{"box", test_box()}}) + "o sketch\nv 0 0 0\nv 1 0 0\nl 9 10\np 9\n";
  write_text(temp_file("sketch.obj"), text);
  MeshReport report;
  const TriangleMesh m = read_mesh(temp_file("sketch.obj"), 1.0, &report);
  EXPECT_EQ(m.body_names, std::vector<std::string>{"box"});  // the object without triangles is no body
  EXPECT_EQ(report.ignored_primitives, 2);
  EXPECT_TRUE(has_warning(report, "2 points and lines were ignored")) << all_warnings(report);
}

TEST(Mesh, ConcavePolygonsAreCutInsideTheirOutline) {
  // An L-shaped prism, 10 high, whose end faces are concave hexagons, written from the corner of the notch: a
  // fan from there would cover the notch and leave part of the L bare.
  const std::vector<Eigen::Vector2d> l = {{20, 10}, {10, 10}, {10, 20}, {0, 20}, {0, 0}, {20, 0}};
  std::string text = "o ell\n";
  for (double z : {0.0, 10.0})
    for (const auto& p : l) text += fmt::format("v {} {} {}\n", p.x(), p.y(), z);
  text += "f 6 5 4 3 2 1\nf 7 8 9 10 11 12\n";  // bottom facing down, top facing up
  for (int i = 0; i < 6; ++i) {
    const int j = (i + 1) % 6;
    text += fmt::format("f {} {} {} {}\n", i + 1, j + 1, j + 7, i + 7);
  }
  write_text(temp_file("ell.obj"), text);
  MeshReport report;
  const TriangleMesh m = read_mesh(temp_file("ell.obj"), 1.0, &report);
  EXPECT_EQ(m.triangles.size(), 2u * 4 + 6 * 2);
  EXPECT_NEAR(m.volume_mm3(), 300.0 * 10, 1e-9);
  EXPECT_NEAR(area_at(m, 5), 300.0, 1e-9);
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d c = (corner(m, t, 0) + corner(m, t, 1) + corner(m, t, 2)) / 3.0;
    EXPECT_FALSE(c.x() > 10 + 1e-9 && c.y() > 10 + 1e-9)
        << "a triangle in the notch, centred at " << c.transpose();
  }
}

TEST(Mesh, PlyFacesWithoutCornersAreIgnored) {
  // A face of no corners: assimp's own triangulation aborts the program on it (found by tests/fuzz).
  write_text(temp_file("tetra.ply"),
             "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
             "element face 5\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n10 0 0\n0 10 0\n"
             "0 0 10\n3 0 2 1\n3 0 1 3\n0\n3 0 3 2\n3 1 2 3\n");
  MeshReport report;
  const TriangleMesh m = read_mesh(temp_file("tetra.ply"), 1.0, &report);
  EXPECT_EQ(m.triangles.size(), 4u);
  EXPECT_EQ(report.ignored_primitives, 1);
  EXPECT_NEAR(m.volume_mm3(), 1000.0 / 6, 1e-9);
}

TEST(Mesh, APlyHeaderMustEnd) {
  // assimp reads a PLY header without end_header for ever (found by tests/fuzz).
  write_text(temp_file("data.ply"), "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n0\n");
  EXPECT_NE(read_error(temp_file("data.ply")).find(":5:1: PLY header: '0' is not a header line"),
            std::string::npos)
      << read_error(temp_file("data.ply"));
  write_text(temp_file("open.ply"), "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n");
  EXPECT_NE(read_error(temp_file("open.ply")).find("not a PLY: its header has no end_header line"),
            std::string::npos)
      << read_error(temp_file("open.ply"));
  // Whatever its name: assimp knows a PLY by its first line too.
  write_text(temp_file("open.model"), "ply\nformat ascii 1.0\nelement vertex 4\n");
  EXPECT_NE(read_error(temp_file("open.model")).find("end_header"), std::string::npos);
  write_text(temp_file("tab.ply"), "ply\nformat ascii 1.0\nend_header\v0 0 0\n");  // a vertical tab
  EXPECT_NE(read_error(temp_file("tab.ply")).find("is not a header line"), std::string::npos);
  write_text(temp_file("odd.ply"), "ply\nformat utf8 1.0\nend_header\n");
  EXPECT_NE(read_error(temp_file("odd.ply")).find("PLY format 'utf8'"), std::string::npos);
  write_text(temp_file("notply.ply"), "solid x\n");
  EXPECT_NE(read_error(temp_file("notply.ply")).find("its first line is not \"ply\""), std::string::npos);
}

TEST(Mesh, AMeshBeyondTheMemoryBudgetIsRefusedBeforeReading) {
  // 12 triangles of binary STL at 300 bytes each need 3,600 bytes; the same box as OBJ (about 300 bytes of
  // text) is estimated at 24 bytes a byte.
  write_stl(test_box(), temp_file("box.stl"));
  EXPECT_EQ(read_mesh(temp_file("box.stl"), 1.0, nullptr, 3600).triangles.size(), 12u);
  std::string message;
  try {
    (void)read_mesh(temp_file("box.stl"), 1.0, nullptr, 3500);
  } catch (const InputError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("reading it would take about 3.6e-06 GB of memory, more than the 3.5e-06 GB budget"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("Decimate it first"), std::string::npos);
  write_text(temp_file("box.obj"), obj({{"box", test_box()}}));
  const double bytes = static_cast<double>(std::filesystem::file_size(temp_file("box.obj")));
  EXPECT_NO_THROW((void)read_mesh(temp_file("box.obj"), 1.0, nullptr, 24 * bytes));
  EXPECT_THROW((void)read_mesh(temp_file("box.obj"), 1.0, nullptr, 23 * bytes), InputError);
}

// The cost of reading a mesh is all fixed: 300 bytes a triangle binary STL's header counts, else 24 a byte.
TEST(Mesh, ReadingCostsPerTriangleOfBinaryStlElsePerByte) {
  write_stl(test_box(), temp_file("box.stl"));
  const std::uintmax_t bytes = std::filesystem::file_size(temp_file("box.stl"));
  std::string head(std::size_t{84}, '\0');
  std::ifstream(temp_file("box.stl"), std::ios::binary).read(head.data(), 84);
  const MemoryCost stl = read_mesh_cost(temp_file("box.stl"), bytes, head);
  EXPECT_DOUBLE_EQ(stl.fixed_bytes, 12 * 300.0);
  EXPECT_DOUBLE_EQ(stl.bytes(), stl.fixed_bytes);
  EXPECT_DOUBLE_EQ(read_mesh_cost("box.obj", 1000, head).bytes(), 24'000.0);
  EXPECT_DOUBLE_EQ(read_mesh_cost("box.stl", 1000, "solid box\n").bytes(), 24'000.0);  // ASCII STL
}

TEST(Mesh, ANestedShellInOneBodyIsACavity) {
  // The outer and the inner box in one object, both wound outward in the file: the inner one is a cavity.
  TriangleMesh both = make_box({100, 100, 50});
  const TriangleMesh inner = make_box({20, 30, 10}, {40, 30, 20});
  for (auto t : inner.triangles) {
    for (int& v : t) v += 8;
    both.triangles.push_back(t);
  }
  both.vertices.insert(both.vertices.end(), inner.vertices.begin(), inner.vertices.end());
  write_text(temp_file("cavity.obj"), obj({{"hollow", both}}));
  MeshReport report;
  const TriangleMesh m = read_mesh(temp_file("cavity.obj"), 1.0, &report);
  EXPECT_EQ(report.bodies, 1);
  EXPECT_EQ(report.shells, 2);
  EXPECT_EQ(report.cavities, 1);
  EXPECT_EQ(report.reversed_shells, 1);
  EXPECT_NEAR(m.volume_mm3(), 100.0 * 100 * 50 - 20.0 * 30 * 10, 1e-6);
  EXPECT_NEAR(area_at(m, 25), 10000.0 - 600.0, 1e-6);
  EXPECT_NEAR(area_at(m, 10), 10000.0, 1e-6);
}

TEST(Mesh, ThreeMfObjectsAreBodiesWithTheirPlacement) {
  const TriangleMesh a = test_box(), b = make_box({5, 5, 5});
  write_text(temp_file("placed.3mf"), three_mf({{"left", a}, {"right", b}}, "1 0 0 0 1 0 0 0 1 100 0 0"));
  MeshReport report;
  const TriangleMesh m = read_mesh(temp_file("placed.3mf"), 1.0, &report);
  EXPECT_EQ(report.bodies, 2);
  EXPECT_NEAR(m.min_corner().x(), 100.0, 1e-9);  // the build item's transform is baked in
  EXPECT_NEAR(m.max_corner().x(), 111.0, 1e-9);
  EXPECT_NEAR(m.volume_mm3(), kVolume + 125.0, 1e-6);
  EXPECT_EQ(m.body_names.size(), 2u);
}

TEST(Mesh, UnreadableFilesAreInputErrorsNamingTheFile) {
  write_text(temp_file("empty.stl"), "");
  EXPECT_NE(read_error(temp_file("empty.stl")).find("empty"), std::string::npos);
  write_text(temp_file("text.stl"), "this is a shopping list, not a mesh\n");
  EXPECT_NE(read_error(temp_file("text.stl"))
                .find("not an STL: 36 bytes, shorter than a binary STL's 84-byte header"),
            std::string::npos)
      << read_error(temp_file("text.stl"));
  // Binary STL: cut short, a header counting what no file this size holds, and no triangles at all.
  std::string binary(84, '\0');
  binary[80] = 100;  // 100 triangles
  binary += std::string(12 * 50, '\0');
  write_text(temp_file("cut.stl"), binary);
  EXPECT_NE(read_error(temp_file("cut.stl"))
                .find("truncated binary STL: its header counts 100 triangles (5084 bytes), the file has 684 "
                      "bytes (12 "
                      "whole triangles)"),
            std::string::npos)
      << read_error(temp_file("cut.stl"));
  binary[83] = 100;  // about 1.7 billion triangles
  write_text(temp_file("garbage.stl"), binary);
  EXPECT_NE(read_error(temp_file("garbage.stl")).find("not an STL: as binary STL its header would count"),
            std::string::npos);
  write_text(temp_file("none.stl"), std::string(84, '\0'));
  EXPECT_NE(read_error(temp_file("none.stl")).find("the binary STL holds no triangles"), std::string::npos);
  write_text(temp_file("text.obj"), "this is a shopping list, not a mesh\n");
  read_error(temp_file("text.obj"));
  write_text(temp_file("notes.txt"), "this is a shopping list, not a mesh\n");
  read_error(temp_file("notes.txt"));
  // A malformed ASCII STL, with many facets after the bad number: assimp quotes the rest of the file, which
  // the message cuts short.
  std::string bad = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 garbage 0\n";
  for (int i = 0; i < 100; ++i) bad += "vertex 0 1 0\n";
  write_text(temp_file("bad.stl"), bad);
  const std::string message = read_error(temp_file("bad.stl"));
  EXPECT_NE(message.find("cannot read the mesh"), std::string::npos) << message;
  EXPECT_LT(message.size(), 400u) << message;
  write_text(temp_file("short.stl"), std::string(90, 'x'));
  read_error(temp_file("short.stl"));
  EXPECT_NE(read_error(temp_file("missing.stl")).find("no such mesh file"), std::string::npos);
  // Points and lines only.
  write_text(temp_file("lines.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
  EXPECT_NE(read_error(temp_file("lines.obj")).find("no triangles"), std::string::npos);
  // Only degenerate faces.
  write_text(temp_file("flat.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 2\nf 2 3 3\n");
  EXPECT_NE(read_error(temp_file("flat.obj")).find("after repair"), std::string::npos);
  write_text(temp_file("point.obj"), "v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n");
  EXPECT_NE(read_error(temp_file("point.obj")).find("after repair"), std::string::npos);
}

TEST(Mesh, NonFiniteCoordinatesAreInputErrors) {
  write_text(temp_file("nan.stl"),
             "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 nan\nvertex 0 1 0\nendloop\n"
             "endfacet\nendsolid t\n");
  EXPECT_NE(read_error(temp_file("nan.stl")).find("not a finite number: (1, 0, nan)"), std::string::npos);
  TriangleMesh box = test_box();
  box.vertices[3].y() = std::numeric_limits<double>::quiet_NaN();
  write_stl(box, temp_file("nan_binary.stl"));
  EXPECT_NE(read_error(temp_file("nan_binary.stl")).find("not a finite number"), std::string::npos);
}

TEST(Mesh, AnAbsurdSizeIsAnInputError) {
  write_text(temp_file("huge.obj"), obj({{"box", make_box({5000, 100, 100})}}));
  EXPECT_NO_THROW((void)read_mesh(temp_file("huge.obj")));                              // 5 m
  EXPECT_NE(read_error(temp_file("huge.obj"), 25.4).find("units"), std::string::npos);  // 127 m
  EXPECT_THROW((void)read_mesh(temp_file("huge.obj"), 0.0), InputError);
}

TEST(Mesh, SelectBodyOfAMeshWithoutBodyTags) {
  TriangleMesh m = make_box({1, 2, 3});
  m.body.clear();
  m.body_names.clear();
  const TriangleMesh b = select_body(m, 0);
  EXPECT_EQ(b.triangles.size(), 12u);
  EXPECT_EQ(b.body_names, std::vector<std::string>{"part"});
  EXPECT_NEAR(b.volume_mm3(), 6.0, 1e-12);
}

TEST(MeshRepair, RepairsAHandBuiltMesh) {
  TriangleMesh box = test_box();
  std::swap(box.triangles[2][0], box.triangles[2][1]);
  MeshReport report;
  const TriangleMesh m = repair_mesh(box, report);
  EXPECT_EQ(report.flipped_faces, 1);
  EXPECT_NEAR(m.volume_mm3(), kVolume, 1e-6);
  add_repair_warnings(report, "box");
  EXPECT_EQ(report.warnings, std::vector<std::string>{"box: 1 face was flipped to match its neighbours"});
}

}  // namespace
}  // namespace beadtwin::slicer
