#include "sim/voids.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <fmt/format.h>

#include "core/units.hpp"

namespace beadtwin::sim {

namespace {

const openvdb::Coord kFaces[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

// One connected piece of gap voxels and the beads around it.
struct Piece {
  double volume_voxels = 0.0;
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();  // sum of voxel centres weighted by their empty part
  std::vector<openvdb::Coord> voxels;
  std::set<int> moves;        // moves of the material next to it
  std::map<int, int> layers;  // layer of that material -> how many faces
};

bool is_boundary(const Move& m) {
  return m.feature == Feature::kBoundary || m.pass >= 0;
}

bool is_fill(const Move& m) {
  return m.feature == Feature::kFill;
}

// Two consecutive moves of one path turning by more than 90°.
bool sharp_turn_between(const Toolpath& tp, const std::set<int>& moves) {
  for (const int i : moves) {
    if (!moves.count(i + 1)) continue;
    const Move& a = tp.moves[static_cast<std::size_t>(i)];
    const Move& b = tp.moves[static_cast<std::size_t>(i) + 1];
    const Eigen::Vector2d u = (a.end - a.start).head<2>(), v = (b.end - b.start).head<2>();
    if (u.norm() > 0.0 && v.norm() > 0.0 && (a.end - b.start).norm() < 1e-3 && u.dot(v) < 0.0) return true;
  }
  return false;
}

std::string kind_of(const Toolpath& tp, const std::set<int>& moves) {
  if (sharp_turn_between(tp, moves)) return "at a zigzag turn";
  bool boundary = false, fill = false, other = false;
  for (const int i : moves) {
    if (i < 0 || static_cast<std::size_t>(i) >= tp.moves.size()) continue;
    const Move& m = tp.moves[static_cast<std::size_t>(i)];
    if (is_boundary(m)) {
      boundary = true;
    } else if (is_fill(m)) {
      fill = true;
    } else {
      other = true;
    }
  }
  if (boundary && fill) return "between fill and boundary";
  if (boundary && !fill && !other) return "between passes";
  if (fill && !boundary && !other) return "between fill beads";
  return "between beads";
}

}  // namespace

VoidsFound locate_voids(const openvdb::MaskGrid& gaps, const Deposit& deposit, const Toolpath& toolpath,
                        double min_volume_mm3, std::size_t max_listed) {
  VoidsFound out;
  out.layer_volume_mm3.assign(toolpath.layers.size(), 0.0);
  const double s = deposit.voxel_size_mm;
  const double voxel_volume = s * s * s;
  const auto fill = deposit.fill->getConstAccessor();
  const auto layer = deposit.layer->getConstAccessor();
  const auto move = deposit.move->getConstAccessor();
  const auto gap = gaps.getConstAccessor();
  openvdb::MaskGrid seen;
  auto visited = seen.getAccessor();
  std::vector<Piece> pieces;
  std::vector<openvdb::Coord> stack;
  for (auto it = gaps.cbeginValueOn(); it; ++it) {
    if (visited.isValueOn(it.getCoord())) continue;
    Piece piece;
    stack.assign(1, it.getCoord());
    visited.setValueOn(it.getCoord());
    while (!stack.empty()) {
      const openvdb::Coord c = stack.back();
      stack.pop_back();
      const double empty = 1.0 - std::clamp<double>(fill.getValue(c), 0.0, 1.0);
      piece.volume_voxels += empty;
      piece.weighted += empty * voxel_center_mm(c, s);
      piece.voxels.push_back(c);
      for (const openvdb::Coord& f : kFaces) {
        const openvdb::Coord n = c + f;
        if (gap.isValueOn(n)) {
          if (!visited.isValueOn(n)) {
            visited.setValueOn(n);
            stack.push_back(n);
          }
        } else if (fill.getValue(n) >= 0.5f) {
          piece.moves.insert(move.getValue(n));
          ++piece.layers[layer.getValue(n)];
        }
      }
    }
    pieces.push_back(std::move(piece));
  }
  std::vector<Defect> listed;
  for (Piece& p : pieces) {
    const double volume = p.volume_voxels * voxel_volume;
    // The layer most of its surroundings belong to (the lowest on a tie).
    int in_layer = -1, most = 0;
    for (const auto& [l, n] : p.layers)
      if (n > most) {
        most = n;
        in_layer = l;
      }
    if (in_layer >= 0 && static_cast<std::size_t>(in_layer) < out.layer_volume_mm3.size())
      out.layer_volume_mm3[static_cast<std::size_t>(in_layer)] += volume;
    if (volume < min_volume_mm3 || p.volume_voxels <= 0.0) continue;
    ++out.count;
    // Where it is: the voxel of the piece nearest its centre (a ring's centre is not in it).
    const Eigen::Vector3d centre = p.weighted / p.volume_voxels;
    Eigen::Vector3d at = voxel_center_mm(p.voxels.front(), s);
    for (const openvdb::Coord& c : p.voxels)
      if ((voxel_center_mm(c, s) - centre).squaredNorm() < (at - centre).squaredNorm())
        at = voxel_center_mm(c, s);
    p.moves.erase(-1);
    Defect d;
    d.kind = DefectKind::kVoid;
    d.position_mm = at;
    d.layer = in_layer;
    d.move = p.moves.empty() ? 0 : static_cast<std::size_t>(*p.moves.begin());
    d.source_line = p.moves.empty() ? 0 : toolpath.moves[d.move].source_line;
    d.size = volume;
    d.detail = kind_of(toolpath, p.moves);
    listed.push_back(std::move(d));
  }
  std::stable_sort(listed.begin(), listed.end(),
                   [](const Defect& a, const Defect& b) { return a.size > b.size; });
  if (listed.size() > max_listed) listed.resize(max_listed);
  out.defects = std::move(listed);
  return out;
}

}  // namespace beadtwin::sim
