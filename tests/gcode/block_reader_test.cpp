#include "gcode/block_reader.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "gcode/program_reader.hpp"

namespace beadtwin::gcode {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

Toolpath read(const std::string& program, const ReaderOptions& o = {}, ReadStats* stats = nullptr) {
  std::istringstream in(program);
  return read_gcode(in, "test.gcode", o, stats);
}

std::vector<Move> moves_of_line(const Toolpath& tp, int line) {
  std::vector<Move> out;
  for (const Move& m : tp.moves)
    if (m.source_line == line) out.push_back(m);
  return out;
}

double filament_area(double d) {
  return kPi * d * d / 4.0;
}

// ---- arcs ----

struct PlaneCase {
  int g;         // 17, 18, 19
  char u, v, n;  // axis letters: u × v = n
  char iu, iv;   // centre offset letters for u and v
  int au, av, an;
};
constexpr PlaneCase kPlanes[] = {{17, 'X', 'Y', 'Z', 'I', 'J', 0, 1, 2},
                                 {18, 'Z', 'X', 'Y', 'K', 'I', 2, 0, 1},
                                 {19, 'Y', 'Z', 'X', 'J', 'K', 1, 2, 0}};

// Checks the moves of the arc on line 3: they chain from `start` to `end`, every vertex is on the circle
// about `centre` of radius r (in the plane), every chord's midpoint within `tol` of it, the length in the
// plane is r times `turned`, the first step turns the right way, and the normal axis moves linearly.
void expect_arc(const Toolpath& tp, const PlaneCase& p, const Vector3d& start, const Vector3d& end,
                const Vector2d& centre, double r, double turned, bool ccw, double tol) {
  const std::vector<Move> arc = moves_of_line(tp, 3);
  ASSERT_FALSE(arc.empty());
  const auto uv = [&](const Vector3d& q) { return Vector2d(q[p.au], q[p.av]); };
  EXPECT_LT((arc.front().start - start).norm(), 1e-9);
  EXPECT_LT((arc.back().end - end).norm(), 1e-9);
  double length = 0.0;
  for (std::size_t k = 0; k < arc.size(); ++k) {
    const Move& m = arc[k];
    if (k > 0) {
      EXPECT_LT((m.start - arc[k - 1].end).norm(), 1e-12) << "moves chain";
    }
    EXPECT_NEAR((uv(m.end) - centre).norm(), r, 1e-9) << "vertex " << k;
    const double mid = (0.5 * (uv(m.start) + uv(m.end)) - centre).norm();
    EXPECT_LE(r - mid, tol + 1e-12) << "chord " << k << " sags too far";
    length += (uv(m.end) - uv(m.start)).norm();
    const double expected_n = start[p.an] + (end[p.an] - start[p.an]) * double(k + 1) / double(arc.size());
    EXPECT_NEAR(m.end[p.an], expected_n, 1e-9) << "the normal axis moves with the angle";
    EXPECT_EQ(m.kind, MoveKind::kPrint);
  }
  EXPECT_LE(length, r * turned + 1e-9);
  EXPECT_GE(length, r * turned * (1.0 - 1e-3)) << "arc length r·angle";
  const Vector2d a = uv(arc.front().start) - centre;
  const Vector2d b = uv(arc.front().end) - centre;
  const double cross = a.x() * b.y() - a.y() * b.x();
  EXPECT_EQ(cross > 0.0, ccw) << "G2 turns clockwise, G3 counter-clockwise, seen from +" << p.n;
}

TEST(GcodeReaderArcs, AllThreePlanesWithOffsetsRadiusFullCircleAndHelix) {
  const double r = 20.0;
  const double tol = 0.01;
  for (const PlaneCase& p : kPlanes) {
    SCOPED_TRACE(fmt::format("G{}", p.g));
    Vector3d start = Vector3d::Zero();
    start[p.au] = r;
    const auto at = [&](double u, double v, double n) {
      Vector3d q = Vector3d::Zero();
      q[p.au] = u;
      q[p.av] = v;
      q[p.an] = n;
      return q;
    };
    const std::string head = fmt::format("G21 G90 M83 F600\nG0 {}{} {}0 {}0\n", p.u, r, p.v, p.n);
    const auto program = [&](const std::string& arc) { return head + fmt::format("G{} ", p.g) + arc + "\n"; };
    // Quarter counter-clockwise and clockwise, with centre offsets.
    expect_arc(read(program(fmt::format("G3 {}0 {}{} {}{} {}0 E1", p.u, p.v, r, p.iu, -r, p.iv))), p, start,
               at(0, r, 0), Vector2d::Zero(), r, kPi / 2, true, tol);
    expect_arc(read(program(fmt::format("G2 {}0 {}{} {}{} {}0 E1", p.u, p.v, -r, p.iu, -r, p.iv))), p, start,
               at(0, -r, 0), Vector2d::Zero(), r, kPi / 2, false, tol);
    // Full circle: the end is the start.
    expect_arc(read(program(fmt::format("G2 {}{} {}0 {}{} E1", p.u, r, p.v, p.iu, -r))), p, start, start,
               Vector2d::Zero(), r, 2 * kPi, false, tol);
    // R: the shorter arc, and with a negative R the longer one about (r, r).
    expect_arc(read(program(fmt::format("G3 {}0 {}{} R{} E1", p.u, p.v, r, r))), p, start, at(0, r, 0),
               Vector2d::Zero(), r, kPi / 2, true, tol);
    expect_arc(read(program(fmt::format("G3 {}0 {}{} R{} E1", p.u, p.v, r, -r))), p, start, at(0, r, 0),
               Vector2d(r, r), r, 3 * kPi / 2, true, tol);
    // Helix: two full turns (P2) while the normal axis rises 5 mm.
    expect_arc(read(program(fmt::format("G3 {}{} {}0 {}5 {}{} P2 E1", p.u, r, p.v, p.n, p.iu, -r))), p, start,
               at(r, 0, 5), Vector2d::Zero(), r, 4 * kPi, true, tol);
  }
}

TEST(GcodeReaderArcs, TheChordToleranceSetsTheSegments) {
  ReaderOptions coarse;
  coarse.chord_tolerance_mm = 0.5;
  const std::string program = "G0 X100 Y0\nG3 X100 Y0 I-100 J0 E1 F600\n";
  const std::size_t fine = moves_of_line(read(program), 2).size();
  const std::size_t few = moves_of_line(read(program, coarse), 2).size();
  // A chord of angle φ sags r (1 − cos φ/2): 2π / (2 acos(1 − tol / r)) chords.
  EXPECT_EQ(fine, static_cast<std::size_t>(std::ceil(kPi / std::acos(1.0 - 0.01 / 100.0))));
  EXPECT_EQ(few, static_cast<std::size_t>(std::ceil(kPi / std::acos(1.0 - 0.5 / 100.0))));
}

TEST(GcodeReaderArcs, ArcsWithoutACentreOrWithTooShortARadiusAreErrors) {
  const auto line_of = [](const std::string& program) {
    try {
      read(program);
    } catch (const InputError& e) {
      return e.where().line;
    }
    return 0;
  };
  EXPECT_EQ(line_of("G0 X0 Y0\nG2 X10 Y0 F600\n"), 2) << "no centre";
  EXPECT_EQ(line_of("G0 X0 Y0\nG1 X1\nG2 X10 Y0 R2 F600\n"), 3) << "radius shorter than half the chord";
  EXPECT_EQ(line_of("G0 X0 Y0\nG2 X0 Y0 R5 F600\n"), 2) << "R with the end on the start";
  EXPECT_EQ(line_of("G0 X0 Y0\nG2 X10 Y0 R5.01 F600\n"), 0) << "a half circle rounded";
}

// ---- modes ----

TEST(GcodeReaderModes, RelativeMovesInchesAndFeeds) {
  const Toolpath tp = read("G91\nG1 X10 Y5 F600\nG1 X10\nG90\nG1 X0\n");
  ASSERT_EQ(tp.moves.size(), 3u);
  EXPECT_EQ(tp.moves[0].end, Vector3d(10, 5, 0));
  EXPECT_EQ(tp.moves[1].end, Vector3d(20, 5, 0));
  EXPECT_EQ(tp.moves[2].end, Vector3d(0, 5, 0));
  EXPECT_DOUBLE_EQ(tp.moves[0].feed_mm_s, 10.0);
  EXPECT_EQ(tp.moves[0].source_line, 2);

  const Toolpath in = read("G20\nG1 X1 Y2 F60\nG21\nG1 X10 F600\n");
  ASSERT_EQ(in.moves.size(), 2u);
  EXPECT_NEAR(in.moves[0].end.x(), 25.4, 1e-12);
  EXPECT_NEAR(in.moves[0].end.y(), 50.8, 1e-12);
  EXPECT_NEAR(in.moves[0].feed_mm_s, 25.4, 1e-12) << "60 in/min";
  EXPECT_NEAR(in.moves[1].end.x(), 10.0, 1e-12);
  EXPECT_NEAR(in.moves[1].feed_mm_s, 10.0, 1e-12);

  ReaderOptions inch;
  inch.inches = true;
  EXPECT_NEAR(read("G1 X1 F60\n", inch).moves.at(0).end.x(), 25.4, 1e-12) << "the default units";

  const Toolpath shifted = read("G1 X10 F600\nG92 X0 Y0\nG1 X5 Y1\n");
  ASSERT_EQ(shifted.moves.size(), 2u);
  EXPECT_EQ(shifted.moves[1].end, Vector3d(15, 1, 0)) << "G92 moves the program's origin";

  const Toolpath homed = read("G1 X10 Y10 F600\nG28 X0\nG1 Y20\n");
  EXPECT_EQ(homed.moves.at(1).start, Vector3d(0, 10, 0));
}

TEST(GcodeReaderModes, VolumeFromEWithResetsAndRelativeE) {
  const double d = 1.75;
  const Toolpath tp = read(
      "G21 G90 M82\n"
      "G1 X10 E1 F600\n"    // E +1
      "G1 X20 E3\n"         // E +2
      "G92 E0\n"            //
      "G1 X30 E0.5\n"       // E +0.5
      "M83\n"               //
      "G1 X40 E0.25\n"      // E +0.25
      "G1 X50 E0.25\n"      // E +0.25
      "G91\nG1 X10 E1\n");  // E +1 (G91: relative E too)
  const double sum_e = 1 + 2 + 0.5 + 0.25 + 0.25 + 1;
  EXPECT_NEAR(tp.commanded_volume_mm3(), filament_area(d) * sum_e, 1e-9);
  ASSERT_EQ(tp.moves.size(), 6u);
  EXPECT_NEAR(tp.moves[1].volume_mm3, 2 * filament_area(d), 1e-12);
  EXPECT_NEAR(tp.moves[3].volume_mm3, 0.25 * filament_area(d), 1e-12);
  for (const Move& m : tp.moves) EXPECT_EQ(m.kind, MoveKind::kPrint);

  ReaderOptions thick;
  thick.filament_diameter_mm = 2.85;
  EXPECT_NEAR(read("G1 X10 E2 F600\n", thick).commanded_volume_mm3(), 2 * filament_area(2.85), 1e-12);
  EXPECT_NEAR(read("M200 D1.75\nG1 X10 E2 F600\n").commanded_volume_mm3(), 2.0, 1e-12) << "volumetric E";
  EXPECT_NEAR(read("M200 D1.75\nM200 D0\nG1 X10 E2 F600\n").commanded_volume_mm3(), 2 * filament_area(1.75),
              1e-12);
  ReaderOptions vol;
  vol.volumetric_e = true;
  EXPECT_NEAR(read("G1 X10 E2 F600\n", vol).commanded_volume_mm3(), 2.0, 1e-12);
}

TEST(GcodeReaderModes, RetractionsAreReversesAndUnretractsRefillFirst) {
  const double a = filament_area(1.75);
  const Toolpath tp = read("G1 X10 E1 F600\nG1 E0.5 F1800\nG0 X20\nG1 E1\nG1 E1.2\nG1 X30 E2.2 F600\n");
  ASSERT_EQ(tp.moves.size(), 6u);
  EXPECT_EQ(tp.moves[1].kind, MoveKind::kDwell);
  EXPECT_EQ(tp.moves[1].event, ExtruderEvent::kReverse);
  EXPECT_NEAR(tp.moves[1].duration_s, 0.5 / 30.0, 1e-12) << "0.5 mm at 1800 mm/min";
  EXPECT_EQ(tp.moves[1].volume_mm3, 0.0);
  EXPECT_EQ(tp.moves[2].kind, MoveKind::kTravel);
  EXPECT_EQ(tp.moves[3].event, ExtruderEvent::kPrime);
  EXPECT_NEAR(tp.moves[3].volume_mm3, 0.0, 1e-12) << "the unretract refills the nozzle";
  EXPECT_EQ(tp.moves[4].event, ExtruderEvent::kPrime);
  EXPECT_NEAR(tp.moves[4].volume_mm3, 0.2 * a, 1e-12) << "past the refill: a prime";
  EXPECT_NEAR(tp.commanded_volume_mm3(), (1 + 0.2 + 1) * a, 1e-12);
  ReaderOptions no_refill;
  no_refill.refill_after_retract = false;
  EXPECT_NEAR(read("G1 X10 E1 F600\nG1 E0.5\nG1 E1\n", no_refill).commanded_volume_mm3(), 1.5 * a, 1e-12);
}

TEST(GcodeReaderModes, DwellsInMillisecondsOrSeconds) {
  const Toolpath tp = read("G4 P500\nG4 S2\nG4 X1.5\n");
  ASSERT_EQ(tp.moves.size(), 3u);
  EXPECT_DOUBLE_EQ(tp.moves[0].duration_s, 0.5);
  EXPECT_DOUBLE_EQ(tp.moves[1].duration_s, 2.0);
  EXPECT_DOUBLE_EQ(tp.moves[2].duration_s, 1.5);
  for (const Move& m : tp.moves) EXPECT_EQ(m.kind, MoveKind::kDwell);
  ReaderOptions fanuc;
  fanuc.dwell_p_seconds = true;
  EXPECT_DOUBLE_EQ(read("G4 P1.5\n", fanuc).moves.at(0).duration_s, 1.5);
}

// ---- pumps and events ----

Extruder gear_pump() {
  Extruder e;
  e.kind = ExtruderKind::kGearPump;
  e.displacement_mm3_per_rev = 10000.0;  // 10 cm³/rev
  return e;
}

TEST(GcodeReaderPump, SpeedWordsGiveFlowAndEventsTheMeltState) {
  ReaderOptions o;
  o.extruder = gear_pump();
  ReadStats st;
  const Toolpath tp = read(
      "M27\n"
      "G0 X0 Y0 Z5 F6000\n"
      "M23 S30\n"        // 30 rpm: 5000 mm³/s
      "G4 P1000\n"       // a dwell with the pump on: a prime blob
      "M104 S200\n"      // S of M104 is a temperature
      "G1 X100 F3000\n"  // 2 s at 50 mm/s
      "G1 X200 S60\n"    // twice the speed: twice the material
      "M24\nM24\n"       // melt off once
      "G0 X0\nM28\n",
      o, &st);
  std::vector<ExtruderEvent> events;
  for (const Move& m : tp.moves)
    if (m.kind == MoveKind::kDwell) events.push_back(m.event);
  EXPECT_EQ(events,
            (std::vector<ExtruderEvent>{ExtruderEvent::kHeatOn, ExtruderEvent::kMeltOn, ExtruderEvent::kPrime,
                                        ExtruderEvent::kMeltOff, ExtruderEvent::kHeatOff}));
  const std::vector<Move> prime = moves_of_line(tp, 4);
  ASSERT_EQ(prime.size(), 1u);
  EXPECT_NEAR(prime[0].volume_mm3, 5000.0, 1e-9);
  EXPECT_EQ(prime[0].feature, Feature::kPrime);
  EXPECT_NEAR(moves_of_line(tp, 6).at(0).volume_mm3, 10000.0, 1e-9);
  EXPECT_NEAR(moves_of_line(tp, 7).at(0).volume_mm3, 20000.0, 1e-9);
  EXPECT_EQ(moves_of_line(tp, 10).at(0).kind, MoveKind::kTravel) << "melt off: no material";
  EXPECT_EQ(st.warning_count(), 0u) << (st.messages.empty() ? "" : st.messages[0]);
  // The bead: A = 100 mm², h = 5 (the first layer, at Z 5).
  const Move bead = moves_of_line(tp, 6).at(0);
  EXPECT_NEAR(bead.layer_height_mm, 5.0, 1e-12);
  EXPECT_NEAR(bead.bead_width_mm, bead_width_mm(100.0, 5.0), 1e-12);
  EXPECT_NEAR(bead_area_mm2(bead.bead_width_mm, bead.layer_height_mm), 100.0, 1e-9);

  // M3/M5 as the melt codes of a spindle-style pump.
  ReaderOptions spindle = o;
  spindle.melt_on = {"M3"};
  spindle.melt_off = {"M5"};
  EXPECT_NEAR(read("G0 Z5\nM3 S30\nG1 X100 F3000\nM5\n", spindle).commanded_volume_mm3(), 10000.0, 1e-9);
}

// A machine whose speed word is another letter (ReaderOptions::rpm_word): that letter is the speed, on the
// melt on, on print moves and on the reverse code; S keeps its other meanings (a dwell's seconds) and is no
// speed on a move.
TEST(GcodeReaderPump, TheSpeedWordIsTheConfiguredLetter) {
  ReaderOptions o;
  o.extruder = gear_pump();
  o.rpm_word = "Q";
  o.reverse_on = {"M71"};
  o.reverse_off = {"M72"};
  ReadStats st;
  const std::string program =
      "G0 X0 Y0 Z5 F6000\n"
      "M23 Q30\n"        // 30 rpm: 5000 mm³/s
      "G4 S1\n"          // S of G4 is its time: a 1 s prime blob
      "G1 X100 F3000\n"  // 2 s at 50 mm/s
      "G1 X200 Q60\n"    // twice the speed: twice the material
      "M71 Q20\n"        // the reverse speed: nothing laid
      "G4 P500\n"
      "M72\n"
      "M24\n";
  const Toolpath tp = read(program, o, &st);
  EXPECT_EQ(st.warning_count(), 0u) << (st.messages.empty() ? "" : st.messages[0]);
  const std::vector<Move> blob = moves_of_line(tp, 3);
  ASSERT_EQ(blob.size(), 1u);
  EXPECT_NEAR(blob[0].duration_s, 1.0, 1e-12);
  EXPECT_NEAR(blob[0].volume_mm3, 5000.0, 1e-9);
  EXPECT_NEAR(moves_of_line(tp, 4).at(0).volume_mm3, 10000.0, 1e-9);
  EXPECT_NEAR(moves_of_line(tp, 5).at(0).volume_mm3, 20000.0, 1e-9);
  const std::vector<Move> reverse = moves_of_line(tp, 7);
  ASSERT_EQ(reverse.size(), 1u);
  EXPECT_EQ(reverse[0].event, ExtruderEvent::kReverse);
  EXPECT_EQ(reverse[0].volume_mm3, 0.0);

  // S on a move is no speed here: an unused word, the speed stays.
  ReadStats s_stats;
  const Toolpath s_move = read("G0 Z5\nM23 Q30\nG1 X100 F3000 S60\nM24\n", o, &s_stats);
  EXPECT_NEAR(s_move.commanded_volume_mm3(), 10000.0, 1e-9);
  EXPECT_EQ(s_stats.count("unused word S"), 1u);
  EXPECT_THROW(read("M23 Q-5\n", o), InputError) << "a negative speed";

  // No speed word at all: the pump's speed is never known, S is no speed either.
  ReaderOptions none = o;
  none.rpm_word.clear();
  ReadStats none_stats;
  const Toolpath unknown = read("G0 Z5\nM23 S30\nG1 X100 F3000\nM24\n", none, &none_stats);
  EXPECT_EQ(unknown.commanded_volume_mm3(), 0.0);
  EXPECT_EQ(none_stats.count("unused word S"), 1u);
  EXPECT_EQ(none_stats.count("unknown flow"), 1u);
}

TEST(GcodeReaderPump, UnknownFlowTakesTheDefaultBeadOrWarns) {
  ReadStats st;
  const Toolpath none = read("G0 Z2 F600\nM23\nG1 X100\nG1 X200\nM24\n", {}, &st);
  EXPECT_EQ(none.moves.at(2).kind, MoveKind::kPrint);
  EXPECT_EQ(none.commanded_volume_mm3(), 0.0);
  EXPECT_EQ(st.count("unknown flow"), 2u);
  EXPECT_EQ(st.messages.size(), 1u) << "one message per kind";
  ReaderOptions d;
  d.default_bead_width_mm = 10.0;
  d.default_layer_height_mm = 2.0;
  const Toolpath with = read("G0 Z2\nM23\nG1 X100 F600\nM24\n", d);
  EXPECT_NEAR(with.commanded_volume_mm3(), bead_area_mm2(10.0, 2.0) * 100.0, 1e-9);
  EXPECT_NEAR(with.moves.at(2).bead_width_mm, 10.0, 1e-9);
}

// The hybrid machine of seed 002 (Negrău, Pancu and Grebenișan 2023): a filament drive fed at a constant
// v_e that M23/M24 only start and stop, so the flow is Q = π d_f² v_e / 4 (eq. 1) whatever the axes do and
// the axis feed sets the bead, A = Q / v (eq. 12). Table 1: 1.75 mm filament at 2.31 mm/s.
TEST(GcodeReaderPump, ConstantFilamentFeedLaysQOverTheFeed) {
  Extruder drive;
  drive.kind = ExtruderKind::kFilament;
  drive.filament_diameter_mm = 1.75;
  drive.constant_feed_mm_s = 2.31;
  ReaderOptions o;
  o.extruder = drive;
  const double q = filament_area(1.75) * 2.31;  // 5.56 mm³/s
  ReadStats st;
  const Toolpath tp = read(
      "G0 X0 Y0 Z0.5\n"
      "G1 X10 F100\n"     // melt off: travel
      "M23\n"             // feed start
      "G1 X20 F100\n"     // 10 mm at 100 mm/min: 6 s of feed
      "G1 X30 F550\n"     // 5.5 times faster: 5.5 times thinner
      "G4 P500\n"         // the feed runs on while the head waits: 0.5 s of it, a blob
      "G0 X40\n"          // rapid: nothing booked
      "G1 X50 E1 F100\n"  // an E word says what is fed instead
      "M24\n"             // feed stop
      "G1 X60 F100\n",
      o, &st);
  EXPECT_EQ(moves_of_line(tp, 2).at(0).kind, MoveKind::kTravel);
  const Move slow = moves_of_line(tp, 4).at(0), fast = moves_of_line(tp, 5).at(0);
  EXPECT_NEAR(slow.volume_mm3, q * 6.0, 1e-9);
  EXPECT_NEAR(fast.volume_mm3, q * 60.0 / 550.0 * 10.0, 1e-9);
  EXPECT_NEAR(slow.volume_mm3 / slow.length_mm(), q / (100.0 / 60.0), 1e-9);  // A = Q / v
  EXPECT_NEAR(bead_area_mm2(slow.bead_width_mm, 0.5), q / (100.0 / 60.0), 1e-9);
  EXPECT_GT(slow.bead_width_mm, 5.0 * fast.bead_width_mm);
  EXPECT_NEAR(moves_of_line(tp, 6).at(0).volume_mm3, q * 0.5, 1e-9);
  EXPECT_EQ(moves_of_line(tp, 7).at(0).kind, MoveKind::kTravel);
  EXPECT_NEAR(moves_of_line(tp, 8).at(0).volume_mm3, filament_area(1.75) * 1.0, 1e-9);
  EXPECT_EQ(moves_of_line(tp, 10).at(0).kind, MoveKind::kTravel) << "feed stopped: no material";
  EXPECT_EQ(st.count("unknown flow"), 0u);

  // Without codes to start and stop it, a constant feed is refused.
  ReaderOptions no_codes = o;
  no_codes.melt_on.clear();
  EXPECT_THROW((void)read("G1 X1 F100\n", no_codes), InputError);
  // A pump has no constant filament feed.
  ReaderOptions pump = o;
  pump.extruder = gear_pump();
  pump.extruder->constant_feed_mm_s = 2.31;
  EXPECT_THROW((void)read("G1 X1 F100\n", pump), InputError);
}

// ---- layers, beads, features ----

TEST(GcodeReaderLayers, MaterialAtANewZStartsALayerHopsDoNot) {
  const double a = filament_area(1.75);
  ReadStats st;
  const Toolpath tp = read(
      ";LAYER_CHANGE\n"
      "G1 Z0.3 F600\n"    // 2
      "G1 X10 E1\n"       // 3: layer 0
      "G1 Z0.7\n"         // 4: hop
      "G1 X20\n"          // 5: travel at the hop
      "G1 Z0.3\n"         // 6
      "G1 X30 E2\n"       // 7: still layer 0
      ";LAYER_CHANGE\n"   //
      "G1 Z0.6\n"         // 9: into layer 1
      "G1 X40 E3\n"       // 10: layer 1, 0.3 high
      ";LAYER_CHANGE\n"   //
      ";HEIGHT:0.35\n"    //
      "G1 Z1.0\n"         // 13
      "G1 X50 E3.001\n",  // 14: layer 2, annotated 0.35 high, and too little material to flatten: round
      {}, &st);
  ASSERT_EQ(tp.layers.size(), 3u);
  EXPECT_NEAR(tp.layers[0].z_mm, 0.3, 1e-12);
  EXPECT_NEAR(tp.layers[0].height_mm, 0.3, 1e-12);
  EXPECT_NEAR(tp.layers[1].height_mm, 0.3, 1e-12);
  EXPECT_NEAR(tp.layers[2].height_mm, 0.35, 1e-12);
  EXPECT_EQ(moves_of_line(tp, 2).at(0).layer, 0) << "the move to the first layer's Z is the layer's";
  EXPECT_EQ(moves_of_line(tp, 4).at(0).layer, 0);
  EXPECT_EQ(moves_of_line(tp, 5).at(0).layer, 0);
  EXPECT_EQ(moves_of_line(tp, 9).at(0).layer, 1) << "the move to the new Z is the new layer's";
  EXPECT_EQ(moves_of_line(tp, 14).at(0).layer, 2);
  EXPECT_EQ(tp.layers[1].first_move, 6u);
  EXPECT_EQ(st.count("layer markers"), 0u);

  const Move m = moves_of_line(tp, 10).at(0);
  EXPECT_NEAR(m.layer_height_mm, 0.3, 1e-12);
  EXPECT_NEAR(m.bead_width_mm, bead_width_mm(a / 10.0, 0.3), 1e-12);
  const Move round = moves_of_line(tp, 14).at(0);
  const double area = 0.001 * a / 10.0;
  ASSERT_LT(area, kPi * 0.35 * 0.35 / 4);
  EXPECT_NEAR(round.bead_width_mm, std::sqrt(4 * area / kPi), 1e-12);
  EXPECT_NEAR(round.layer_height_mm, round.bead_width_mm, 1e-15);

  // Markers that do not match the layers found are a warning.
  ReadStats off;
  read(";LAYER_CHANGE\nG1 Z0.3 X10 E1 F600\n;LAYER_CHANGE\n", {}, &off);
  EXPECT_EQ(off.count("layer markers"), 1u);
}

TEST(GcodeReaderLayers, AnnotationsGiveWidthHeightAndFeature) {
  ReadStats st;
  const Toolpath tp = read(
      "G1 Z0.2 F600\n"
      ";TYPE:External perimeter\n;WIDTH:0.5\n;HEIGHT:0.25\n"
      "G1 X10 E1\n"  // 5
      ";TYPE:Internal infill\n"
      "G1 X20 E2\n"  // 7
      ";TYPE:Gap fill\n"
      "G1 X30 E3\n"  // 9
      ";TYPE:Something new\n"
      "G1 X40 E4\n"               // 11
      "G1 X50 E5 ; PERIMETER\n",  // 12: ORNL Slicer 2 style region comment
      {}, &st);
  const Move outer = moves_of_line(tp, 5).at(0);
  EXPECT_EQ(outer.feature, Feature::kBoundary);
  EXPECT_EQ(outer.pass, 0);
  EXPECT_DOUBLE_EQ(outer.bead_width_mm, 0.5);
  EXPECT_DOUBLE_EQ(outer.layer_height_mm, 0.25);
  EXPECT_EQ(moves_of_line(tp, 7).at(0).feature, Feature::kFill);
  EXPECT_EQ(moves_of_line(tp, 9).at(0).feature, Feature::kThinWall);
  EXPECT_EQ(moves_of_line(tp, 11).at(0).feature, Feature::kUnknown);
  EXPECT_EQ(moves_of_line(tp, 12).at(0).feature, Feature::kBoundary);
  EXPECT_EQ(st.count("feature type Something new"), 1u);
  EXPECT_EQ(tp.moves.at(0).feature, Feature::kTravel);
}

// ---- bad input ----

int error_line(const std::string& program, const ReaderOptions& o = {}) {
  try {
    read(program, o);
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "test.gcode");
    return e.where().line;
  }
  return 0;
}

