#include "sim/defects.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/geometry.hpp"
#include "core/units.hpp"

namespace beadtwin::sim {

std::string_view to_string(DefectKind kind) {
  switch (kind) {
    case DefectKind::kVoid:
      return "void";
    case DefectKind::kPlough:
      return "plough";
    case DefectKind::kUnsupported:
      return "unsupported";
    case DefectKind::kRollerCorner:
      return "roller_corner";
    case DefectKind::kCollision:
      return "collision";
  }
  return "?";
}

std::string describe(const Defect& d) {
  switch (d.kind) {
    case DefectKind::kVoid:
      return fmt::format("void of {:.3g} mm³ {}", d.size, d.detail);
    case DefectKind::kPlough:
      return fmt::format("the roller ploughs {:.3g} mm³ of material above its gap", d.size);
    case DefectKind::kUnsupported:
      return fmt::format("{:.3g} mm of bead laid over nothing (no material within a layer below)", d.size);
    case DefectKind::kRollerCorner:
      return fmt::format(
          "the roller stays down through a turn of {:.0f}° within half its width: tighter than it "
          "can follow (lift it, or round the corner)",
          d.size);
    case DefectKind::kCollision:
      return d.detail == "travel"
                 ? fmt::format("a travel move runs {:.3g} mm into the part", d.size)
                 : fmt::format(
                       "the nozzle and roller run into material standing {:.3g} mm above the bead's top",
                       d.size);
  }
  return {};
}

void DefectLog::note(DefectKind kind, std::size_t piece, std::size_t move_index, const Move& move,
                     const Eigen::Vector3d& where, double size, bool add_up) {
  auto& last = last_piece_[static_cast<std::size_t>(kind)];
  auto& index = last_defect_[static_cast<std::size_t>(kind)];
  if (last && *last + 1 == piece && defects_[index].layer == move.layer) {
    Defect& d = defects_[index];
    d.size = add_up ? d.size + size : std::max(d.size, size);
  } else {
    index = defects_.size();
    defects_.push_back({kind, where, move.layer, move_index, move.source_line, size, {}});
  }
  last = piece;
}

namespace {

// A joint between two print moves with the roller down: its distance along the chain of joined moves (mm),
// its turn (radians, signed) and the move after it.
struct Joint {
  double s = 0.0, turn = 0.0;
  std::size_t move = 0;
};

// Logs the joints of one chain whose turns within half a window either side add up to more than a radian.
void flag_tight_joints(const Toolpath& toolpath, const std::vector<Joint>& chain, double window,
                       DefectLog& log) {
  bool open = false;  // a run of flagged joints is being built
  double last_s = -std::numeric_limits<double>::infinity();
  for (const Joint& j : chain) {
    double total = 0.0;
    for (const Joint& o : chain)
      if (std::abs(o.s - j.s) <= 0.5 * window) total += std::abs(o.turn);
    if (total <= 1.0) continue;
    const Move& m = toolpath.moves[j.move];
    const double degrees = total * 180.0 / kPi;
    if (open && j.s - last_s <= window) {
      log.grow_last(degrees);
    } else {
      log.add({DefectKind::kRollerCorner, m.start, m.layer, j.move, m.source_line, degrees, {}});
      open = true;
    }
    last_s = j.s;
  }
}

}  // namespace

void roller_corners(const Toolpath& toolpath, double roller_width_mm, DefectLog& log) {
  const double window = 0.5 * roller_width_mm;
  std::vector<Joint> chain;
  const auto flush = [&] {
    flag_tight_joints(toolpath, chain, window, log);
    chain.clear();
  };
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  double s = 0.0;
  std::size_t previous = kNone;
  for (std::size_t i = 0; i < toolpath.moves.size(); ++i) {
    const Move& m = toolpath.moves[i];
    const Eigen::Vector2d d = (m.end - m.start).head<2>();
    if (m.kind != MoveKind::kPrint || !m.roller_down || !m.deposits() || d.norm() <= 1e-9) {
      if (m.length_mm() > 0.0 || m.kind == MoveKind::kPrint) {
        flush();
        previous = kNone;
      }
      continue;
    }
    if (previous != kNone) {
      const Move& p = toolpath.moves[previous];
      const Eigen::Vector2d u = (p.end - p.start).head<2>().normalized(), v = d.normalized();
      if ((p.end - m.start).norm() <= 1e-3) {
        chain.push_back({s, turn_rad(u, v), i});
      } else {
        flush();
        s = 0.0;
      }
    }
    s += d.norm();
    previous = i;
  }
  flush();
}

}  // namespace beadtwin::sim
