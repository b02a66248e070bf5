#include "slicer/melt_events.hpp"

#include <algorithm>
#include <string>

#include <fmt/format.h>

#include "core/error.hpp"

namespace beadtwin::slicer {
namespace {

constexpr double kSamePoint = 1e-9;  // mm

bool is_event(const Move& m, ExtruderEvent e) {
  return m.kind == MoveKind::kDwell && m.event == e;
}

// A move the head lays material along (coast and prime are measured along these).
bool lays_path(const Move& m) {
  return m.kind == MoveKind::kPrint && m.length_mm() > 0.0;
}

// Time a move takes at its commanded feed, before the motion model: what the prime time is measured by.
double feed_time_s(const Move& m) {
  return lays_path(m) && m.feed_mm_s > 0 ? m.length_mm() / m.feed_mm_s : 0.0;
}

const MeltSettings& settings_for(const std::vector<MeltSettings>& per_section, int section) {
  static const MeltSettings kNothing;
  if (section < 0 || static_cast<std::size_t>(section) >= per_section.size()) return kNothing;
  return per_section[static_cast<std::size_t>(section)];
}

// Splits moves[i] at fraction f of its length; material (and any time) stays with the length it belongs to.
void split_move(std::vector<Move>& moves, std::size_t i, double f) {
  Move second = moves[i];
  Move& first = moves[i];
  const Eigen::Vector3d p = first.start + f * (first.end - first.start);
  first.end = p;
  first.volume_mm3 *= f;
  first.duration_s *= f;
  second.start = p;
  second.volume_mm3 *= 1.0 - f;
  second.duration_s *= 1.0 - f;
  moves.insert(moves.begin() + static_cast<std::ptrdiff_t>(i) + 1, second);
}

// Makes a move end at path distance `d` from the start of `moves` (along the moves that lay material).
void split_at_distance(std::vector<Move>& moves, double d) {
  double at = 0.0;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    if (!lays_path(moves[i])) continue;
    const double length = moves[i].length_mm();
    if (d <= at + kSamePoint) return;  // already a vertex
    if (d < at + length - kSamePoint) {
      split_move(moves, i, (d - at) / length);
      return;
    }
    at += length;
  }
}

double path_length_mm(const std::vector<Move>& moves) {
  double length = 0.0;
  for (const Move& m : moves)
    if (lays_path(m)) length += m.length_mm();
  return length;
}

// One bead as it is rewritten: melt on, the moves with the pump on, the melt off, the coast.
struct Bead {
  Move on;
  std::vector<Move> pumped;
  Move off;
  std::vector<Move> coast;
};

// Moves the last `distance_mm` of the bead's path into its coast, in kCoastSteps equal moves, with the
// material per length falling linearly from the bead's to 0 over the coast: a move over [s0, s1] of a coast
// of length L keeps the fraction ∫(1 − s/L) ds / (s1 − s0) = 1 − (s0 + s1) / (2 L) of its material.
void split_coast(Bead& b, double distance_mm) {
  std::vector<Move>& moves = b.pumped;
  const double total = path_length_mm(moves);
  const double length = std::min(distance_mm, total);
  if (!(length > kSamePoint)) return;
  const double cut = total - length;
  for (int k = 0; k < kCoastSteps; ++k) split_at_distance(moves, cut + k * length / kCoastSteps);
  double at = 0.0;
  std::size_t first = moves.size();
  for (std::size_t i = 0; i < moves.size() && first == moves.size(); ++i) {
    if (!lays_path(moves[i])) continue;
    if (at >= cut - kSamePoint) first = i;
    at += moves[i].length_mm();
  }
  double s = 0.0;  // distance coasted at the start of the move
  for (std::size_t i = first; i < moves.size(); ++i) {
    Move& m = moves[i];
    if (!lays_path(m)) continue;
    const double l = m.length_mm();
    m.volume_mm3 *= std::max(0.0, 1.0 - (2.0 * s + l) / (2.0 * length));
    m.feature = Feature::kCoast;
    m.event = ExtruderEvent::kCoast;
    s += l;
  }
  b.coast.assign(moves.begin() + static_cast<std::ptrdiff_t>(first), moves.end());
  moves.erase(moves.begin() + static_cast<std::ptrdiff_t>(first), moves.end());
}

// Adds `volume_mm3` to the first of `moves` that take `time_s` at their feed (all of them when they take
// less), in proportion to each one's time; a move is split where the time runs out. Returns false (and
// changes nothing) when the moves take no time.
bool spread_prime(std::vector<Move>& moves, double time_s, double volume_mm3) {
  double total = 0.0;
  for (const Move& m : moves) total += feed_time_s(m);
  if (!(total > 0.0) || !(time_s > 0.0)) return false;
  const double cover = std::min(time_s, total);
  std::vector<std::size_t> covered;
  double t = 0.0;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    if (feed_time_s(moves[i]) <= 0.0) continue;
    const double left_mm = (cover - t) * moves[i].feed_mm_s;  // path the prime still covers at this feed
    if (left_mm <= kSamePoint) break;
    if (moves[i].length_mm() > left_mm + kSamePoint) split_move(moves, i, left_mm / moves[i].length_mm());
    covered.push_back(i);
    t += feed_time_s(moves[i]);
  }
  // Shares by the covered moves' own times, so exactly `volume_mm3` is added.
  double covered_time = 0.0;
  for (std::size_t i : covered) covered_time += feed_time_s(moves[i]);
  for (std::size_t i : covered) {
    moves[i].volume_mm3 += volume_mm3 * feed_time_s(moves[i]) / covered_time;
    moves[i].event = ExtruderEvent::kPrime;
  }
  return true;
}

