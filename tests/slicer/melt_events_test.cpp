#include "slicer/melt_events.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "gcode/writer.hpp"

namespace beadtwin::slicer {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kWidth = 20.0;    // mm
constexpr double kHeight = 5.0;    // mm
constexpr double kFeed = 50.0;     // mm/s
constexpr double kPumpCm3 = 10.0;  // cm³/rev

Extruder gear_pump() {
  Extruder e;
  e.kind = ExtruderKind::kGearPump;
  e.displacement_mm3_per_rev = kPumpCm3 * 1000.0;
  return e;
}

// One bead as LayerBuilder lays it: travel to its start, melt on, print moves, melt off.
void add_bead(Toolpath& tp, int section, const std::vector<Vector2d>& path, double w, double h) {
  Move base;
  base.section = section;
  base.layer = section;
  base.bead_width_mm = w;
  base.layer_height_mm = h;
  Move travel = base;
  travel.kind = MoveKind::kTravel;
  travel.feature = Feature::kTravel;
  travel.start = tp.moves.empty() ? Vector3d(-50, -50, h) : tp.moves.back().end;
  travel.end = {path[0].x(), path[0].y(), h};
  travel.feed_mm_s = 200.0;
  tp.moves.push_back(travel);
  Move on = base;
  on.kind = MoveKind::kDwell;
  on.event = ExtruderEvent::kMeltOn;
  on.start = on.end = travel.end;
  tp.moves.push_back(on);
  for (std::size_t i = 1; i < path.size(); ++i) {
    Move m = base;
    m.kind = MoveKind::kPrint;
    m.feature = Feature::kBoundary;
    m.pass = 0;
    m.roller_down = true;
    m.start = {path[i - 1].x(), path[i - 1].y(), h};
    m.end = {path[i].x(), path[i].y(), h};
    m.feed_mm_s = kFeed;
    m.volume_mm3 = bead_area_mm2(w, h) * m.length_mm();
    tp.moves.push_back(m);
  }
  Move off = on;
  off.event = ExtruderEvent::kMeltOff;
  off.start = off.end = tp.moves.back().end;
  tp.moves.push_back(off);
}

// Two beads in two sections (one layer each): an L of 100 + 50 mm, then a straight 200 mm.
Toolpath two_beads(double w = kWidth, double h = kHeight) {
  Toolpath tp;
  tp.sections = {"a", "b"};
  for (int s = 0; s < 2; ++s) {
    ToolpathLayer l;
    l.z_mm = l.height_mm = h;
    l.section = s;
    tp.layers.push_back(l);
  }
  add_bead(tp, 0, {{0, 0}, {100, 0}, {100, 50}}, w, h);
  add_bead(tp, 1, {{0, 100}, {200, 100}}, w, h);
  return tp;
}

const double kArea = bead_area_mm2(kWidth, kHeight);
const double kNominal = kArea * 350.0;  // both beads' material, mm³

std::vector<std::size_t> find(const Toolpath& tp, ExtruderEvent event, MoveKind kind) {
  std::vector<std::size_t> found;
  for (std::size_t i = 0; i < tp.moves.size(); ++i)
    if (tp.moves[i].event == event && tp.moves[i].kind == kind) found.push_back(i);
  return found;
}

// The moves of the first bead (section 0), melt on to the last move before the next travel.
std::vector<Move> first_bead(const Toolpath& tp) {
  std::vector<Move> bead;
  for (const Move& m : tp.moves) {
    if (m.section != 0 || (m.kind == MoveKind::kTravel && !bead.empty())) break;
    if (m.kind != MoveKind::kTravel) bead.push_back(m);
  }
  return bead;
}

void expect_at(const Vector3d& p, double x, double y) {
  EXPECT_NEAR(p.x(), x, 1e-9);
  EXPECT_NEAR(p.y(), y, 1e-9);
}

MeltSettings priming(double time_s, double rpm) {
  MeltSettings s;
  s.prime = true;
  s.prime_time_s = time_s;
  s.prime_rpm = rpm;
  return s;
}

MeltSettings coasting(double distance_mm) {
  MeltSettings s;
  s.coast = true;
  s.coast_distance_mm = distance_mm;
  return s;
}

MeltSettings reversing(double time_s, double rpm) {
  MeltSettings s;
  s.reverse = true;
  s.reverse_time_s = time_s;
  s.reverse_rpm = rpm;
  return s;
}

TEST(MeltEvents, NothingSetChangesNothing) {
  const Toolpath before = two_beads();
  Toolpath tp = before;
  apply_melt_settings(tp, {MeltSettings{}, MeltSettings{}}, gear_pump());
  ASSERT_EQ(tp.moves.size(), before.moves.size());
  for (std::size_t i = 0; i < tp.moves.size(); ++i) {
    EXPECT_EQ(tp.moves[i].start, before.moves[i].start) << i;
    EXPECT_EQ(tp.moves[i].end, before.moves[i].end) << i;
    EXPECT_EQ(tp.moves[i].volume_mm3, before.moves[i].volume_mm3) << i;
    EXPECT_EQ(tp.moves[i].event, before.moves[i].event) << i;
    EXPECT_EQ(tp.moves[i].feature, before.moves[i].feature) << i;
  }
  EXPECT_NEAR(tp.commanded_volume_mm3(), kNominal, 1e-9 * kNominal);
}

TEST(MeltEvents, PrimeIsADwellWithItsBlobAtTheBeadStart) {
  // 30 rpm of a 10 cm³/rev pump for 2 s: 10000 mm³.
  Toolpath tp = two_beads();
  apply_melt_settings(tp, {priming(2.0, 30.0), priming(2.0, 30.0)}, gear_pump());
  const std::vector<std::size_t> primes = find(tp, ExtruderEvent::kPrime, MoveKind::kDwell);
  ASSERT_EQ(primes.size(), 2u);
  for (std::size_t i : primes) {
    const Move& m = tp.moves[i];
    EXPECT_EQ(m.feature, Feature::kPrime);
    EXPECT_EQ(m.duration_s, 2.0);
    EXPECT_NEAR(m.volume_mm3, 10000.0, 1e-9);
    EXPECT_EQ(tp.moves[i - 1].event, ExtruderEvent::kMeltOn) << "the prime follows the melt on";
    EXPECT_EQ(m.end, tp.moves[i - 1].end);
  }
  expect_at(tp.moves[primes[0]].end, 0, 0);
  expect_at(tp.moves[primes[1]].end, 0, 100);
  EXPECT_NEAR(tp.commanded_volume_mm3(), kNominal + 20000.0, 1e-9 * kNominal);

  // Per section: only the second section primes.
  Toolpath one = two_beads();
  apply_melt_settings(one, {MeltSettings{}, priming(2.0, 30.0)}, gear_pump());
  const std::vector<std::size_t> p = find(one, ExtruderEvent::kPrime, MoveKind::kDwell);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(one.moves[p[0]].section, 1);
}

TEST(MeltEvents, PrimeWithoutDelaySpreadsTheSameVolumeOverTheFirstMoves) {
  // 1 s of priming at 50 mm/s covers the first 50 mm of each bead; 30 rpm for 1 s is 5000 mm³.
  MeltSettings s = priming(1.0, 30.0);
  s.delay_during_prime = false;
  Toolpath tp = two_beads();
  apply_melt_settings(tp, {s, s}, gear_pump());
  EXPECT_TRUE(find(tp, ExtruderEvent::kPrime, MoveKind::kDwell).empty()) << "the head does not wait";
  const std::vector<std::size_t> primed = find(tp, ExtruderEvent::kPrime, MoveKind::kPrint);
  ASSERT_EQ(primed.size(), 2u);
  const Move& first = tp.moves[primed[0]];
  expect_at(first.start, 0, 0);
  expect_at(first.end, 50, 0);  // the 100 mm move is split where the prime time ends
  EXPECT_NEAR(first.volume_mm3, kArea * 50.0 + 5000.0, 1e-9);
  const Move& next = tp.moves[primed[0] + 1];
  expect_at(next.start, 50, 0);
  expect_at(next.end, 100, 0);
  EXPECT_NEAR(next.volume_mm3, kArea * 50.0, 1e-9);
  EXPECT_EQ(next.event, ExtruderEvent::kNone);
  EXPECT_NEAR(tp.moves[primed[1]].length_mm(), 50.0, 1e-9);
  // The same material as the dwell would lay.
  Toolpath dwell = two_beads();
  apply_melt_settings(dwell, {priming(1.0, 30.0), priming(1.0, 30.0)}, gear_pump());
  EXPECT_NEAR(tp.commanded_volume_mm3(), dwell.commanded_volume_mm3(), 1e-9 * kNominal);
  EXPECT_NEAR(tp.commanded_volume_mm3(), kNominal + 10000.0, 1e-9 * kNominal);

  // A prime longer than the bead (5 s against 3 s) is spread over all of it, in proportion to time.
  s.prime_time_s = 5.0;
  Toolpath longer = two_beads();
  apply_melt_settings(longer, {s, MeltSettings{}}, gear_pump());
  const std::vector<Move> bead = first_bead(longer);
  double extra = 0.0;
  for (const Move& m : bead) {
    if (m.kind != MoveKind::kPrint) continue;
    EXPECT_EQ(m.event, ExtruderEvent::kPrime);
    EXPECT_NEAR(m.volume_mm3 - kArea * m.length_mm(), 25000.0 * m.length_mm() / 150.0, 1e-9);
    extra += m.volume_mm3 - kArea * m.length_mm();
  }
  EXPECT_NEAR(extra, 25000.0, 1e-9);
}

TEST(MeltEvents, CoastLaysHalfTheBeadDecayingLinearly) {
  Toolpath tp = two_beads();
  apply_melt_settings(tp, {coasting(40.0), coasting(40.0)}, gear_pump());
  const std::vector<Move> bead = first_bead(tp);
  std::size_t off = 0;
  while (off < bead.size() && bead[off].event != ExtruderEvent::kMeltOff) ++off;
  ASSERT_LT(off, bead.size());
  expect_at(bead[off].end, 100, 10);  // 40 mm before the bead's end
  double pumped_length = 0.0, pumped_volume = 0.0;
  for (std::size_t i = 0; i < off; ++i) {
    EXPECT_NE(bead[i].feature, Feature::kCoast);
    pumped_length += bead[i].length_mm();
    pumped_volume += bead[i].volume_mm3;
  }
  EXPECT_NEAR(pumped_length, 110.0, 1e-9);
  EXPECT_NEAR(pumped_volume, kArea * 110.0, 1e-9);
  const std::vector<Move> coast(bead.begin() + static_cast<std::ptrdiff_t>(off) + 1, bead.end());
  ASSERT_EQ(coast.size(), static_cast<std::size_t>(kCoastSteps));
  double length = 0.0, volume = 0.0;
  for (std::size_t k = 0; k < coast.size(); ++k) {
    const Move& m = coast[k];
    EXPECT_EQ(m.kind, MoveKind::kPrint) << "the head keeps moving";
    EXPECT_EQ(m.feature, Feature::kCoast);
    EXPECT_NEAR(m.length_mm(), 10.0, 1e-9);
    // The material per length falls linearly from the bead's to 0: over [10k, 10k + 10] of 40 mm,
    // ∫(1 − s/40) ds = 10 (1 − (2k + 1) / 8).
    EXPECT_NEAR(m.volume_mm3, kArea * 10.0 * (1.0 - (2.0 * static_cast<double>(k) + 1.0) / 8.0), 1e-9) << k;
    length += m.length_mm();
    volume += m.volume_mm3;
  }
  EXPECT_NEAR(length, 40.0, 1e-9);
  EXPECT_NEAR(volume, 0.5 * kArea * 40.0, 1e-9);
  expect_at(coast.back().end, 100, 50);
  EXPECT_NEAR(tp.commanded_volume_mm3(), kNominal - 2 * 0.5 * kArea * 40.0, 1e-9 * kNominal);

  // A coast round the corner starts on the first leg and keeps the corner.
  Toolpath corner = two_beads();
  apply_melt_settings(corner, {coasting(60.0)}, gear_pump());
  double corner_length = 0.0, corner_volume = 0.0;
  bool through_corner = false;
  Vector3d start = Vector3d::Constant(1e9);
  for (const Move& m : first_bead(corner)) {
    if (m.feature != Feature::kCoast) continue;
    if (corner_length == 0.0) start = m.start;
    corner_length += m.length_mm();
    corner_volume += m.volume_mm3;
    through_corner |= (m.end - Vector3d(100, 0, kHeight)).norm() < 1e-9;
  }
  expect_at(start, 90, 0);
  EXPECT_TRUE(through_corner);
  EXPECT_NEAR(corner_length, 60.0, 1e-9);
  EXPECT_NEAR(corner_volume, 0.5 * kArea * 60.0, 1e-9);
}

TEST(MeltEvents, ReverseAtTheBeadEndOrAtTheCoastStart) {
  // No coast: after the melt off, where the bead ends.
  Toolpath tp = two_beads();
  apply_melt_settings(tp, {reversing(0.5, 10.0)}, gear_pump());
  std::vector<std::size_t> r = find(tp, ExtruderEvent::kReverse, MoveKind::kDwell);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(tp.moves[r[0]].feature, Feature::kReverse);
  EXPECT_EQ(tp.moves[r[0]].duration_s, 0.5);
  EXPECT_EQ(tp.moves[r[0]].volume_mm3, 0.0);
  EXPECT_EQ(tp.moves[r[0] - 1].event, ExtruderEvent::kMeltOff);
  expect_at(tp.moves[r[0]].end, 100, 50);
  EXPECT_NEAR(tp.commanded_volume_mm3(), kNominal, 1e-9 * kNominal);

  // With a coast: at its end, or at its start with reverse during coast.
  MeltSettings s = reversing(0.5, 10.0);
  s.coast = true;
  s.coast_distance_mm = 40.0;
  Toolpath after = two_beads();
  apply_melt_settings(after, {s}, gear_pump());
  r = find(after, ExtruderEvent::kReverse, MoveKind::kDwell);
  ASSERT_EQ(r.size(), 1u);
  expect_at(after.moves[r[0]].end, 100, 50);
  EXPECT_EQ(after.moves[r[0] - 1].feature, Feature::kCoast);
  s.reverse_during_coast = true;
  Toolpath during = two_beads();
  apply_melt_settings(during, {s}, gear_pump());
  r = find(during, ExtruderEvent::kReverse, MoveKind::kDwell);
  ASSERT_EQ(r.size(), 1u);
  expect_at(during.moves[r[0]].end, 100, 10);
  EXPECT_EQ(during.moves[r[0] - 1].event, ExtruderEvent::kMeltOff);
  EXPECT_EQ(during.moves[r[0] + 1].feature, Feature::kCoast);

  // Without the delay the head does not wait: the event stays, with no time.
  s.delay_during_reverse = false;
  Toolpath moving = two_beads();
  apply_melt_settings(moving, {s}, gear_pump());
  r = find(moving, ExtruderEvent::kReverse, MoveKind::kDwell);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(moving.moves[r[0]].duration_s, 0.0);
}

TEST(MeltEvents, SetAtControlRecordsTheEventsWithTheirTimes) {
  MeltSettings s = priming(2.0, 30.0);
  s.delay_during_prime = false;
  s.reverse = true;
  s.reverse_time_s = 0.5;
  s.delay_during_reverse = false;
  s.set_at_control = true;
  Toolpath tp = two_beads();
  apply_melt_settings(tp, {s, s}, gear_pump());
  const std::vector<std::size_t> primes = find(tp, ExtruderEvent::kPrime, MoveKind::kDwell);
  const std::vector<std::size_t> reverses = find(tp, ExtruderEvent::kReverse, MoveKind::kDwell);
  ASSERT_EQ(primes.size(), 2u);
  ASSERT_EQ(reverses.size(), 2u);
  EXPECT_EQ(tp.moves[primes[0]].duration_s, 2.0);
  EXPECT_NEAR(tp.moves[primes[0]].volume_mm3, 10000.0, 1e-9);
  EXPECT_EQ(tp.moves[reverses[0]].duration_s, 0.5);
  EXPECT_TRUE(find(tp, ExtruderEvent::kPrime, MoveKind::kPrint).empty());
}

TEST(MeltEvents, CommandedVolumeAndTimeAfterTiming) {
  MeltSettings s = priming(2.0, 30.0);
  s.coast = true;
  s.coast_distance_mm = 40.0;
  s.reverse = true;
  s.reverse_time_s = 0.5;
  s.reverse_rpm = 10.0;
  Toolpath plain = two_beads();
  Toolpath tp = two_beads();
  apply_melt_settings(tp, {s, s}, gear_pump());
  const double expected = kNominal + 2 * 10000.0 - 2 * 0.5 * kArea * 40.0;
  EXPECT_NEAR(tp.commanded_volume_mm3(), expected, 1e-9 * kNominal);
  time_toolpath(plain, {});
  time_toolpath(tp, {});
  EXPECT_NEAR(tp.commanded_volume_mm3(), expected, 1e-9 * kNominal);
  for (std::size_t i : find(tp, ExtruderEvent::kPrime, MoveKind::kDwell))
    EXPECT_EQ(tp.moves[i].duration_s, 2.0);
  for (std::size_t i : find(tp, ExtruderEvent::kReverse, MoveKind::kDwell))
    EXPECT_EQ(tp.moves[i].duration_s, 0.5);
  // The splits leave the path as it was: the extra time is the dwells' (the coast's splits are straight on,
  // and the one at the corner was a vertex already).
  EXPECT_NEAR(tp.total_time_s() - plain.total_time_s(), 2 * (2.0 + 0.5), 1e-6);
  EXPECT_NEAR(tp.print_length_mm(), plain.print_length_mm(), 1e-9);
  EXPECT_EQ(tp.layers[1].first_move, find(tp, ExtruderEvent::kMeltOn, MoveKind::kDwell)[1] - 1);
}

TEST(MeltEvents, BadSettingsAreInputErrors) {
  Toolpath tp = two_beads();
  try {
    apply_melt_settings(tp, {MeltSettings{}, coasting(-1.0)}, gear_pump());
    FAIL() << "a negative coast distance was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "melt[1].coast_distance");
  }
  Extruder filament;
  filament.kind = ExtruderKind::kFilament;
  filament.filament_diameter_mm = 1.75;
  EXPECT_THROW(apply_melt_settings(tp, {priming(1.0, 10.0)}, filament), InputError) << "no RPM to prime at";
  EXPECT_THROW(apply_melt_settings(tp, {}, Extruder{}), InputError) << "a pump without a displacement";
  tp.moves.pop_back();  // the last melt off
  EXPECT_THROW(apply_melt_settings(tp, {}, gear_pump()), InternalError);
}

// --- The program --------------------------------------------------------------------------------------

std::vector<std::string> lines_of(const std::string& g) {
  std::vector<std::string> lines;
  std::istringstream in(g);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

// Whether the program has the word `letter` followed by a number (" S28.4", " E-1.2").
bool has_word(const std::string& g, char letter) {
  for (std::size_t at = g.find(std::string(" ") + letter); at != std::string::npos;
       at = g.find(std::string(" ") + letter, at + 1)) {
    const char c = at + 2 < g.size() ? g[at + 2] : ' ';
    if ((c >= '0' && c <= '9') || c == '-' || c == '.') return true;
  }
  return false;
}

// Sum of the E words of the program.
double e_total(const std::string& g) {
  double total = 0.0;
  for (const std::string& l : lines_of(g)) {
    const std::size_t e = l.find(" E");
    const bool motion = l.rfind("G1", 0) == 0 || l.rfind("G2", 0) == 0 || l.rfind("G3", 0) == 0;
    if (motion && e != std::string::npos) total += std::strtod(l.c_str() + e + 2, nullptr);
  }
  return total;
}

std::size_t index_of(const std::vector<std::string>& lines, const std::string& text, std::size_t from = 0) {
  for (std::size_t i = from; i < lines.size(); ++i)
    if (lines[i] == text) return i;
  return lines.size();
}

TEST(MeltGcode, GearPumpWritesThePrimeDwellAndTheSpeed) {
  MeltSettings s = priming(2.0, 30.0);
  s.coast = true;
  s.coast_distance_mm = 40.0;
  s.reverse = true;
  s.reverse_time_s = 0.5;
  s.reverse_rpm = 10.0;
  Toolpath tp = two_beads();
  const Extruder pump = gear_pump();
  apply_melt_settings(tp, {s, s}, pump);
  time_toolpath(tp, {});
  gcode::GcodeDialect d;
  d.reverse_on = "M25";
  d.reverse_off = "M26";
  gcode::GcodeOptions o;
  o.extruder = &pump;
  o.melt = {s, s};
  const std::string g = gcode::write_gcode(tp, d, {}, o);
  const std::vector<std::string> lines = lines_of(g);
  // The pump starts at the priming speed, the head waits, then the bead's speed: A v / D =
  // 94.635 mm² · 50 mm/s · 60 / 10000 mm³ = 28.39 rpm.
  const std::size_t on = index_of(lines, "M23 S30 (melt on)");
  ASSERT_LT(on, lines.size()) << g;
  EXPECT_EQ(lines[on + 1], "G4 P2000 (prime)");
  EXPECT_NE(g.find("G1 X100 F3000 S28.4\n"), std::string::npos) << g;
  // The coast runs with the pump off: no speed words until the reverse, which waits its time.
  const std::size_t off = index_of(lines, "M24 (melt off)", on);
  const std::size_t reverse = index_of(lines, "M25 S10 (reverse)", off);
  ASSERT_LT(reverse, lines.size()) << g;
  EXPECT_EQ(lines[off + 1], "(coast)");
  for (std::size_t i = off + 1; i < reverse; ++i) EXPECT_FALSE(has_word(lines[i], 'S')) << lines[i];
  EXPECT_EQ(reverse - off - 2, static_cast<std::size_t>(kCoastSteps)) << "the coast's moves";
  EXPECT_EQ(lines[reverse + 1], "G4 P500 (reverse)");
  EXPECT_EQ(lines[reverse + 2], "M26 (reverse off)");
  // The second bead starts at the priming speed again.
  EXPECT_LT(index_of(lines, "M23 S30 (melt on)", on + 1), lines.size());

  // Codes left empty are comments.
  gcode::GcodeDialect plain;
  const std::string c = gcode::write_gcode(tp, plain, {}, o);
  EXPECT_NE(c.find("\n(reverse at 10 rpm)\nG4 P500 (reverse)\n(reverse off)\n"), std::string::npos) << c;
}

TEST(MeltGcode, ReverseWithoutDelayRunsThroughTheCoast) {
  MeltSettings s = reversing(0.5, 10.0);
  s.coast = true;
  s.coast_distance_mm = 40.0;
  s.reverse_during_coast = true;
  s.delay_during_reverse = false;
  Toolpath tp = two_beads();
  const Extruder pump = gear_pump();
  apply_melt_settings(tp, {s}, pump);
  time_toolpath(tp, {});
  gcode::GcodeDialect d;
  d.reverse_on = "M25";
  d.reverse_off = "M26";
  gcode::GcodeOptions o;
  o.extruder = &pump;
  o.melt = {s};
  const std::vector<std::string> lines = lines_of(gcode::write_gcode(tp, d, {}, o));
  const std::size_t off = index_of(lines, "M24 (melt off)");
  ASSERT_LT(off, lines.size());
  EXPECT_EQ(lines[off + 1], "M25 S10 (reverse)");
  EXPECT_EQ(lines[off + 2], "(coast)");
  const std::size_t end = index_of(lines, "M26 (reverse off)", off);
  ASSERT_LT(end, lines.size());
  // Through the coast and the travel to the next bead, off before its melt on; no dwell.
  EXPECT_EQ(lines[end - 1].rfind("G0", 0), 0u) << lines[end - 1];
  EXPECT_EQ(lines[end + 1].rfind("M23", 0), 0u) << lines[end + 1];
  for (std::size_t i = off; i < end; ++i) EXPECT_EQ(lines[i].rfind("G4", 0), std::string::npos) << lines[i];
}

TEST(MeltGcode, SetAtControlWritesOnlyTheCodes) {
  MeltSettings s = priming(2.0, 30.0);
  s.reverse = true;
  s.reverse_time_s = 0.5;
  s.reverse_rpm = 10.0;
  s.set_at_control = true;
  Toolpath tp = two_beads();
  const Extruder pump = gear_pump();
  apply_melt_settings(tp, {s, s}, pump);
  time_toolpath(tp, {});
  gcode::GcodeDialect d;
  d.prime_code = "M27";
  d.reverse_on = "M25";
  d.reverse_off = "M26";
  gcode::GcodeOptions o;
  o.extruder = &pump;
  o.melt = {s, s};
  const std::string g = gcode::write_gcode(tp, d, {}, o);
  EXPECT_NE(g.find("M23 S28.4 (melt on)\nM27 (prime, set at control)\n"), std::string::npos) << g;
  EXPECT_NE(g.find("M24 (melt off)\nM25 (reverse, set at control)\n"), std::string::npos) << g;
  for (const char* absent : {"G4", "S30", "S10", "M26"})
    EXPECT_EQ(g.find(absent), std::string::npos) << absent;
}

TEST(MeltGcode, FilamentEWordsFollowEquationThree) {
  // A desktop-sized bead on a 1.75 mm filament: eq. 3, v_e / v_x = 4 h (π h / 4 + b_p) / (π d_f²).
  const double w = 0.6, h = 0.3, d_f = 1.75;
  const double b_p = w - h;
  const double e_per_mm = 4.0 * h * (kPi / 4.0 * h + b_p) / (kPi * d_f * d_f);
  Extruder f;
  f.kind = ExtruderKind::kFilament;
  f.filament_diameter_mm = d_f;
  Toolpath tp = two_beads(w, h);
  time_toolpath(tp, {});
  gcode::GcodeDialect d;
  d.decimals = 4;
  gcode::GcodeOptions o;
  o.extruder = &f;
  const std::string g = gcode::write_gcode(tp, d, {}, o);
  EXPECT_NE(g.find("G90 (absolute)\nM83 (relative extrusion)\n"), std::string::npos);
  EXPECT_NEAR(e_total(g), 350.0 * e_per_mm, 0.6e-4) << g;
  for (const std::string& l : lines_of(g)) {
    if (l.rfind("G1", 0) == 0) {
      EXPECT_NE(l.find(" E"), std::string::npos) << l;
    }
    if (l.rfind("G0", 0) == 0) {
      EXPECT_EQ(l.find(" E"), std::string::npos) << l;
    }
    EXPECT_FALSE(has_word(l, 'S')) << "no pump speed on a filament machine: " << l;
  }

  // A prime from a drive of 50 mm³/rev at 6 rpm for 2 s: 10 mm³ fed in place.
  f.displacement_mm3_per_rev = 50.0;
  Toolpath primed = two_beads(w, h);
  apply_melt_settings(primed, {priming(2.0, 6.0)}, f);
  time_toolpath(primed, {});
  const std::string p = gcode::write_gcode(primed, d, {}, o);
  const double prime_e = 10.0 / (kPi * d_f * d_f / 4.0);
  EXPECT_NE(p.find(fmt::format("G1 E{:.4f} F", prime_e)), std::string::npos) << p;
  EXPECT_NEAR(e_total(p), 350.0 * e_per_mm + prime_e, 0.6e-4);
}

TEST(MeltGcode, FilamentArcsCarryTheMaterialOfTheirMoves) {
  // A 64-segment circle as one bead: written as a few arcs, the E words still add up to eq. 3.
  const double w = 0.6, h = 0.3, d_f = 1.75;
  Extruder f;
  f.kind = ExtruderKind::kFilament;
  f.filament_diameter_mm = d_f;
  std::vector<Vector2d> ring;
  for (int i = 0; i <= 64; ++i)
    ring.emplace_back(100 + 50 * std::cos(2 * kPi * i / 64), 50 * std::sin(2 * kPi * i / 64));
  double length = 0.0;
  for (std::size_t i = 1; i < ring.size(); ++i) length += (ring[i] - ring[i - 1]).norm();
  Toolpath tp;
  tp.sections = {"a"};
  tp.layers.resize(1);
  tp.layers[0].section = 0;
  tp.layers[0].z_mm = tp.layers[0].height_mm = h;
  add_bead(tp, 0, ring, w, h);
  time_toolpath(tp, {});
  gcode::GcodeDialect d;
  d.arcs = true;
  d.decimals = 4;
  gcode::GcodeOptions o;
  o.extruder = &f;
  o.arc_tolerance_mm = {0.05};
  const std::string g = gcode::write_gcode(tp, d, {}, o);
  int arcs = 0;
  for (const std::string& l : lines_of(g)) arcs += l.rfind("G3", 0) == 0;
  EXPECT_GE(arcs, 2) << g;
  EXPECT_LT(arcs, 32) << "arcs replace the segments: " << g;
  EXPECT_NEAR(e_total(g), length * 4.0 * h * (kPi / 4.0 * h + (w - h)) / (kPi * d_f * d_f), 0.6e-4) << g;
}

TEST(MeltGcode, NothingChangesWithoutAnExtruder) {
  MeltSettings s = priming(2.0, 30.0);
  s.coast = true;
  s.coast_distance_mm = 40.0;
  s.reverse = true;
  s.reverse_time_s = 0.5;
  s.set_at_control = true;
  Toolpath tp = two_beads();
  apply_melt_settings(tp, {s, s}, gear_pump());
  time_toolpath(tp, {});
  gcode::GcodeDialect d;
  d.reverse_on = "M25";
  d.prime_code = "M27";
  gcode::GcodeOptions o;
  o.melt = {s, s};
  const std::string g = gcode::write_gcode(tp, d, {});
  EXPECT_EQ(gcode::write_gcode(tp, d, {}, o), g) << "melt settings alone change nothing";
  // The events are plain dwells, as every program had them.
  EXPECT_NE(g.find("M23 (melt on)\nG4 P2000 (prime)\n"), std::string::npos) << g;
  EXPECT_NE(g.find("\nG4 P500 (reverse)\n"), std::string::npos) << g;
  EXPECT_FALSE(has_word(g, 'S'));
  EXPECT_FALSE(has_word(g, 'E'));
  for (const char* absent : {"M83", "M25", "M27", "set at control"})
    EXPECT_EQ(g.find(absent), std::string::npos) << absent;
}

}  // namespace
}  // namespace beadtwin::slicer
