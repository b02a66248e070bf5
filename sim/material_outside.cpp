#include "sim/material_outside.hpp"

#include <algorithm>
#include <array>
#include <vector>

#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace beadtwin::sim {

MaterialOutside measure_material_outside(const openvdb::FloatGrid& fill,
                                         const openvdb::FloatGrid& cad_distance, double voxel_mm) {
  openvdb::tree::LeafManager<const openvdb::FloatTree> leaves(fill.tree());
  std::vector<std::array<double, 2>> per_leaf(leaves.leafCount(), {0.0, 0.0});  // material, outside
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.leafCount()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      const auto ca = cad_distance.getConstUnsafeAccessor();
                      for (std::size_t l = range.begin(); l < range.end(); ++l)
                        for (auto it = leaves.leaf(l).cbeginValueOn(); it; ++it) {
                          const double share =
                              std::clamp(0.5 + ca.getValue(it.getCoord()) / voxel_mm, 0.0, 1.0);
                          per_leaf[l][0] += *it;
                          per_leaf[l][1] += *it * share;
                        }
                    });
  double material = 0.0, outside = 0.0;
  for (const auto& [m, o] : per_leaf) material += m, outside += o;
  MaterialOutside out;
  out.volume_mm3 = outside * (voxel_mm * voxel_mm * voxel_mm);
  out.fraction = material > 0 ? outside / material : 0.0;
  return out;
}

}  // namespace beadtwin::sim
