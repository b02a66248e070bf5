// The deposit's voxel fields as files: a .vtu parsed back block by block and value by value, and a .vdb read
// back with OpenVDB as Blender and Houdini read it.
#include "sim/deposit_files.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>

#include <openvdb/io/File.h>

#include "tests/read_file.hpp"
#include "tests/sim/ring_deposit.hpp"

namespace beadtwin::sim {
namespace {

using beadtwin::testing::read_file;
using testing::fresh_dir;
using testing::get;
using testing::ring;

// A .vtu as a reader sees it: the counts from the XML, and each appended array's bytes.
struct Vtu {
  std::string xml;
  std::size_t points = 0, cells = 0;
  std::map<std::string, std::string> type;  // array name -> VTK type
  std::map<std::string, std::string> data;  // array name -> its bytes, without the block header
};

// Parses what the VTK XML reader needs: the header, the arrays' offsets, and the appended blocks, each a
// UInt64 byte count then the bytes; the blocks must tile the appended data exactly.
Vtu parse_vtu(const std::string& file) {
  Vtu v;
  const std::string marker = "<AppendedData encoding=\"raw\">\n_";
  const std::size_t data_at = file.find(marker);
  if (data_at == std::string::npos) throw std::runtime_error("no raw appended data");
  v.xml = file.substr(0, data_at);
  const std::size_t start = data_at + marker.size();
  std::smatch m;
  if (!std::regex_search(v.xml, m, std::regex(R"re(NumberOfPoints="(\d+)" NumberOfCells="(\d+)")re")))
    throw std::runtime_error("no piece counts");
  v.points = std::stoul(m[1]);
  v.cells = std::stoul(m[2]);
  const std::regex array(
      R"re(<DataArray type="(\w+)" Name="(\w+)"[^>]* format="appended" offset="(\d+)"/>)re");
  std::size_t expected_offset = 0;
  for (auto it = std::sregex_iterator(v.xml.begin(), v.xml.end(), array); it != std::sregex_iterator();
       ++it) {
    const std::string name = (*it)[2];
    const std::size_t offset = std::stoul((*it)[3]);
    if (offset != expected_offset) throw std::runtime_error(name + ": blocks do not follow each other");
    const auto bytes = get<std::uint64_t>(file, start + offset);
    v.type[name] = (*it)[1];
    v.data[name] = file.substr(start + offset + 8, bytes);
    if (v.data[name].size() != bytes) throw std::runtime_error(name + ": block runs past the file");
    expected_offset = offset + 8 + bytes;
  }
  if (file.substr(start + expected_offset) != "\n  </AppendedData>\n</VTKFile>\n")
    throw std::runtime_error("the file does not end after the last block");
  return v;
}

TEST(DepositVtu, ParsesBackWithTheDepositsVoxelsAndValues) {
  const Deposit& d = ring();
  const auto path = fresh_dir("files_vtu") / "fields.vtu";
  const VtuCounts counts = write_deposit_vtu(d, path);
  const Vtu v = parse_vtu(read_file(path));
  EXPECT_NE(v.xml.find(R"(<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" )"
                       R"(header_type="UInt64">)"),
            std::string::npos)
      << v.xml;
  EXPECT_EQ(v.cells, d.active_voxels);
  EXPECT_EQ(counts.cells, v.cells);
  EXPECT_EQ(counts.points, v.points);
  ASSERT_EQ(v.type.at("Points"), "Float32");
  ASSERT_EQ(v.type.at("connectivity"), "Int32");
  ASSERT_EQ(v.type.at("offsets"), "Int32");
  ASSERT_EQ(v.type.at("types"), "UInt8");
  ASSERT_EQ(v.type.at("fill"), "Float32");
  ASSERT_EQ(v.type.at("time_s"), "Float32");
  ASSERT_EQ(v.type.at("layer"), "Int32");
  ASSERT_EQ(v.data.at("Points").size(), 12 * v.points);
  ASSERT_EQ(v.data.at("connectivity").size(), 4 * 8 * v.cells);
  ASSERT_EQ(v.data.at("offsets").size(), 4 * v.cells);
  ASSERT_EQ(v.data.at("types").size(), v.cells);
  for (const char* field : {"fill", "time_s", "layer"})
    ASSERT_EQ(v.data.at(field).size(), 4 * v.cells) << field;

  // Points are the voxels' corners, each once: shared between neighbouring cells.
  const double s = d.voxel_size_mm;
  std::set<std::tuple<int, int, int>> corners;
  for (auto it = d.fill->cbeginValueOn(); it; ++it)
    for (int c = 0; c < 8; ++c)
      corners.emplace(it.getCoord().x() + (c & 1), it.getCoord().y() + (c >> 1 & 1),
                      it.getCoord().z() + (c >> 2));
  EXPECT_EQ(v.points, corners.size());
  EXPECT_LT(v.points, 8 * v.cells / 2);

