#include "sim/porosity.hpp"

#include <algorithm>
#include <vector>

#include <openvdb/tools/Filter.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.hpp"

namespace beadtwin::sim {

namespace {

constexpr float kSolidFill = 0.5f;
const openvdb::Coord kPlanSteps[] = {openvdb::Coord(1, 0, 0), openvdb::Coord(0, 1, 0)};

using FillAccessor = openvdb::FloatGrid::ConstAccessor;
using Leaves = openvdb::tree::LeafManager<const openvdb::FloatTree>;

bool solid(const FillAccessor& fill, const openvdb::Coord& ijk) {
  return fill.getValue(ijk) >= kSolidFill;
}

// From solid voxel `from`, walks along `step` over non-solid voxels; if another solid voxel closes the run
// within `max_gap` voxels, appends the run's voxels to `out`. Every gap is found once, from its lower end.
void append_gap(const FillAccessor& fill, const openvdb::Coord& from, const openvdb::Coord& step, int max_gap,
                std::vector<openvdb::Coord>& out) {
  openvdb::Coord at = from + step;
  if (solid(fill, at)) return;
  for (int length = 1; length <= max_gap; ++length, at += step) {
    if (!solid(fill, at + step)) continue;
    for (openvdb::Coord v = from + step; v != at + step; v += step) out.push_back(v);
    return;
  }
}

// How many of the six faces of solid voxel `offset` of `leaf` face a voxel that is not solid. Neighbours
// inside the leaf are read from it directly, the others through the accessor.
int open_faces(const openvdb::FloatTree::LeafNodeType& leaf, openvdb::Index offset,
               const FillAccessor& fill) {
  using Leaf = openvdb::FloatTree::LeafNodeType;
  constexpr int kLast = static_cast<int>(Leaf::DIM) - 1;
  const openvdb::Coord local = Leaf::offsetToLocalCoord(offset);
  const openvdb::Coord ijk = leaf.origin() + local;
  // Offsets of one step along x, y and z inside a leaf.
  constexpr openvdb::Index kStride[3] = {Leaf::DIM * Leaf::DIM, Leaf::DIM, 1};
  int open = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const int at = local[axis];
    openvdb::Coord step(0, 0, 0);
    step[axis] = 1;
    open += at > 0 ? leaf.getValue(offset - kStride[axis]) < kSolidFill : !solid(fill, ijk - step);
    open += at < kLast ? leaf.getValue(offset + kStride[axis]) < kSolidFill : !solid(fill, ijk + step);
  }
  return open;
}

// Runs `per_leaf(leaf, accessor) -> double` over all leaves in parallel; sums in leaf order, so the result
// never depends on the number of threads.
template <class F>
double sum_over_leaves(const openvdb::FloatGrid& fill, const Leaves& leaves, F per_leaf) {
  std::vector<double> partial(leaves.leafCount(), 0.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.leafCount()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      const FillAccessor accessor = fill.getConstAccessor();
                      for (std::size_t n = range.begin(); n != range.end(); ++n)
                        partial[n] = per_leaf(n, leaves.leaf(n), accessor);
                    });
  double total = 0.0;
  for (const double p : partial) total += p;
  return total;
}

}  // namespace