TEST(GcodeReaderBadInput, BinaryAbsurdAndNonFiniteInputAreErrors) {
  EXPECT_EQ(error_line(std::string("G1 X1\nG1 X2\0\x01\x02", 14)), 2) << "NUL bytes: not text";
  EXPECT_EQ(error_line("G1 X1 F600\nG1 X200000\n"), 2) << "200 m";
  EXPECT_EQ(error_line("G91\nG1 X60000 F600\nG1 X60000\n"), 3) << "relative moves adding up past 100 m";
  EXPECT_EQ(error_line("G1 X1 F-5\n"), 1);
  EXPECT_EQ(error_line("G1 X1\n#1=[5\nG1 X#1\n"), 2) << "a macro program's syntax error names its line";
  EXPECT_EQ(error_line("G1 X1 F600\n#1=1000000\nG1 X#1\n"), 3)
      << "macro values are checked like written ones";
  EXPECT_EQ(error_line("G1 X1 F600\nG4 P-1\n"), 2);
  ReaderOptions few;
  few.max_moves = 10;
  EXPECT_EQ(error_line("G0 X100 Y0\nG3 X100 Y0 I-100 J0 F600\n", few), 2) << "too many moves";

  // Blocks from another source (the macro interpreter) are checked too.
  GcodeReader reader({}, "macro.nc");
  Block b;
  b.line = 40;
  b.words = {{'G', 1, 1}, {'X', std::numeric_limits<double>::infinity(), 4}};
  try {
    reader.feed(b);
    ADD_FAILURE() << "an infinite X was taken";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "macro.nc");
    EXPECT_EQ(e.where().line, 40);
    EXPECT_EQ(e.where().column, 4);
  }
  ReaderOptions bad;
  bad.melt_on = {"23"};
  bad.chord_tolerance_mm = 0;
  try {
    GcodeReader r(bad, "x");
    ADD_FAILURE() << "bad options taken";
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find("melt_on"), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("chord_tolerance_mm"), std::string::npos) << e.message();
  }
}

