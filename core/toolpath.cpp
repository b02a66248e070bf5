#include "core/toolpath.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/memory.hpp"

namespace beadtwin {

std::string_view to_string(MoveKind kind) {
  switch (kind) {
    case MoveKind::kPrint:
      return "print";
    case MoveKind::kTravel:
      return "travel";
    case MoveKind::kDwell:
      return "dwell";
  }
  return "?";
}

std::string_view to_string(Feature feature) {
  switch (feature) {
    case Feature::kUnknown:
      return "unknown";
    case Feature::kTravel:
      return "travel";
    case Feature::kRaft:
      return "raft";
    case Feature::kBoundary:
      return "boundary";
    case Feature::kFill:
      return "fill";
    case Feature::kLeadIn:
      return "lead-in";
    case Feature::kLeadOut:
      return "lead-out";
    case Feature::kCoast:
      return "coast";
    case Feature::kStockOnTop:
      return "stock-on-top";
    case Feature::kThinWall:
      return "thin-wall";
    case Feature::kPrime:
      return "prime";
    case Feature::kReverse:
      return "reverse";
  }
  return "?";
}

std::string_view to_string(ExtruderEvent event) {
  switch (event) {
    case ExtruderEvent::kNone:
      return "none";
    case ExtruderEvent::kMeltOn:
      return "melt-on";
    case ExtruderEvent::kMeltOff:
      return "melt-off";
    case ExtruderEvent::kPrime:
      return "prime";
    case ExtruderEvent::kCoast:
      return "coast";
    case ExtruderEvent::kReverse:
      return "reverse";
    case ExtruderEvent::kHeatOn:
      return "heat-on";
    case ExtruderEvent::kHeatOff:
      return "heat-off";
  }
  return "?";
}

double Toolpath::commanded_volume_mm3() const {
  double v = 0.0;
  for (const Move& m : moves) v += m.volume_mm3;
  return v;
}

double Toolpath::print_length_mm() const {
  double l = 0.0;
  for (const Move& m : moves)
    if (m.kind == MoveKind::kPrint) l += m.length_mm();
  return l;
}

double Toolpath::travel_length_mm() const {
  double l = 0.0;
  for (const Move& m : moves)
    if (m.kind == MoveKind::kTravel) l += m.length_mm();
  return l;
}

double Toolpath::total_time_s() const {
  if (moves.empty()) return 0.0;
  return moves.back().start_s + moves.back().duration_s;
}

void Toolpath::index_layers() {
  for (auto& layer : layers) {
    layer.first_move = layer.end_move = 0;
    layer.start_s = layer.end_s = 0.0;
  }
  std::vector<bool> seen(layers.size(), false);
  int current = -1;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const int l = moves[i].layer;
    if (l < 0) continue;
    BT_CHECK_OP(static_cast<std::size_t>(l), <, layers.size());
    ToolpathLayer& layer = layers[static_cast<std::size_t>(l)];
    if (l != current) {
      if (seen[static_cast<std::size_t>(l)])
        throw InternalError("toolpath layer " + std::to_string(l) + " is not contiguous in the move list");
      seen[static_cast<std::size_t>(l)] = true;
      layer.first_move = i;
      layer.start_s = moves[i].start_s;
      current = l;
    }
    layer.end_move = i + 1;
    layer.end_s = moves[i].start_s + moves[i].duration_s;
  }
}

