#include "sim/deposit_files.hpp"

#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <openvdb/io/File.h>

#include "core/atomic_file.hpp"

namespace beadtwin::sim {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the .vtu says LittleEndian and copies the machine's bytes as they are");

void require_material(const Deposit& deposit, const std::filesystem::path& path) {
  if (!deposit.fill || !deposit.time || !deposit.layer)
    throw std::invalid_argument(fmt::format("cannot write {}: the deposit has no grids", path.string()));
  if (deposit.fill->activeVoxelCount() == 0)
    throw std::invalid_argument(fmt::format(
        "cannot write {}: the deposit holds no material, there is nothing to show", path.string()));
}

// A copy of `grid` that shares its tree, under another name.
template <class GridT>
typename GridT::Ptr named(const typename GridT::Ptr& grid, const std::string& name, const std::string& unit) {
  typename GridT::Ptr copy = grid->copy();
  copy->setName(name);
  copy->setCreator("beadtwin");
  copy->insertMeta("unit", openvdb::StringMetadata(unit));
  return copy;
}

// Bytes gathered into large writes: the .vtu is written a few values at a time, millions of times.
class Chunked {
 public:
  explicit Chunked(std::ostream& out) : out_(out) { buffer_.reserve(kSize); }
  ~Chunked() { flush(); }
  Chunked(const Chunked&) = delete;
  Chunked& operator=(const Chunked&) = delete;

  template <class T>
  void put(const T& value) {
    if (buffer_.size() + sizeof value > kSize) flush();
    const auto* bytes = reinterpret_cast<const char*>(&value);
    buffer_.insert(buffer_.end(), bytes, bytes + sizeof value);
  }
  void flush() {
    out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }

 private:
  static constexpr std::size_t kSize = std::size_t{1} << 20;
  std::ostream& out_;
  std::vector<char> buffer_;
};

// The corners of every voxel that holds material, numbered in the tree's order: value = point index.
// VTK_VOXEL's corner order: x fastest, then y, then z.
const openvdb::Coord kCorner[8] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
constexpr std::uint8_t kVtkVoxel = 11;

openvdb::Int64Tree number_corners(const openvdb::FloatTree& fill, std::size_t& count) {
  openvdb::Int64Tree corners(-1);
  {
    openvdb::tree::ValueAccessor<openvdb::Int64Tree> acc(corners);
    for (auto v = fill.cbeginValueOn(); v; ++v)
      for (const openvdb::Coord& c : kCorner) acc.setValueOn(v.getCoord() + c);
  }
  std::int64_t n = 0;
  for (auto leaf = corners.beginLeaf(); leaf; ++leaf)
    for (auto v = leaf->beginValueOn(); v; ++v) v.setValue(n++);
  count = static_cast<std::size_t>(n);
  return corners;
}

// The appended data blocks in the order they are written; each is a UInt64 byte count, then the values.
struct Layout {
  std::size_t cells = 0, points = 0, index_bytes = 4;
  std::uint64_t points_bytes() const { return 12 * points; }
  std::uint64_t connectivity_bytes() const { return 8 * index_bytes * cells; }
  std::uint64_t offsets_bytes() const { return index_bytes * cells; }
  std::uint64_t types_bytes() const { return cells; }
  std::uint64_t field_bytes() const { return 4 * cells; }  // fill, time_s, layer: 4 bytes each
};

std::string vtu_header(const Layout& l, double voxel_size_mm) {
  const char* index = l.index_bytes == 4 ? "Int32" : "Int64";
  std::uint64_t at = 0;
  const auto next = [&at](std::uint64_t bytes) {
    const std::uint64_t here = at;
    at += 8 + bytes;
    return here;
  };
  std::string x = "<?xml version=\"1.0\"?>\n";
  x += fmt::format(
      "<!-- beadtwin deposit: one VTK_VOXEL cell per voxel holding material, {} mm voxels, lengths in mm, "
      "time_s in seconds -->\n",
      voxel_size_mm);
  x += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
       "header_type=\"UInt64\">\n  <UnstructuredGrid>\n";
  x += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", l.points, l.cells);
  x += fmt::format(
      "      <Points>\n        <DataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\" "
      "format=\"appended\" offset=\"{}\"/>\n      </Points>\n",
      next(l.points_bytes()));
  x += "      <Cells>\n";
  x += fmt::format(
      "        <DataArray type=\"{}\" Name=\"connectivity\" format=\"appended\" offset=\"{}\"/>\n", index,
      next(l.connectivity_bytes()));
  x += fmt::format("        <DataArray type=\"{}\" Name=\"offsets\" format=\"appended\" offset=\"{}\"/>\n",
                   index, next(l.offsets_bytes()));
  x += fmt::format("        <DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"{}\"/>\n",
                   next(l.types_bytes()));
  x += "      </Cells>\n      <CellData Scalars=\"fill\">\n";
  for (const auto& [type, name] : {std::pair{"Float32", "fill"}, {"Float32", "time_s"}, {"Int32", "layer"}})
    x += fmt::format("        <DataArray type=\"{}\" Name=\"{}\" format=\"appended\" offset=\"{}\"/>\n", type,
                     name, next(l.field_bytes()));
  x += "      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n_";
  return x;
}

template <class Index>
void write_cells(const Deposit& d, const openvdb::Int64Tree& corners, const Layout& l, Chunked& out) {
  const openvdb::FloatTree& fill = d.fill->tree();
  out.put(std::uint64_t{l.connectivity_bytes()});
  openvdb::tree::ValueAccessor<const openvdb::Int64Tree> corner(corners);
  for (auto v = fill.cbeginValueOn(); v; ++v)
    for (const openvdb::Coord& c : kCorner) out.put(static_cast<Index>(corner.getValue(v.getCoord() + c)));
  out.put(std::uint64_t{l.offsets_bytes()});
  for (std::size_t i = 1; i <= l.cells; ++i) out.put(static_cast<Index>(8 * i));
  out.put(std::uint64_t{l.types_bytes()});
  for (std::size_t i = 0; i < l.cells; ++i) out.put(kVtkVoxel);
}

void write_fields(const Deposit& d, const Layout& l, Chunked& out) {
  const openvdb::FloatTree& fill = d.fill->tree();
  out.put(std::uint64_t{l.field_bytes()});
  for (auto v = fill.cbeginValueOn(); v; ++v) out.put(static_cast<float>(*v));
  out.put(std::uint64_t{l.field_bytes()});
  openvdb::tree::ValueAccessor<const openvdb::FloatTree> time(d.time->tree());
  for (auto v = fill.cbeginValueOn(); v; ++v) out.put(static_cast<float>(time.getValue(v.getCoord())));
  out.put(std::uint64_t{l.field_bytes()});
  openvdb::tree::ValueAccessor<const openvdb::Int32Tree> layer(d.layer->tree());
  for (auto v = fill.cbeginValueOn(); v; ++v)
    out.put(static_cast<std::int32_t>(layer.getValue(v.getCoord())));
}

}  // namespace