TEST(GcodeReaderBadInput, UnknownWordsAreCountedWarningsNeverSpam) {
  std::string program = "G1 X1 F600\n";
  for (int i = 0; i < 50; ++i) program += "M999\nG1 X2 Q5\n";
  program += "G1 X10 A90\nG1 X11 B5\nT1\nG93\n";
  ReaderOptions o;
  o.max_messages = 3;
  ReadStats st;
  const Toolpath tp = read(program, o, &st);
  EXPECT_EQ(st.count("unknown code M999"), 50u);
  EXPECT_EQ(st.count("unused word Q"), 50u);
  EXPECT_EQ(st.count("rotary axis A"), 0u);  // rotary axes are kept, not warned about
  EXPECT_EQ(st.count("tool change"), 1u);
  EXPECT_EQ(st.count("unknown code G93"), 1u);
  EXPECT_EQ(st.messages.size(), 3u);
  EXPECT_EQ(st.messages[0], "test.gcode:2:1: gcode: unknown code M999; ignored with its parameters");
  EXPECT_NE(st.messages[1].find("test.gcode:3:7:"), std::string::npos) << st.messages[1];
  EXPECT_EQ(tp.moves.back().end.x(), 11.0) << "rotary axes do not stop the move";
  EXPECT_EQ(st.lines, 105u);
}