  const std::string& pts = v.data.at("Points");
  const auto point = [&](std::int32_t i) {
    const std::size_t at = 12 * static_cast<std::size_t>(i);
    return openvdb::Vec3d(get<float>(pts, at), get<float>(pts, at + 4), get<float>(pts, at + 8));
  };
  auto fill = d.fill->getConstAccessor();
  auto time = d.time->getConstAccessor();
  auto layer = d.layer->getConstAccessor();
  double volume = 0.0;
  int layers_seen = 0;
  for (std::size_t c = 0; c < v.cells; ++c) {
    ASSERT_EQ(get<std::int32_t>(v.data.at("offsets"), 4 * c), static_cast<std::int32_t>(8 * (c + 1)));
    ASSERT_EQ(get<std::uint8_t>(v.data.at("types"), c), 11);  // VTK_VOXEL
    // VTK_VOXEL: corner k is the lowest corner plus (k & 1, k >> 1 & 1, k >> 2) voxels.
    const auto conn = [&](int k) { return get<std::int32_t>(v.data.at("connectivity"), 4 * (8 * c + k)); };
    const openvdb::Vec3d lo = point(conn(0));
    for (int k = 1; k < 8; ++k) {
      const openvdb::Vec3d step = (point(conn(k)) - lo) / s;
      ASSERT_NEAR(step.x(), k & 1, 1e-4);
      ASSERT_NEAR(step.y(), k >> 1 & 1, 1e-4);
      ASSERT_NEAR(step.z(), k >> 2, 1e-4);
    }
    // The cell is voxel (i,j,k) spanning [i, i+1)·s: its values are that voxel's.
    const openvdb::Coord ijk(static_cast<int>(std::lround(lo.x() / s)),
                             static_cast<int>(std::lround(lo.y() / s)),
                             static_cast<int>(std::lround(lo.z() / s)));
    ASSERT_TRUE(fill.isValueOn(ijk)) << ijk;
    const float f = get<float>(v.data.at("fill"), 4 * c);
    EXPECT_EQ(f, fill.getValue(ijk));
    EXPECT_EQ(get<float>(v.data.at("time_s"), 4 * c), time.getValue(ijk));
    const auto l = get<std::int32_t>(v.data.at("layer"), 4 * c);
    EXPECT_EQ(l, layer.getValue(ijk));
    layers_seen = std::max(layers_seen, l + 1);
    volume += f * s * s * s;
  }
  EXPECT_EQ(layers_seen, 4);
  EXPECT_NEAR(volume / d.deposited_volume_mm3, 1.0, 1e-5);
}

// A Python that has VTK (Debian's python3-vtk9 installs it for the system's Python, which need not be the
// first python3 on the PATH); empty when none has.
std::string python_with_vtk() {
  for (const std::string python : {"python3", "/usr/bin/python3"})
    if (std::system((python + " -c 'import vtk' >/dev/null 2>&1").c_str()) == 0) return python;
  return {};
}

// ParaView's own reader, when this machine has VTK's Python module.
TEST(DepositVtu, VtkReadsIt) {
  const std::string python = python_with_vtk();
  if (python.empty()) GTEST_SKIP() << "no VTK for Python here (Debian: python3-vtk9)";
  const auto dir = fresh_dir("files_vtk");
  write_deposit_vtu(ring(), dir / "fields.vtu");
  const std::string script =
      "import vtk; r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName('" + (dir / "fields.vtu").string() +
      "'); r.Update(); g = r.GetOutput(); c = g.GetCellData(); "
      "print(g.GetNumberOfCells(), g.GetNumberOfPoints(), g.GetCellType(0), "
      "c.GetArray('fill').GetRange()[1], "
      "c.GetArray('layer').GetRange()[1], c.GetArray('time_s').GetRange()[1], g.GetBounds()[4], "
      "r.GetErrorCode())";
  const std::string out = (dir / "vtk.txt").string();
  ASSERT_EQ(std::system((python + " -c \"" + script + "\" > " + out + " 2>&1").c_str()), 0) << read_file(out);
  std::istringstream words(read_file(out));
  std::size_t cells = 0, points = 0;
  int type = 0, error = -1;
  double max_fill = 0, max_layer = 0, max_time = 0, z_min = 1;
  words >> cells >> points >> type >> max_fill >> max_layer >> max_time >> z_min >> error;
  EXPECT_EQ(error, 0) << read_file(out);
  EXPECT_EQ(cells, ring().active_voxels) << read_file(out);
  EXPECT_GT(points, cells);
  EXPECT_EQ(type, 11);  // VTK_VOXEL
  EXPECT_NEAR(max_fill, 1.0, 1e-6);
  EXPECT_EQ(max_layer, 3);
  EXPECT_GT(max_time, 0.0);
  EXPECT_NEAR(z_min, 0.0, 1e-6);  // the first layer sits on the table, z = 0
}

TEST(DepositVdb, ReadsBackWithNamesClassesAndUnits) {
  const Deposit& d = ring();
  const auto dir = fresh_dir("files_vdb");
  write_deposit_vdb(d, dir / "deposit.vdb");
  openvdb::io::File file((dir / "deposit.vdb").string());
  file.open();
  const auto meta = file.getMetadata();
  EXPECT_EQ(meta->metaValue<std::string>("length_unit"), "mm");
  EXPECT_EQ(meta->metaValue<double>("voxel_size_mm"), d.voxel_size_mm);
  EXPECT_EQ(meta->metaValue<std::string>("creator"), "beadtwin");
  const openvdb::GridPtrVecPtr grids = file.getGrids();
  file.close();
  std::map<std::string, openvdb::GridBase::Ptr> by_name;
  for (const auto& g : *grids) by_name[g->getName()] = g;
  ASSERT_EQ(by_name.size(), 5u);  // fill, density, time_s, layer, move
  const auto fill = openvdb::gridPtrCast<openvdb::FloatGrid>(by_name.at("fill"));
  const auto density = openvdb::gridPtrCast<openvdb::FloatGrid>(by_name.at("density"));
  const auto time = openvdb::gridPtrCast<openvdb::FloatGrid>(by_name.at("time_s"));
  const auto layer = openvdb::gridPtrCast<openvdb::Int32Grid>(by_name.at("layer"));
  const auto move = openvdb::gridPtrCast<openvdb::Int32Grid>(by_name.at("move"));
  ASSERT_TRUE(fill && density && time && layer && move);
  EXPECT_EQ(static_cast<std::size_t>(move->activeVoxelCount()), d.active_voxels);
  EXPECT_EQ(fill->getGridClass(), openvdb::GRID_FOG_VOLUME);
  EXPECT_EQ(density->getGridClass(), openvdb::GRID_FOG_VOLUME);
  EXPECT_EQ(time->metaValue<std::string>("unit"), "s");
  EXPECT_EQ(static_cast<std::size_t>(fill->activeVoxelCount()), d.active_voxels);
  EXPECT_EQ(static_cast<std::size_t>(density->activeVoxelCount()), d.active_voxels);
  EXPECT_EQ(fill->transform(), d.fill->transform());
  auto original = d.fill->getConstAccessor();
  auto dens = density->getConstAccessor();
  for (auto it = fill->cbeginValueOn(); it; ++it) {
    ASSERT_EQ(*it, original.getValue(it.getCoord()));
    ASSERT_EQ(*it, dens.getValue(it.getCoord()));
  }
  // The deposit's own grids keep their names.
  EXPECT_EQ(d.time->getName(), "time");
}

TEST(DepositVdb, DensityIsAnInstanceNotASecondCopy) {
  const Deposit& d = ring();
  const auto dir = fresh_dir("files_vdb_size");
  write_deposit_vdb(d, dir / "deposit.vdb");
  // The same grids without the density alias.
  openvdb::FloatGrid::Ptr fill = d.fill->copy(), time = d.time->copy();
  openvdb::Int32Grid::Ptr layer = d.layer->copy(), move = d.move->copy();
  fill->setName("fill");
  time->setName("time_s");
  openvdb::io::File((dir / "three.vdb").string()).write({fill, time, layer, move});
  EXPECT_LT(std::filesystem::file_size(dir / "deposit.vdb"),
            std::filesystem::file_size(dir / "three.vdb") + 4096);
}

TEST(DepositFiles, EmptyDepositIsAnErrorAndWritesNothing) {
  const Deposit empty = testing::empty_deposit();
  const auto dir = fresh_dir("files_empty");
  for (const char* name : {"fields.vtu", "deposit.vdb"}) {
    const auto path = dir / name;
    try {
      if (path.extension() == ".vtu")
        write_deposit_vtu(empty, path);
      else
        write_deposit_vdb(empty, path);
      FAIL() << "wrote " << path;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("no material"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(DepositFiles, UnwritablePlaceIsAnErrorNamingThePathAndLeavesNothing) {
  const auto dir = fresh_dir("files_unwritable");
  std::ofstream(dir / "a-file") << "x";
  for (const auto& path : {dir / "no-such-folder" / "fields.vtu", dir / "a-file" / "fields.vtu",
                           dir / "no-such-folder" / "deposit.vdb"}) {
    try {
      if (path.extension() == ".vtu")
        write_deposit_vtu(ring(), path);
      else
        write_deposit_vdb(ring(), path);
      FAIL() << "wrote " << path;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()),
            1);
}

}  // namespace
}  // namespace beadtwin::sim