Porosity measure_porosity(const openvdb::FloatGrid& fill, int max_gap_voxels, openvdb::MaskGrid* gaps_out) {
  BT_CHECK_OP(max_gap_voxels, >=, 1);
  const Leaves leaves(fill.tree());
  Porosity result;

  // Material, and the enclosed gaps each leaf's solid voxels open.
  std::vector<std::vector<openvdb::Coord>> gaps(leaves.leafCount());
  std::vector<std::size_t> faces(leaves.leafCount(), 0);
  result.material_voxels = sum_over_leaves(
      fill, leaves,
      [&](std::size_t n, const openvdb::FloatTree::LeafNodeType& leaf, const FillAccessor& accessor) {
        double material = 0.0;
        for (auto it = leaf.cbeginValueOn(); it; ++it) {
          material += *it;
          if (*it < kSolidFill) continue;
          faces[n] += open_faces(leaf, it.pos(), accessor);
          for (const openvdb::Coord& step : kPlanSteps)
            append_gap(accessor, it.getCoord(), step, max_gap_voxels, gaps[n]);
        }
        return material;
      });
  for (const std::size_t f : faces) result.surface_faces += f;

  // A gap closed along both x and y is one void: the mask holds each voxel once.
  openvdb::MaskGrid enclosed;
  {
    auto mask = enclosed.getAccessor();
    for (const auto& leaf_gaps : gaps)
      for (const openvdb::Coord& v : leaf_gaps) mask.setValueOn(v);
  }
  {
    const FillAccessor accessor = fill.getConstAccessor();
    for (auto it = enclosed.cbeginValueOn(); it; ++it)
      result.void_voxels += 1.0 - accessor.getValue(it.getCoord());
  }

  // Solid voxels not quite full, inside the envelope in plan.
  result.void_voxels += sum_over_leaves(
      fill, leaves,
      [&enclosed](std::size_t, const openvdb::FloatTree::LeafNodeType& leaf, const FillAccessor& accessor) {
        const auto mask = enclosed.getConstAccessor();
        const auto in_envelope = [&](const openvdb::Coord& ijk) {
          return solid(accessor, ijk) || mask.isValueOn(ijk);
        };
        double void_voxels = 0.0;
        for (auto it = leaf.cbeginValueOn(); it; ++it) {
          if (*it < kSolidFill || *it >= 1.0f) continue;
          const openvdb::Coord c = it.getCoord();
          if (in_envelope(c.offsetBy(1, 0, 0)) && in_envelope(c.offsetBy(-1, 0, 0)) &&
              in_envelope(c.offsetBy(0, 1, 0)) && in_envelope(c.offsetBy(0, -1, 0)))
            void_voxels += 1.0 - *it;
        }
        return void_voxels;
      });
  if (gaps_out) gaps_out->tree().merge(enclosed.tree());
  return result;
}

openvdb::FloatGrid::Ptr local_porosity(const openvdb::FloatGrid& fill, const openvdb::MaskGrid& gaps,
                                       int radius_voxels) {
  BT_CHECK(radius_voxels >= 1);
  // Two fields on the envelope: the void in each voxel and the envelope's amount (material + void). Their
  // box means over the same cube divide to the local void fraction, whatever the cube's share of outside
  // air (which counts in neither).
  auto void_grid = openvdb::FloatGrid::create(0.0f);
  void_grid->setTransform(fill.transform().copy());
  void_grid->tree().topologyUnion(fill.tree());
  void_grid->tree().topologyUnion(gaps.tree());
  auto envelope = void_grid->deepCopy();
  {
    auto fill_at = fill.getConstAccessor();
    auto gap_at = gaps.getConstAccessor();
    auto env_at = envelope->getAccessor();
    for (auto it = void_grid->beginValueOn(); it; ++it) {
      const openvdb::Coord c = it.getCoord();
      const float f = std::clamp(fill_at.getValue(c), 0.0f, 1.0f);
      const float v = gap_at.isValueOn(c) ? 1.0f - f : 0.0f;
      it.setValue(v);
      env_at.setValue(c, f + v);
    }
  }
  openvdb::tools::Filter<openvdb::FloatGrid> void_filter(*void_grid);
  void_filter.mean(radius_voxels);
  openvdb::tools::Filter<openvdb::FloatGrid> envelope_filter(*envelope);
  envelope_filter.mean(radius_voxels);
  auto env_at = envelope->getConstAccessor();
  for (auto it = void_grid->beginValueOn(); it; ++it) {
    const float e = env_at.getValue(it.getCoord());
    it.setValue(e > 0.0f ? *it / e : 0.0f);
  }
  void_grid->setName("porosity");
  return void_grid;
}

}  // namespace beadtwin::sim