TEST(GcodeReaderBadInput, AToolChangeIsOneWarningWithOrWithoutM6) {
  // T2 M06 on one line is one tool change, not a tool change and an unknown M6; M6 alone is one too.
  ReadStats st;
  (void)read("G1 X1 F600\nT2 M06\nG1 X2\nM6 T3\nM6\nG1 X3\n", {}, &st);
  EXPECT_EQ(st.count("tool change"), 3u);
  EXPECT_EQ(st.count("unknown code M6"), 0u);
  ASSERT_EQ(st.messages.size(), 1u);
  EXPECT_EQ(st.messages[0], "test.gcode:2:1: gcode: tool change T2 ignored: one extruder is modelled");
}

TEST(GcodeReaderBadInput, ProgramEndAndBlockDelete) {
  ReadStats st;
  const Toolpath tp = read("G1 X1 F600\n/G1 X5\nM30\nG1 X100\nG1 Xjunk\n", {}, &st);
  EXPECT_TRUE(st.ended);
  EXPECT_EQ(st.deleted_blocks, 1u);
  ASSERT_EQ(tp.moves.size(), 1u) << "the block deleted and everything after M30 left out";
  EXPECT_EQ(st.lines, 3u) << "reading stops at the end of the program";
  ReaderOptions keep;
  keep.block_delete = false;
  EXPECT_EQ(read("G1 X1 F600\n/G1 X5\nM2\n", keep).moves.size(), 2u);
  // A macro program is read whole: all its lines, not those before its first macro line.
  ReadStats macro;
  (void)read("G0 X0 F600\n#1 = 5\nWHILE [#1 GT 0] DO 1\nG1 X#1\n#1 = #1 - 1\nEND 1\nM30", {}, &macro);
  EXPECT_EQ(macro.lines, 7u);
}

