// Tests of the material writer (sim/fill_writer.hpp): conservation, and its spreading rule against a plain
// restatement of that rule which reads every voxel of every ring, so that what FillWriter skips (the rings
// in slices with no gap or no room, found from its counts) is shown to change nothing, bit for bit.
#include "sim/fill_writer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <random>
#include <tuple>
#include <vector>

namespace beadtwin::sim {
namespace {

struct Grids {
  openvdb::FloatGrid::Ptr fill = openvdb::FloatGrid::create(0.0f);
  openvdb::FloatGrid::Ptr time = openvdb::FloatGrid::create(0.0f);
  openvdb::Int32Grid::Ptr layer = openvdb::Int32Grid::create(-1);
  openvdb::Int32Grid::Ptr move = openvdb::Int32Grid::create(-1);
};

using Key = std::tuple<int, int, int>;

// The rule of fill_writer.hpp, read voxel by voxel: every cell first takes what fits; the excess goes ring
// by ring (L1 in plan) into the gaps of its level within the spread radius, then into any free voxel within
// the squeeze radius, then up, each ring's voxels sharing it in proportion to their free room.
int level_of(const std::vector<CoverageCell>& cells) {
  return cells.empty() ? 0 : cells.front().ijk.z();
}

struct Reference {
  std::map<Key, float> fill;
  float at(int x, int y, int z) const {
    const auto it = fill.find({x, y, z});
    return it == fill.end() ? 0.0f : it->second;
  }
  void add(const std::vector<CoverageCell>& cells, double per_fraction, int spread_radius,
           int squeeze_radius) {
    std::vector<std::pair<openvdb::Coord, double>> overflow;
    for (const CoverageCell& c : cells) {
      const double before = at(c.ijk.x(), c.ijk.y(), c.ijk.z());
      const double after = before + c.fraction * per_fraction;
      if (after > 1.0) {
        fill[{c.ijk.x(), c.ijk.y(), c.ijk.z()}] = 1.0f;
        overflow.emplace_back(c.ijk, after - 1.0);
      } else {
        fill[{c.ijk.x(), c.ijk.y(), c.ijk.z()}] = static_cast<float>(after);
      }
    }
    for (const auto& [ijk, excess_at] : overflow) {
      double excess = excess_at;
      const auto ring = [&](int r, int k, bool gaps_only) {
        std::vector<std::pair<Key, double>> cells_of_ring;
        double room = 0.0;
        const auto consider = [&](int di, int dj) {
          const Key key{ijk.x() + di, ijk.y() + dj, k};
          const double held = at(std::get<0>(key), std::get<1>(key), k);
          if (held >= 1.0 || (gaps_only && held <= 0.0)) return;
          cells_of_ring.emplace_back(key, 1.0 - held);
          room += 1.0 - held;
        };
        if (r == 0) consider(0, 0);
        for (int di = -r; r > 0 && di <= r; ++di) {
          consider(di, r - std::abs(di));
          if (r != std::abs(di)) consider(di, -(r - std::abs(di)));
        }
        if (room <= 0.0) return false;
        const double share = std::min(1.0, excess / room);
        for (const auto& [key, free] : cells_of_ring)
          fill[key] = share >= 1.0 ? 1.0f : static_cast<float>(1.0 - free + share * free);
        excess -= share * room;
        return share < 1.0 || excess <= 0.0;
      };
      const int k0 = ijk.z();
      bool done = false;
      for (int r = 1; r <= spread_radius && !done; ++r) done = ring(r, k0, true);
      for (int r = 1; r <= squeeze_radius && !done; ++r) done = ring(r, k0, false);
      for (int up = 1; !done; ++up)
        for (int r = 0; r <= squeeze_radius && !done; ++r) done = ring(r, k0 + up, false);
    }
  }
};

// Beads of random cells, some overfilling, laid over a patch that crosses leaf borders and the origin (the
// leaves at negative indices). With `full_square`, a square of whole leaf slices at level 0 is filled first,
// so that spreads from inside it cross full slices on their way out.
void spread_as_the_rule(int spread_radius, int squeeze_radius, bool full_square) {
  SCOPED_TRACE(testing::Message() << "radii " << spread_radius << " " << squeeze_radius
                                  << (full_square ? ", full square" : ""));
  Grids g;
  Reference ref;
  double added = 0.0;
  {
    FillWriter writer(*g.fill, *g.time, *g.layer, *g.move);
    const auto lay = [&](const std::vector<CoverageCell>& cells, double p, int bead) {
      for (const CoverageCell& c : cells) added += c.fraction * p;
      writer.add(cells, p, {static_cast<double>(bead), 1.0, level_of(cells), bead}, spread_radius,
                 squeeze_radius);
      ref.add(cells, p, spread_radius, squeeze_radius);
    };
    if (full_square)
      for (int y = -16; y < 16; ++y) {
        std::vector<CoverageCell> row;
        for (int x = -16; x < 16; ++x) row.push_back({openvdb::Coord(x, y, 0), 1.0f, 0.5f});
        lay(row, 1.0, y);
      }
    std::mt19937 random(static_cast<unsigned>(spread_radius * 100 + squeeze_radius + (full_square ? 7 : 0)));
    std::uniform_int_distribution<int> plan(-20, 20), level(full_square ? 0 : -3, full_square ? 0 : 2),
        length(1, 30);
    std::uniform_real_distribution<float> fraction(0.05f, 1.0f);
    std::uniform_real_distribution<double> per_fraction(0.2, 2.5);
    for (int bead = 0; bead < 400; ++bead) {
      std::vector<CoverageCell> cells;
      const int x = plan(random), y = plan(random), z = level(random), n = length(random);
      const bool along_x = bead % 2 == 0;
      for (int i = 0; i < n; ++i) {
        const openvdb::Coord ijk(along_x ? x + i : x, along_x ? y : y + i, z);
        cells.push_back({ijk, fraction(random), 0.5f});
      }
      lay(cells, per_fraction(random), bead);
    }
  }
  std::size_t voxels = 0;
  double held = 0.0;
  for (const auto& [key, value] : ref.fill) {
    const auto [x, y, z] = key;
    ASSERT_EQ(g.fill->tree().getValue({x, y, z}), value) << "voxel " << x << " " << y << " " << z;
    voxels += value > 0.0f;
    held += value;
  }
  EXPECT_EQ(static_cast<std::size_t>(g.fill->activeVoxelCount()), voxels);
  EXPECT_NEAR(held, added, 1e-4 * added);  // nothing dropped
  // The writer's masks lived in the leaves' transient data, cleared when it was done.
  for (auto leaf = g.fill->tree().cbeginLeaf(); leaf; ++leaf) EXPECT_EQ(leaf->transientData(), 0u);
}

// The radii of a desktop bead and of an LSAM bead on coarse voxels, and beyond the 63 rings the writer's
// masks cover.
TEST(FillWriter, SpreadsAsItsRuleReadVoxelByVoxel) {
  for (const auto& [spread_radius, squeeze_radius] :
       {std::pair{3, 1}, std::pair{11, 1}, std::pair{13, 4}, std::pair{70, 2}})
    spread_as_the_rule(spread_radius, squeeze_radius, false);
}

// Spreads that start inside full slices and squeeze out past them.
TEST(FillWriter, SpreadsOutOfFullSlicesAsItsRule) {
  for (const auto& [spread_radius, squeeze_radius] : {std::pair{2, 6}, std::pair{11, 12}})
    spread_as_the_rule(spread_radius, squeeze_radius, true);
}

}  // namespace
}  // namespace beadtwin::sim