// An extruder event where the head stands, in the bead's section and layer.
Move event_dwell(const Move& like, const Eigen::Vector3d& at, ExtruderEvent event, Feature feature,
                 double duration_s, double volume_mm3) {
  Move m = like;
  m.kind = MoveKind::kDwell;
  m.event = event;
  m.feature = feature;
  m.start = m.end = at;
  m.duration_s = duration_s;
  m.volume_mm3 = volume_mm3;
  m.feed_mm_s = 0.0;
  return m;
}

void add_prime(std::vector<Move>& out, Bead& b, const MeltSettings& s, const Extruder& e) {
  const double volume = s.prime_rpm > 0 ? flow_for_rpm(e, s.prime_rpm) * s.prime_time_s : 0.0;
  const bool wait = s.delay_during_prime || s.set_at_control;
  if (!wait && spread_prime(b.pumped, s.prime_time_s, volume)) return;
  // A bead with no moving time before its melt off cannot take the prime on the move: it waits.
  if (wait || s.prime_time_s > 0)
    out.push_back(
        event_dwell(b.on, b.on.end, ExtruderEvent::kPrime, Feature::kPrime, s.prime_time_s, volume));
}

void lay_bead(std::vector<Move>& out, Bead b, const MeltSettings& s, const Extruder& e) {
  if (s.coast && s.coast_distance_mm > 0) split_coast(b, s.coast_distance_mm);
  out.push_back(b.on);
  if (s.prime) add_prime(out, b, s, e);
  out.insert(out.end(), b.pumped.begin(), b.pumped.end());
  const Eigen::Vector3d bead_end = b.off.end;
  if (!b.coast.empty()) b.off.start = b.off.end = b.coast.front().start;
  out.push_back(b.off);
  const double reverse_s = s.delay_during_reverse || s.set_at_control ? s.reverse_time_s : 0.0;
  const bool reverse_on_coast = s.reverse_during_coast && !b.coast.empty();
  if (s.reverse && reverse_on_coast)
    out.push_back(event_dwell(b.off, b.off.end, ExtruderEvent::kReverse, Feature::kReverse, reverse_s, 0.0));
  out.insert(out.end(), b.coast.begin(), b.coast.end());
  if (s.reverse && !reverse_on_coast)
    out.push_back(event_dwell(b.off, bead_end, ExtruderEvent::kReverse, Feature::kReverse, reverse_s, 0.0));
}

}  // namespace

void validate_melt_settings(const std::vector<MeltSettings>& per_section, const Extruder& extruder) {
  for (std::size_t i = 0; i < per_section.size(); ++i) {
    const MeltSettings& s = per_section[i];
    const auto check = [&](double value, const char* name, const char* unit) {
      if (!(value >= 0))
        throw InputError({}, fmt::format("melt[{}].{}", i, name),
                         fmt::format("must not be negative, got {} {}", value, unit));
    };
    check(s.prime_time_s, "prime_time", "s");
    check(s.prime_rpm, "prime_rpm", "rpm");
    check(s.coast_distance_mm, "coast_distance", "mm");
    check(s.reverse_time_s, "reverse_time", "s");
    check(s.reverse_rpm, "reverse_rpm", "rpm");
    const auto needs_rpm = [&](bool used, double rpm, const char* name) {
      if (used && rpm > 0 && !extruder.has_rpm())
        throw InputError({}, fmt::format("melt[{}].{}", i, name),
                         fmt::format("a {} extruder without a displacement per revolution has no RPM",
                                     to_string(extruder.kind)));
    };
    needs_rpm(s.prime, s.prime_rpm, "prime_rpm");
    needs_rpm(s.reverse, s.reverse_rpm, "reverse_rpm");
  }
}

void apply_melt_settings(Toolpath& tp, const std::vector<MeltSettings>& per_section,
                         const Extruder& extruder) {
  validate(extruder);
  validate_melt_settings(per_section, extruder);
  const std::vector<Move>& in = tp.moves;
  std::vector<Move> out;
  out.reserve(in.size() + in.size() / 4);
  for (std::size_t i = 0; i < in.size();) {
    if (!is_event(in[i], ExtruderEvent::kMeltOn)) {
      out.push_back(in[i++]);
      continue;
    }
    std::size_t off = i + 1;
    while (off < in.size() && !is_event(in[off], ExtruderEvent::kMeltOff)) ++off;
    if (off == in.size())
      throw InternalError(fmt::format("toolpath move {}: melt on without a melt off after it", i));
    Bead bead{
        in[i],
        {in.begin() + static_cast<std::ptrdiff_t>(i) + 1, in.begin() + static_cast<std::ptrdiff_t>(off)},
        in[off],
        {}};
    lay_bead(out, std::move(bead), settings_for(per_section, in[i].section), extruder);
    i = off + 1;
  }
  tp.moves = std::move(out);
  tp.index_layers();
}

}  // namespace beadtwin::slicer