// Rotary axes B and C (seed 002's 5-axis machine) are parsed and kept with the moves,
// absolute or relative like the linear axes; a program without them keeps no rotary column at all.
TEST(GcodeReader, RotaryAxesAreKeptWithTheMoves) {
  const Toolpath tp =
      read("G90\nG1 X10 F600\nG1 X20 B90\nG1 X30 C45\nG91\nG1 X5 B-30 C15\nG90\nG92 B0\nG1 X40\n");
  ASSERT_EQ(tp.rotary_deg.size(), tp.moves.size());
  ASSERT_GE(tp.moves.size(), 5u);
  const auto at = [&](double x) {
    for (std::size_t i = 0; i < tp.moves.size(); ++i)
      if (std::abs(tp.moves[i].end.x() - x) < 1e-9) return tp.rotary_deg[i];
    ADD_FAILURE() << "no move to x = " << x;
    return Eigen::Vector3f(Eigen::Vector3f::Zero());
  };
  EXPECT_TRUE(at(10).isZero());
  EXPECT_FLOAT_EQ(at(20).y(), 90.0f);
  EXPECT_FLOAT_EQ(at(30).y(), 90.0f);
  EXPECT_FLOAT_EQ(at(30).z(), 45.0f);
  EXPECT_FLOAT_EQ(at(35).y(), 60.0f);  // relative
  EXPECT_FLOAT_EQ(at(35).z(), 60.0f);
  EXPECT_FLOAT_EQ(at(40).y(), 0.0f);  // G92 B0 set it
  EXPECT_TRUE(read("G1 X10 F600\nG1 X20\n").rotary_deg.empty());
}

