// What is wrong with a deposit, where it is and what caused it: the defects the deposit reports
// (sim/deposit.hpp), how runs of them are merged, and the check that needs the toolpath alone: corners
// tighter than the roller can follow. Travel moves that run into the part as it stands are measured apart
// (sim/travel_collision.hpp), and so are the voids (sim/voids.hpp); material ploughed by the roller, beads
// laid over nothing and the nozzle running into material above a bead are found while laying
// (sim/deposit.cpp). The report's types (scenarios/input/result.hpp) hold these defects, so this header
// leaves OpenVDB out.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/toolpath.hpp"

namespace beadtwin::sim {

// Runs of consecutive pieces with the same problem are one defect.
enum class DefectKind : std::uint8_t {
  kVoid,          // an enclosed void between beads (size: its volume, mm³)
  kPlough,        // material pushed above the roller's gap (size: the volume, mm³)
  kUnsupported,   // a bead laid over nothing within a layer height (size: the span's length, mm)
  kRollerCorner,  // the roller engaged through a corner tighter than it can follow (size: the turn, degrees)
  kCollision,     // the nozzle or roller runs into material standing above it (size: how deep, mm)
};
std::string_view to_string(DefectKind kind);

// One defect, where it is and what caused it.
struct Defect {
  DefectKind kind = DefectKind::kVoid;
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();  // where it starts (a void: its centre)
  int layer = -1;
  std::size_t move = 0;  // index into Toolpath::moves of the move that caused it (a void: a bead next to it)
  int source_line = 0;   // the program line of that move; 0 for planned toolpaths
  double size = 0.0;     // see DefectKind
  std::string detail;    // one line for a person
};

// The defect in one line for a person, from its kind, size and (for a void, or a collision on a travel
// move: "travel") its detail so far.
std::string describe(const Defect& defect);

// Defects found while laying, in the order found, with runs of consecutive pieces merged into one.
class DefectLog {
 public:
  // A defect of `kind` at piece number `piece` (pieces count up along the toolpath), caused by move number
  // `move_index` (`move`, for its layer and source line), at `where` (mm), of `size`. When the last defect of
  // this kind was noted at the piece before, in the same layer, it grows instead: by `size` when `add_up`
  // (volumes, lengths), to the larger of the two otherwise (depths).
  void note(DefectKind kind, std::size_t piece, std::size_t move_index, const Move& move,
            const Eigen::Vector3d& where, double size, bool add_up);
  void add(Defect d) { defects_.push_back(std::move(d)); }  // as it is, merging nothing
  // The last defect added grows to `size` when that is larger. Precondition: one was added.
  void grow_last(double size) { defects_.back().size = std::max(defects_.back().size, size); }
  std::vector<Defect> take() { return std::move(defects_); }  // every defect logged; the log is spent

 private:
  std::vector<Defect> defects_;
  std::array<std::optional<std::size_t>, 8> last_piece_{};
  std::array<std::size_t, 8> last_defect_{};
};

// Logs the corners of `toolpath` that a roller `roller_width_mm` wide (> 0) cannot follow. A steered roller
// turns about the nozzle as the path turns; its inner edge stands still on a turn of radius half its width,
// and would have to run backwards on a tighter one, so it skids and lifts. The path's radius at a joint of
// two print moves with the roller down is judged over a window of half the roller's width centred on it: a
// turn of more than one radian within it is a radius under half the width. A run of such joints within a
// window of each other is one defect, its size the largest turn in degrees.
void roller_corners(const Toolpath& toolpath, double roller_width_mm, DefectLog& log);

}  // namespace beadtwin::sim