namespace {

// Duration of a straight move of length L from speed v0 to v1 with cruise speed vc and acceleration a,
// where v0 and v1 are reachable (the planner guarantees it).
double trapezoid_time(double length, double v0, double vc, double v1, double a) {
  const double d_acc = (vc * vc - v0 * v0) / (2 * a);
  const double d_dec = (vc * vc - v1 * v1) / (2 * a);
  if (d_acc + d_dec <= length) return (vc - v0) / a + (vc - v1) / a + (length - d_acc - d_dec) / vc;
  // Triangle: peak speed where acceleration and deceleration meet.
  const double vp = std::sqrt(std::max(0.0, (2 * a * length + v0 * v0 + v1 * v1) / 2));
  return (vp - v0) / a + (vp - v1) / a;
}

// std::min(cap, std::sqrt(y)), the root taken only where it may be the smaller (it seldom is, and the
// passes over the moves wait on it): y above cap² by more than rounding can account for has a root, rounded
// correctly and so no smaller than the double cap, no smaller than cap.
double min_root(double cap, double y) {
  if (y > cap * cap * (1.0 + 1e-12)) return cap;
  return std::min(cap, std::sqrt(y));
}

// The motion plan: calls `timed(i, start_s, duration_s)` for every move in order. Each move's length is
// found once.
template <class Timed>
void plan_motion(const std::vector<Move>& moves, const MotionLimits& limits, Timed&& timed) {
  const double a = limits.acceleration_mm_s2;
  BT_CHECK(a > 0.0);
  const std::size_t n = moves.size();
  // Three numbers a move: for a long program, memory worth having in huge pages (core/memory.hpp).
  std::vector<double> length, cruise, entry;
  for (std::vector<double>* v : {&length, &cruise, &entry}) reserve_huge(*v, n + 1);
  length.resize(n);
  cruise.resize(n);
  entry.assign(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const Move& m = moves[i];
    length[i] = m.length_mm();
    const double cap = m.kind == MoveKind::kTravel ? limits.max_travel_mm_s : limits.max_feed_mm_s;
    cruise[i] = m.kind == MoveKind::kDwell ? 0.0 : std::min(m.feed_mm_s > 0 ? m.feed_mm_s : cap, cap);
  }
  // Junction speed between consecutive motion moves (junction-deviation model). Instantaneous events (dwells
  // of no duration) stop the head, except before a coast: the pump stops and the head moves on.
  const auto instant = [&](std::size_t i) {
    return moves[i].kind == MoveKind::kDwell && !(moves[i].duration_s > 0.0);
  };
  for (std::size_t i = 1; i < n; ++i) {
    std::size_t before = i - 1, after = i;
    while (before > 0 && instant(before)) --before;
    while (after + 1 < n && instant(after)) ++after;
    const bool into_coast = moves[before].kind == MoveKind::kPrint &&
                            moves[after].feature == Feature::kCoast && moves[after].kind == MoveKind::kPrint;
    const std::size_t pi = into_coast ? before : i - 1;
    const std::size_t mi = into_coast ? after : i;
    const Move& p = moves[pi];
    const Move& m = moves[mi];
    if (length[pi] <= 0 || length[mi] <= 0 || p.kind == MoveKind::kDwell || m.kind == MoveKind::kDwell)
      continue;
    // As Eigen's normalized(): the vector over its norm.
    const Eigen::Vector3d u = (p.end - p.start) / length[pi];
    const Eigen::Vector3d w = (m.end - m.start) / length[mi];
    const double cos_theta =
        std::clamp(-u.dot(w), -1.0, 1.0);  // angle between reversed incoming and outgoing
    double vj = std::min(cruise[pi], cruise[mi]);
    if (cos_theta > -0.999999) {
      const double sin_half = std::sqrt(std::max(0.0, 0.5 * (1.0 - cos_theta)));
      if (sin_half < 0.999999) {
        const double r = limits.junction_deviation_mm * sin_half / (1.0 - sin_half);
        vj = std::min(vj, std::sqrt(a * r));
      }
    }
    entry[i] = vj;
  }
  // Backward then forward pass so every speed change is reachable within the move's length.
  for (std::size_t i = n; i-- > 0;)
    entry[i] = min_root(entry[i], entry[i + 1] * entry[i + 1] + 2 * a * length[i]);
  for (std::size_t i = 0; i < n; ++i)
    entry[i + 1] = min_root(entry[i + 1], entry[i] * entry[i] + 2 * a * length[i]);
  double t = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Move& m = moves[i];
    if (m.kind == MoveKind::kDwell) {
      timed(i, t, m.duration_s);
      t += m.duration_s;
      continue;
    }
    if (length[i] <= 0.0 || cruise[i] <= 0.0) {
      timed(i, t, 0.0);
      continue;
    }
    const double vc = std::max({cruise[i], entry[i], entry[i + 1]});
    const double d = trapezoid_time(length[i], entry[i], vc, entry[i + 1], a);
    timed(i, t, d);
    t += d;
  }
}

}  // namespace

void time_toolpath(Toolpath& toolpath, const MotionLimits& limits) {
  plan_motion(toolpath.moves, limits, [&](std::size_t i, double start_s, double duration_s) {
    toolpath.moves[i].start_s = start_s;
    toolpath.moves[i].duration_s = duration_s;
  });
  toolpath.index_layers();
}

double motion_time_s(const Toolpath& toolpath, const MotionLimits& limits) {
  double end_s = 0.0;
  plan_motion(toolpath.moves, limits,
              [&](std::size_t, double start_s, double duration_s) { end_s = start_s + duration_s; });
  return end_s;
}

}  // namespace beadtwin