// The part-cooling fan (Marlin M106 S0-255 / M107): every move carries the fan's output from the line that
// set it on, as a fraction of full; M106 without S is full; M106 with P2 is another fan and changes nothing
// here; the speed word S of an M106 block is the fan's, never the pump's.
TEST(GcodeReader, FanCodesSetTheFanOutputOfTheMovesAfterThem) {
  ReaderOptions o;
  o.rpm_word = "S";
  const Toolpath tp =
      read("G90\nG1 X10 F600\nM106 S128\nG1 X20\nM106 P2 S255\nG1 X30\nM106\nG1 X40\nM107\nG1 X50\n", o);
  const auto fan_at = [&](double x) {
    for (const Move& m : tp.moves)
      if (std::abs(m.end.x() - x) < 1e-9) return m.fan;
    ADD_FAILURE() << "no move to x = " << x;
    return -1.0f;
  };
  EXPECT_FLOAT_EQ(fan_at(10), 0.0f);
  EXPECT_FLOAT_EQ(fan_at(20), 128.0f / 255.0f);
  EXPECT_FLOAT_EQ(fan_at(30), 128.0f / 255.0f);
  EXPECT_FLOAT_EQ(fan_at(40), 1.0f);
  EXPECT_FLOAT_EQ(fan_at(50), 0.0f);
  // On a machine whose fan-on code is another one, M106 is housekeeping and the fan stays off.
  ReaderOptions other;
  other.fan_on = {"M300"};
  other.fan_off = {"M301"};
  const Toolpath off = read("G1 X10 F600\nM106 S255\nG1 X20\nM300 S51\nG1 X30\n", other);
  EXPECT_FLOAT_EQ(off.moves.at(1).fan, 0.0f);
  EXPECT_FLOAT_EQ(off.moves.at(2).fan, 0.2f);
}

