#include "thermal/snapshot_files.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "sim/deposit_files.hpp"

namespace beadtwin::thermal {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the VTK file says LittleEndian: the machine's bytes are copied as they are");

// Appended raw binary arrays of VTK XML: each a UInt64 byte count, then the values.
template <class T>
void append_block(std::ostream& out, const std::vector<T>& values) {
  const auto bytes = static_cast<std::uint64_t>(values.size() * sizeof(T));
  out.write(reinterpret_cast<const char*>(&bytes), sizeof bytes);
  out.write(reinterpret_cast<const char*>(values.data()), static_cast<std::streamsize>(bytes));
}

}  // namespace

void write_temperature_vdb(const ThermalMesh& mesh, const TemperatureSnapshot& snapshot,
                           const std::filesystem::path& path) {
  BT_CHECK(mesh.cell_grid != nullptr);
  BT_CHECK_OP(snapshot.temp_c.size(), ==, mesh.cells.size());
  auto temperature = openvdb::FloatGrid::create(std::numeric_limits<float>::quiet_NaN());
  temperature->setTransform(mesh.cell_grid->transform().copy());
  temperature->setName("temperature_c");
  temperature->insertMeta("unit", openvdb::StringMetadata("degC"));
  {
    openvdb::FloatGrid::Accessor out = temperature->getAccessor();
    for (auto it = mesh.cell_grid->cbeginValueOn(); it; ++it) {
      const float t = snapshot.temp_c[static_cast<std::size_t>(*it)];
      if (!std::isnan(t)) out.setValue(it.getCoord(), t);
    }
  }
  openvdb::MetaMap meta;
  meta.insertMeta("time_s", openvdb::DoubleMetadata(snapshot.time_s));
  sim::write_vdb(openvdb::GridPtrVec{temperature}, meta, path);
}

std::size_t write_temperature_vtp(const ThermalMesh& mesh, const TemperatureSnapshot& snapshot,
                                  const std::filesystem::path& path) {
  BT_CHECK_OP(snapshot.temp_c.size(), ==, mesh.cells.size());
  std::vector<float> points, temperature, volume, birth;
  std::vector<std::int32_t> layer;
  for (std::size_t i = 0; i < mesh.cells.size(); ++i) {
    if (std::isnan(snapshot.temp_c[i])) continue;
    const ThermalCell& c = mesh.cells[i];
    for (int k = 0; k < 3; ++k) points.push_back(static_cast<float>(c.centroid_mm[k]));
    temperature.push_back(snapshot.temp_c[i]);
    volume.push_back(static_cast<float>(c.volume_mm3));
    birth.push_back(static_cast<float>(c.birth_s));
    layer.push_back(c.layer);
  }
  const std::size_t n = temperature.size();
  std::vector<std::int64_t> connectivity(n), offsets(n);
  for (std::size_t i = 0; i < n; ++i) {
    connectivity[i] = static_cast<std::int64_t>(i);
    offsets[i] = static_cast<std::int64_t>(i + 1);
  }
  // Byte offsets of the appended blocks, in the order they follow the header.
  std::uint64_t offset = 0;
  const auto next = [&](std::size_t bytes) {
    const std::uint64_t at = offset;
    offset += sizeof(std::uint64_t) + bytes;
    return at;
  };
  const std::uint64_t at_points = next(points.size() * sizeof(float));
  const std::uint64_t at_temp = next(n * sizeof(float));
  const std::uint64_t at_volume = next(n * sizeof(float));
  const std::uint64_t at_birth = next(n * sizeof(float));
  const std::uint64_t at_layer = next(n * sizeof(std::int32_t));
  const std::uint64_t at_conn = next(n * sizeof(std::int64_t));
  const std::uint64_t at_off = next(n * sizeof(std::int64_t));
  AtomicStream file(path);
  std::ostream& out = file.stream();
  out << "<?xml version=\"1.0\"?>\n"
      << "<!-- beadtwin thermal cells at t = " << fmt::format("{:.3f}", snapshot.time_s)
      << " s: centroids in mm, temperature in degC -->\n"
      << "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "<PolyData>\n"
      << fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfVerts=\"{}\">\n", n, n)
      << fmt::format(
             "<FieldData><DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
             "format=\"ascii\">{}</DataArray></FieldData>\n",
             snapshot.time_s)
      << "<PointData Scalars=\"temperature_c\">\n"
      << fmt::format(
             "<DataArray type=\"Float32\" Name=\"temperature_c\" format=\"appended\" offset=\"{}\"/>\n",
             at_temp)
      << fmt::format("<DataArray type=\"Float32\" Name=\"volume_mm3\" format=\"appended\" offset=\"{}\"/>\n",
                     at_volume)
      << fmt::format("<DataArray type=\"Float32\" Name=\"birth_s\" format=\"appended\" offset=\"{}\"/>\n",
                     at_birth)
      << fmt::format("<DataArray type=\"Int32\" Name=\"layer\" format=\"appended\" offset=\"{}\"/>\n",
                     at_layer)
      << "</PointData>\n<Points>\n"
      << fmt::format(
             "<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"appended\" offset=\"{}\"/>\n",
             at_points)
      << "</Points>\n<Verts>\n"
      << fmt::format("<DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\"{}\"/>\n",
                     at_conn)
      << fmt::format("<DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"{}\"/>\n",
                     at_off)
      << "</Verts>\n</Piece>\n</PolyData>\n<AppendedData encoding=\"raw\">\n_";
  append_block(out, points);
  append_block(out, temperature);
  append_block(out, volume);
  append_block(out, birth);
  append_block(out, layer);
  append_block(out, connectivity);
  append_block(out, offsets);
  out << "\n</AppendedData>\n</VTKFile>\n";
  file.commit();
  return n;
}

}  // namespace beadtwin::thermal
