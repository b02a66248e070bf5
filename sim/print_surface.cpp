#include "sim/print_surface.hpp"

#include <limits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "sim/closed_voids.hpp"
#include "sim/skin.hpp"
#include "sim/slits.hpp"

namespace beadtwin::sim {

int plate_row(const openvdb::FloatGrid& fill) {
  int lowest = std::numeric_limits<int>::max();
  for (auto it = fill.cbeginValueOn(); it; ++it)
    if (*it >= kPrintedFill) lowest = std::min(lowest, it.getCoord().z());
  if (lowest == std::numeric_limits<int>::max())
    throw InputError(
        fmt::format("nothing was deposited: no voxel of the deposit is at least {} full", kPrintedFill));
  return lowest;
}

openvdb::FloatGrid::Ptr solid_print(const openvdb::FloatGrid& fill, int plate_k, bool on_plate, int depth) {
  auto solid = fill.deepCopy();
  solid->tree().voxelizeActiveTiles();  // the slits are looked for voxel by voxel
  openvdb::CoordBBox box = fill.evalActiveVoxelBoundingBox();
  box.expand(1);
  if (on_plate) box.min().z() = plate_k;
  fill_slits(*solid, kPrintedFill);
  fill_closed_voids(*solid, box, !on_plate, kPrintedFill);
  if (!on_plate) return solid;
  std::vector<std::pair<openvdb::Coord, float>> row;
  for (auto it = solid->cbeginValueOn(); it; ++it)
    if (it.getCoord().z() == plate_k) row.emplace_back(it.getCoord(), *it);
  auto acc = solid->getAccessor();
  for (const auto& [ijk, value] : row)
    for (int k = 1; k <= depth; ++k) acc.setValue(ijk.offsetBy(0, 0, -k), value);
  return solid;
}

NearestTriangles print_surface(const openvdb::FloatGrid::Ptr& solid) {
  constexpr double kAdaptivity = 0.01;
  Deposit as_printed;
  as_printed.fill = solid;
  const SkinMesh mesh = extract_skin(as_printed, kAdaptivity, /*outer_only=*/false);
  const std::vector<openvdb::Vec3s>& p = mesh.points_mm;
  std::vector<std::array<unsigned, 3>> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const openvdb::Vec3I& t : mesh.triangles)
    if ((p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).lengthSqr() > 0) triangles.push_back({t[0], t[1], t[2]});
  return NearestTriangles(p, triangles);
}

}  // namespace beadtwin::sim
