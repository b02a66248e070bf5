#include "sim/sweep_plan.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>

#include "core/error.hpp"
#include "core/units.hpp"

namespace beadtwin::sim {

namespace {

constexpr double kJoinToleranceMm = 1e-3;  // how close two moves' end and start must be to continue a bead
constexpr double kPuddleLengthMm = 1e-6;   // plan length below which a move is a puddle
// Sharpest turn still joined (170°): beyond it the bisector cut would run far along both beads.
const double kMinJoinCos = std::cos(170.0 / 180.0 * kPi);

BeadSweep sweep_of(const Move& move, bool round_free_ends) {
  BeadSweep s;
  s.start_xy = move.start.head<2>();
  s.end_xy = move.end.head<2>();
  s.start_top_mm = move.start.z();
  s.end_top_mm = move.end.z();
  const Eigen::Vector2d axis = s.end_xy - s.start_xy;
  if (axis.norm() <= kPuddleLengthMm) {
    s.start_xy = s.end_xy;
    s.start_top_mm = s.end_top_mm;
    s.profile = puddle_profile(move.volume_mm3, move.layer_height_mm);
    return s;
  }
  s.profile = moving_bead_profile(move.volume_mm3 / move.length_mm(), move.layer_height_mm);
  if (!round_free_ends) s.start_cut = s.end_cut = axis.normalized();
  return s;
}

Eigen::Vector2d direction(const BeadSweep& s) {
  return (s.end_xy - s.start_xy).normalized();
}

// The bisector normal if `second` continues `first`, nothing otherwise.
std::optional<Eigen::Vector2d> joint(const BeadSweep& first, const BeadSweep& second) {
  if (first.is_puddle() || second.is_puddle()) return std::nullopt;
  if ((first.end_xy - second.start_xy).norm() > kJoinToleranceMm) return std::nullopt;
  if (std::abs(first.end_top_mm - second.start_top_mm) > kJoinToleranceMm) return std::nullopt;
  const Eigen::Vector2d u = direction(first);
  const Eigen::Vector2d v = direction(second);
  if (u.dot(v) < kMinJoinCos) return std::nullopt;
  return Eigen::Vector2d((u + v).normalized());
}

void join(BeadSweep& first, BeadSweep& second, const Eigen::Vector2d& bisector) {
  first.end_cut = bisector;
  second.start_cut = bisector;
}

// How far after the melt off ooze is followed: beyond five time constants less than 1 % is left.
constexpr double kOozeTimeConstants = 5.0;

// The ooze pieces after the melt off at `off`. `bead` is the bead's pieces (since its melt on, or the
// previous melt off): they give the material up in proportion to their own, at most half of it.
std::vector<PlannedSweep> ooze_after(const Toolpath& tp, std::size_t off, std::span<PlannedSweep> bead,
                                     double tau) {
  std::vector<PlannedSweep> out;
  const Move& last = tp.moves[bead.back().move];
  if (!(last.duration_s > 0.0)) return out;
  const double q0 = last.volume_mm3 / last.duration_s;
  const double t_off = tp.moves[off].start_s + tp.moves[off].duration_s;
  double total = 0.0;
  for (std::size_t j = off + 1; j < tp.moves.size(); ++j) {
    const Move& m = tp.moves[j];
    if (m.deposits() || m.event == ExtruderEvent::kMeltOn || m.event == ExtruderEvent::kReverse ||
        m.event == ExtruderEvent::kPrime)
      break;
    const double t0 = std::max(0.0, m.start_s - t_off), t1 = t0 + m.duration_s;
    if (t0 > kOozeTimeConstants * tau) break;
    if (!(m.duration_s > 0.0)) continue;
    const double v = q0 * tau * (std::exp(-t0 / tau) - std::exp(-t1 / tau));
    Move shaped = m;
    shaped.volume_mm3 = v;
    shaped.layer_height_mm = last.layer_height_mm;
    out.push_back({j, sweep_of(shaped, false), 0.0, 1.0, v, 0.5 * (m.start.z() + m.end.z()),
                   last.layer_height_mm, true});
    total += v;
  }
  double available = 0.0;
  for (const PlannedSweep& p : bead) available += p.volume_mm3;
  const double scale = total > 0.5 * available ? 0.5 * available / total : 1.0;
  for (PlannedSweep& p : out) {
    p.volume_mm3 *= scale;
    if (p.sweep.is_puddle()) {
      p.sweep.profile = puddle_profile(p.volume_mm3, p.nominal_height_mm);
    } else {
      p.sweep.profile = moving_bead_profile(p.volume_mm3 / tp.moves[p.move].length_mm(), p.nominal_height_mm);
    }
  }
  const double keep = available > 0.0 ? 1.0 - scale * total / available : 1.0;
  for (PlannedSweep& p : bead) p.volume_mm3 *= keep;
  return out;
}

void add_ooze(const Toolpath& tp, std::vector<PlannedSweep>& sweeps, double tau) {
  std::vector<PlannedSweep> out;
  out.reserve(sweeps.size());
  std::size_t next = 0;        // next sweep to copy
  std::size_t bead_first = 0;  // index into `out` of the current bead's first piece
  for (std::size_t i = 0; i < tp.moves.size(); ++i) {
    const ExtruderEvent e = tp.moves[i].event;
    if (e != ExtruderEvent::kMeltOff && e != ExtruderEvent::kMeltOn) continue;
    while (next < sweeps.size() && sweeps[next].move < i) out.push_back(sweeps[next++]);
    if (e == ExtruderEvent::kMeltOff && out.size() > bead_first && !out.back().ooze) {
      std::vector<PlannedSweep> ooze =
          ooze_after(tp, i, std::span<PlannedSweep>(out).subspan(bead_first), tau);
      out.insert(out.end(), ooze.begin(), ooze.end());
    }
    bead_first = out.size();
  }
  while (next < sweeps.size()) out.push_back(sweeps[next++]);
  sweeps = std::move(out);
}

}  // namespace

std::vector<PlannedSweep> plan_sweeps(const Toolpath& toolpath, const SweepPlanOptions& options) {
  BT_CHECK_OP(options.max_piece_mm, >, 0.0);
  std::vector<PlannedSweep> out;
  std::size_t chain_first = 0;  // index into `out` of the current continuous bead's first move
  bool moved_dry = false;       // a move with length but without material since the last depositing move
  const auto close_chain = [&out, &chain_first] {
    if (out.size() < chain_first + 2) return;
    BeadSweep& last = out.back().sweep;
    BeadSweep& first = out[chain_first].sweep;
    if (const auto bisector = joint(last, first)) join(last, first, *bisector);
  };
  for (std::size_t i = 0; i < toolpath.moves.size(); ++i) {
    const Move& move = toolpath.moves[i];
    if (!move.deposits()) {
      if (move.length_mm() > 0.0) moved_dry = true;
      continue;
    }
    BT_CHECK_OP(move.layer_height_mm, >, 0.0);
    const BeadSweep whole = sweep_of(move, options.round_free_ends);
    const double plan_length = (whole.end_xy - whole.start_xy).norm();
    const int pieces =
        whole.is_puddle() ? 1 : std::max(1, static_cast<int>(std::ceil(plan_length / options.max_piece_mm)));
    for (int k = 0; k < pieces; ++k) {
      const double a = static_cast<double>(k) / pieces, b = static_cast<double>(k + 1) / pieces;
      PlannedSweep planned{i, whole, a, b, move.volume_mm3 / pieces, 0.0, move.layer_height_mm};
      BeadSweep& s = planned.sweep;
      if (pieces > 1) {
        s.start_xy = whole.start_xy + a * (whole.end_xy - whole.start_xy);
        s.end_xy = whole.start_xy + b * (whole.end_xy - whole.start_xy);
        s.start_top_mm = whole.start_top_mm + a * (whole.end_top_mm - whole.start_top_mm);
        s.end_top_mm = whole.start_top_mm + b * (whole.end_top_mm - whole.start_top_mm);
        // Inner cuts are square, so the pieces join into one seamless bead; the move's own ends keep theirs.
        const Eigen::Vector2d axis = direction(whole);
        if (k > 0) s.start_cut = axis;
        if (k + 1 < pieces) s.end_cut = axis;
      }
      planned.nominal_top_mm = 0.5 * (s.start_top_mm + s.end_top_mm);
      std::optional<Eigen::Vector2d> bisector;
      if (k == 0 && !out.empty() && !moved_dry) bisector = joint(out.back().sweep, s);
      if (bisector) {
        join(out.back().sweep, s, *bisector);
      } else if (k == 0) {
        close_chain();
        chain_first = out.size();
      }
      out.push_back(planned);
    }
    moved_dry = false;
  }
  close_chain();
  if (options.ooze_time_s > 0.0) add_ooze(toolpath, out, options.ooze_time_s);
  return out;
}

}  // namespace beadtwin::sim