// The hot end's target (M104/M109 S, M109 R): every move carries the temperature the program last set for
// the tool in use, NaN before any; a T word other than T0 names another tool's heater and is no tool change;
// S0 (heater off) leaves the beads' temperature alone; the S of these blocks is never the pump's speed.
TEST(GcodeReader, HeaterTargetsSetTheNozzleTemperatureOfTheMovesAfterThem) {
  ReaderOptions o;
  o.rpm_word = "S";
  ReadStats st;
  const Toolpath tp = read(
      "M83\nG1 Z0.2 F600\nG1 X10 E1\nM104 S200\nG1 X20 E1\nM109 T0 S215\nG1 X30 E1\nM104 T1 S180\nG1 X40 E1\n"
      "M104 S0\nG1 X50 E1\nM109 R190\nG1 X60 E1\n",
      o, &st);
  const auto nozzle_at = [&](double x) {
    for (const Move& m : tp.moves)
      if (std::abs(m.end.x() - x) < 1e-9) return m.nozzle_c;
    ADD_FAILURE() << "no move to x = " << x;
    return -1.0f;
  };
  EXPECT_TRUE(std::isnan(nozzle_at(10)));
  EXPECT_FLOAT_EQ(nozzle_at(20), 200.0f);
  EXPECT_FLOAT_EQ(nozzle_at(30), 215.0f);
  EXPECT_FLOAT_EQ(nozzle_at(40), 215.0f);
  EXPECT_FLOAT_EQ(nozzle_at(50), 215.0f);
  EXPECT_FLOAT_EQ(nozzle_at(60), 190.0f);
  EXPECT_EQ(st.warning_count(), 0u) << (st.messages.empty() ? "" : st.messages[0]);
  double volume = 0.0;
  for (const Move& m : tp.moves) volume += m.volume_mm3;
  EXPECT_NEAR(volume, 6.0 * std::numbers::pi * 1.75 * 1.75 / 4.0, 1e-9) << "no S taken as a pump speed";
  // On a machine whose programs set no temperature this way, M104 is housekeeping.
  ReaderOptions other;
  other.nozzle_temp = {};
  EXPECT_TRUE(std::isnan(read("M104 S200\nG1 X10 E1 F600\n", other).moves.back().nozzle_c));
}

}  // namespace
}  // namespace beadtwin::gcode
