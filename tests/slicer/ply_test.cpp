// The PLY reader (slicer/ply.hpp), through read_mesh as a run reads a part: text and binary of both byte
// orders give the same solid, and every count the file does not hold is a message at its line or byte.
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "slicer/mesh.hpp"

namespace beadtwin::slicer {
namespace {

std::filesystem::path temp_file(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return std::filesystem::temp_directory_path() /
         fmt::format("bt_ply_{}_{}_{}", info->test_suite_name(), info->name(), name);
}

std::filesystem::path write(const std::string& name, const std::string& bytes) {
  const std::filesystem::path path = temp_file(name);
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::string error_of(const std::filesystem::path& path) {
  try {
    (void)read_mesh(path);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "reading " << path << " did not fail";
  return {};
}

// A 10 x 20 x 30 mm box as six quads, corners counter-clockwise seen from outside.
const double kBox[8][3] = {{0, 0, 0},  {10, 0, 0},  {10, 20, 0},  {0, 20, 0},
                           {0, 0, 30}, {10, 0, 30}, {10, 20, 30}, {0, 20, 30}};
const int kQuads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
constexpr double kBoxVolume = 10.0 * 20.0 * 30.0;

std::string header(const std::string& format, const std::string& vertex_type, const std::string& count_type,
                   const std::string& index_type) {
  return fmt::format(
      "ply\nformat {} 1.0\ncomment made by ply_test\nelement vertex 8\nproperty {} x\nproperty {} y\n"
      "property {} z\nproperty uchar red\nelement face 6\nproperty list {} {} vertex_indices\n"
      "property float quality\nend_header\n",
      format, vertex_type, vertex_type, vertex_type, count_type, index_type);
}

std::string text_box() {
  std::string s = header("ascii", "float", "uchar", "int");
  for (const auto& p : kBox) s += fmt::format("{} {} {} 255\n", p[0], p[1], p[2]);
  for (const auto& q : kQuads) s += fmt::format("4 {} {} {} {} 0.5\n", q[0], q[1], q[2], q[3]);
  return s;
}

template <class T>
void put(std::string& s, T value, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if (big != (std::endian::native == std::endian::big)) std::reverse(b, b + sizeof(T));
  s.append(b, sizeof(T));
}

std::string binary_box(bool big) {
  std::string s = header(big ? "binary_big_endian" : "binary_little_endian", "double", "ushort", "uint");
  for (const auto& p : kBox) {
    for (double c : p) put(s, c, big);
    put(s, std::uint8_t{255}, big);
  }
  for (const auto& q : kQuads) {
    put(s, std::uint16_t{4}, big);
    for (int v : q) put(s, static_cast<std::uint32_t>(v), big);
    put(s, 0.5f, big);
  }
  return s;
}

TEST(Ply, TextAndBinaryOfBothByteOrdersGiveTheSameBox) {
  for (const auto& [name, bytes] :
       {std::pair{"text.ply", text_box()}, std::pair{"little.ply", binary_box(false)},
        std::pair{"big.ply", binary_box(true)}}) {
    MeshReport report;
    const std::filesystem::path path = write(name, bytes);
    const TriangleMesh m = read_mesh(path, 1.0, &report);
    EXPECT_EQ(m.triangles.size(), 12u) << name;
    EXPECT_EQ(m.vertices.size(), 8u) << name;
    EXPECT_NEAR(m.volume_mm3(), kBoxVolume, 1e-9) << name;
    EXPECT_TRUE(m.max_corner().isApprox(Eigen::Vector3d(10, 20, 30))) << name;
    EXPECT_EQ(report.flipped_faces, 0) << name;
    EXPECT_EQ(report.open_edges, 0) << name;
    ASSERT_EQ(m.body_names.size(), 1u) << name;
    EXPECT_EQ(m.body_names[0], path.stem().string());
  }
  // Inches, and a file whose name does not say PLY but whose first line does.
  EXPECT_NEAR(read_mesh(write("box.model", text_box()), 25.4).volume_mm3(), kBoxVolume * 25.4 * 25.4 * 25.4,
              1e-6);
}

TEST(Ply, TheVertexElementMayComeAfterTheFaces) {
  const std::string s =
      "ply\nformat ascii 1.0\nelement face 4\nproperty list uchar int vertex_index\nelement vertex 4\n"
      "property float z\nproperty float y\nproperty float x\nend_header\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
      "0 0 0\n0 0 10\n0 10 0\n10 0 0\n";
  const TriangleMesh m = read_mesh(write("after.ply", s));
  EXPECT_NEAR(m.volume_mm3(), 1000.0 / 6, 1e-9);
}

TEST(Ply, AListCountThatTheLineDoesNotHoldIsAMessageNotAnAllocation) {
  // Found by tests/fuzz: assimp 5.2 resizes a list to its count before reading it, and a count of four
  // billion asked for 26 GB. Here the entries are read one by one, and the line ends first.
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  const std::string message = error_of(write("count.ply", head + "4000000000 0 1 2\n"));
  EXPECT_NE(message.find("count.ply:13:"), std::string::npos) << message;
  EXPECT_NE(message.find("the list 'vertex_indices' counts 4000000000 entries, but the line ends after 3"),
            std::string::npos)
      << message;
  EXPECT_NE(error_of(write("neg.ply", head + "-3 0 1 2\n")).find("counts -3 entries: not a whole number"),
            std::string::npos);

  // Binary: the count is checked against the bytes left before anything is read.
  const std::string bin_header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n";
  std::string bin = bin_header;
  for (int i = 0; i < 9; ++i) put(bin, i == 3 || i == 7 ? 1.0f : 0.0f, false);
  put(bin, std::uint32_t{4000000000u}, false);
  for (int v : {0, 1, 2}) put(bin, v, false);
  const std::string binary = error_of(write("count-bin.ply", bin));
  EXPECT_NE(binary.find(fmt::format("face 1 of 1 (at byte {}): its list 'vertex_indices' counts 4000000000 "
                                    "entries of 4 bytes, but only 12 bytes are left",
                                    bin_header.size() + 36)),
            std::string::npos)
      << binary;
}

TEST(Ply, CountsAndNumbersTheFileDoesNotHoldAreMessagesAtTheirLine) {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const auto expect = [&](const std::string& name, const std::string& body, const std::string& what) {
    const std::string message = error_of(write(name, head + body));
    EXPECT_NE(message.find(what), std::string::npos) << name << ": " << message;
  };
  expect("short.ply", "0 0 0\n1 0 0\n",
         ":3:1: the header counts 3 'vertex' elements of at least 6 bytes each");
  expect("ends.ply", "0 0 0\n100000 0 0\n", "ends.ply:12: the file ends after 2 of the 3 'vertex' elements");
  expect("index.ply", "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
         ":13:7: a face refers to vertex 3, but the file has 3 vertices (counted from 0)");
  expect("word.ply", "0 0 0\n1 zero 0\n0 1 0\n",
         ":11:3: 'zero' is not a number (property 'y' of element 'vertex')");
  expect("more.ply", "0 0 0\n1 0 0 7\n0 1 0\n",
         ":11:7: more numbers on the line than element 'vertex' has properties");
  expect("fewer.ply", "0 0 0\n1 0\n0 1 0\n\n",
         ":11:4: the line ends before vertex 'vertex' has its property 'z'");
  expect("nan.ply", "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n",
         ":11:7: a vertex has a coordinate that is not a finite number: (1, nan, 0)");
  expect("huge.ply", "0 0 0\n1e999 0 0\n0 1 0\n3 0 1 2\n", "not a finite number: (inf, 0, 0)");

  // Counts in the header beyond what the bytes after it can hold, before anything is read.
  const std::string many =
      error_of(write("many.ply",
                     "ply\nformat ascii 1.0\nelement vertex 999999999\nproperty float x\nproperty float y\n"
                     "property float z\nend_header\n0 0 0\n"));
  EXPECT_NE(many.find(":3:1: the header counts 999999999 'vertex' elements of at least 6 bytes each"),
            std::string::npos)
      << many;
  EXPECT_NE(
      error_of(write("nox.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nend_header\n0\n"))
          .find(":3:1: the PLY vertex element has no property x"),
      std::string::npos);
  EXPECT_NE(error_of(write("float-count.ply",
                           "ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\n"
                           "end_header\n"))
                .find(":4:1: a PLY list's count is a whole number: its type cannot be float"),
            std::string::npos);
}

TEST(Ply, ABinaryFileCutShortSaysWhereItEnds) {
  std::string bin = binary_box(false);
  bin.resize(bin.size() - 10);  // inside the last face's corners
  std::string message = error_of(write("corners.ply", bin));
  EXPECT_NE(
      message.find(fmt::format("face 6 of 6 (at byte {}): its list 'vertex_indices' counts 4 entries of 4 "
                               "bytes, but only 10 bytes are left in the file",
                               bin.size() - 12)),
      std::string::npos)
      << message;
  bin = binary_box(false);
  bin.resize(bin.size() - 2);  // inside its quality
  message = error_of(write("quality.ply", bin));
  EXPECT_NE(message.find(fmt::format("face 6 of 6 (at byte {}): the file ends inside it (property 'quality')",
                                     bin.size() - 2)),
            std::string::npos)
      << message;
}

}  // namespace
}  // namespace beadtwin::slicer