void write_deposit_vdb(const Deposit& deposit, const std::filesystem::path& path) {
  require_material(deposit, path);
  const openvdb::FloatGrid::Ptr fill = named<openvdb::FloatGrid>(deposit.fill, "fill", "fraction");
  fill->setGridClass(openvdb::GRID_FOG_VOLUME);
  const openvdb::FloatGrid::Ptr density = named<openvdb::FloatGrid>(deposit.fill, "density", "fraction");
  density->setGridClass(openvdb::GRID_FOG_VOLUME);
  openvdb::GridPtrVec grids = {fill, density, named<openvdb::FloatGrid>(deposit.time, "time_s", "s"),
                               named<openvdb::Int32Grid>(deposit.layer, "layer", "layer index")};
  if (deposit.move) grids.push_back(named<openvdb::Int32Grid>(deposit.move, "move", "toolpath move index"));
  openvdb::MetaMap meta;
  meta.insertMeta("voxel_size_mm", openvdb::DoubleMetadata(deposit.voxel_size_mm));
  write_vdb(grids, meta, path);
}

void write_vdb(const openvdb::GridPtrVec& grids, openvdb::MetaMap meta, const std::filesystem::path& path) {
  openvdb::initialize();
  meta.insertMeta("creator", openvdb::StringMetadata("beadtwin"));
  meta.insertMeta("length_unit", openvdb::StringMetadata("mm"));
  AtomicPath out(path);
  try {
    openvdb::io::File file(out.temp().string());
    file.write(grids, meta);
    file.close();
  } catch (const openvdb::Exception& e) {
    throw std::runtime_error(fmt::format("cannot write {}: {}", path.string(), e.what()));
  }
  out.commit();
}

VtuCounts write_deposit_vtu(const Deposit& deposit, const std::filesystem::path& path) {
  require_material(deposit, path);
  // Active tiles (a block of voxels stored as one value) become voxels, so every cell is one voxel.
  Deposit d = deposit;
  if (deposit.fill->tree().hasActiveTiles()) {
    openvdb::FloatGrid::Ptr copy = deposit.fill->deepCopy();
    copy->tree().voxelizeActiveTiles();
    d.fill = copy;
  }
  Layout l;
  l.cells = static_cast<std::size_t>(d.fill->activeVoxelCount());
  const openvdb::Int64Tree corners = number_corners(d.fill->tree(), l.points);
  constexpr auto kInt32Max = static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());
  l.index_bytes = l.points <= kInt32Max && 8 * l.cells <= kInt32Max ? 4 : 8;

  AtomicStream file(path);
  file.stream() << vtu_header(l, d.voxel_size_mm);
  {
    Chunked out(file.stream());
    out.put(std::uint64_t{l.points_bytes()});
    const openvdb::math::Transform& xf = d.fill->transform();
    const openvdb::Vec3d half(0.5);
    // Index-space corner (i,j,k) is the lower corner of voxel (i,j,k): its centre less half a voxel.
    for (auto leaf = corners.cbeginLeaf(); leaf; ++leaf)
      for (auto v = leaf->cbeginValueOn(); v; ++v) {
        const openvdb::Vec3d p = xf.indexToWorld(v.getCoord().asVec3d() - half);
        for (int a = 0; a < 3; ++a) out.put(static_cast<float>(p[a]));
      }
    if (l.index_bytes == 4)
      write_cells<std::int32_t>(d, corners, l, out);
    else
      write_cells<std::int64_t>(d, corners, l, out);
    write_fields(d, l, out);
  }
  file.stream() << "\n  </AppendedData>\n</VTKFile>\n";
  file.commit();
  return {l.cells, l.points};
}

}  // namespace beadtwin::sim
