// Whole programs through the G-code reader: our own writer's output read back, and PrusaSlicer's.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <Eigen/Geometry>

#include "core/bead.hpp"
#include "core/flow.hpp"
#include "core/units.hpp"
#include "gcode/program_reader.hpp"
#include "gcode/writer.hpp"

namespace beadtwin::gcode {
namespace {

using Eigen::Vector3d;

constexpr double kHeight = 2.0;  // mm
constexpr double kArea = 20.0;   // mm², bead section
constexpr double kFeed = 50.0;   // mm/s: a pump flow of 1000 mm³/s, 6 rpm at 10 cm³/rev
constexpr double kPrimeS = 1.5;  // s

Extruder gear_pump() {
  Extruder e;
  e.kind = ExtruderKind::kGearPump;
  e.displacement_mm3_per_rev = 10000.0;
  return e;
}

Extruder filament_drive() {
  Extruder e;
  e.kind = ExtruderKind::kFilament;
  e.filament_diameter_mm = 2.85;
  return e;
}

// Two layers of beads as the planner lays them, with the layers, features and events the reader is to
// find again: travel, melt on, prime, a boundary square (roller down), melt off, [reverse], travel up,
// melt on, three fill moves, melt off.
Toolpath hand_toolpath(double prime_volume_mm3, bool reverse) {
  Toolpath tp;
  tp.sections = {"base"};
  for (const double z : {kHeight, 2 * kHeight}) {
    ToolpathLayer l;
    l.z_mm = z;
    l.height_mm = kHeight;
    l.section = 0;
    tp.layers.push_back(l);
  }
  Vector3d at = Vector3d::Zero();
  int layer = 0;
  const auto add = [&](MoveKind kind, const Vector3d& to) -> Move& {
    Move m;
    m.kind = kind;
    m.start = at;
    m.end = to;
    m.section = 0;
    m.layer = layer;
    m.feature = Feature::kTravel;
    if (kind == MoveKind::kPrint) {
      m.feed_mm_s = kFeed;
      m.volume_mm3 = kArea * m.length_mm();
      m.bead_width_mm = bead_width_mm(kArea, kHeight);
      m.layer_height_mm = kHeight;
    } else if (kind == MoveKind::kTravel) {
      m.feed_mm_s = 200.0;
    }
    at = to;
    tp.moves.push_back(m);
    return tp.moves.back();
  };
  const auto event = [&](ExtruderEvent e) -> Move& {
    Move& m = add(MoveKind::kDwell, at);
    m.event = e;
    return m;
  };
  add(MoveKind::kTravel, {10, 10, kHeight});
  event(ExtruderEvent::kMeltOn);
  Move& prime = event(ExtruderEvent::kPrime);
  prime.feature = Feature::kPrime;
  prime.duration_s = kPrimeS;
  prime.volume_mm3 = prime_volume_mm3;
  prime.layer_height_mm = kHeight;
  for (const Vector3d& p : {Vector3d(110, 10, kHeight), Vector3d(110, 110, kHeight),
                            Vector3d(10, 110, kHeight), Vector3d(10, 10, kHeight)}) {
    Move& m = add(MoveKind::kPrint, p);
    m.feature = Feature::kBoundary;
    m.pass = 0;
    m.roller_down = true;
  }
  event(ExtruderEvent::kMeltOff);
  if (reverse) {
    Move& r = event(ExtruderEvent::kReverse);
    r.feature = Feature::kReverse;
    r.duration_s = 1.0;
  }
  layer = 1;
  add(MoveKind::kTravel, {20, 20, 2 * kHeight});
  event(ExtruderEvent::kMeltOn);
  for (const Vector3d& p :
       {Vector3d(100, 20, 2 * kHeight), Vector3d(100, 40, 2 * kHeight), Vector3d(20, 40, 2 * kHeight)}) {
    Move& m = add(MoveKind::kPrint, p);
    m.feature = Feature::kFill;
  }
  event(ExtruderEvent::kMeltOff);
  tp.index_layers();
  return tp;
}

bool near_rel(double a, double b, double rel) {
  return std::abs(a - b) <= rel * std::max(std::abs(a), std::abs(b));
}

void expect_same(const Toolpath& want, const Toolpath& got, bool roller) {
  ASSERT_EQ(got.moves.size(), want.moves.size());
  ASSERT_EQ(got.layers.size(), want.layers.size());
  for (std::size_t l = 0; l < want.layers.size(); ++l) {
    EXPECT_NEAR(got.layers[l].z_mm, want.layers[l].z_mm, 1e-3);
    EXPECT_NEAR(got.layers[l].height_mm, want.layers[l].height_mm, 1e-3);
    EXPECT_EQ(got.layers[l].first_move, want.layers[l].first_move);
    EXPECT_EQ(got.layers[l].end_move, want.layers[l].end_move);
  }
  for (std::size_t i = 0; i < want.moves.size(); ++i) {
    SCOPED_TRACE(fmt::format("move {}", i));
    const Move& w = want.moves[i];
    const Move& g = got.moves[i];
    EXPECT_EQ(g.kind, w.kind);
    EXPECT_EQ(g.event, w.event);
    EXPECT_EQ(g.feature, w.feature);
    EXPECT_EQ(g.pass, w.pass);
    EXPECT_EQ(g.layer, w.layer);
    EXPECT_LT((g.start - w.start).norm(), 1e-3);
    EXPECT_LT((g.end - w.end).norm(), 1e-3);
    EXPECT_GT(g.source_line, 0);
    if (w.deposits() || g.deposits()) {
      EXPECT_TRUE(near_rel(g.volume_mm3, w.volume_mm3, 1e-3)) << g.volume_mm3 << " vs " << w.volume_mm3;
    }
    if (w.kind == MoveKind::kDwell) {
      EXPECT_TRUE(near_rel(g.duration_s, w.duration_s, 1e-3)) << g.duration_s;
    } else {
      EXPECT_TRUE(near_rel(g.feed_mm_s, w.feed_mm_s, 1e-6)) << g.feed_mm_s;
    }
    if (w.kind == MoveKind::kPrint) {
      EXPECT_TRUE(near_rel(g.bead_width_mm, w.bead_width_mm, 1e-3)) << g.bead_width_mm;
      EXPECT_NEAR(g.layer_height_mm, w.layer_height_mm, 1e-3);
      if (roller) {
        EXPECT_EQ(g.roller_down, w.roller_down);
      }
    }
  }
  EXPECT_TRUE(near_rel(got.commanded_volume_mm3(), want.commanded_volume_mm3(), 1e-3));
}

TEST(GcodeReaderRoundTrip, PumpProgramWithPrimeReverseAndRollerReadsBack) {
  const Extruder pump = gear_pump();
  // Prime at 12 rpm (2000 mm³/s) for 1.5 s.
  const Toolpath tp = hand_toolpath(flow_for_rpm(pump, 12.0) * kPrimeS, true);
  GcodeDialect d;
  d.prime_code = "M60";
  d.reverse_on = "M61";
  d.reverse_off = "M62";
  d.roller_down = "M50";
  d.roller_up = "M51";
  GcodeOptions o;
  o.extruder = &pump;
  const std::string program = write_gcode(tp, d, {"T", "sc", "v", "m", "x"}, o);
  ASSERT_NE(program.find("M23 S12"), std::string::npos) << program;
  ASSERT_NE(program.find(" S6"), std::string::npos) << program;
  std::istringstream in(program);
  ReadStats st;
  const Toolpath back = read_gcode(in, "roundtrip.nc", reader_options_for(d, &pump), &st);
  EXPECT_EQ(st.warning_count(), 0u) << (st.messages.empty() ? "" : st.messages[0]);
  EXPECT_TRUE(st.ended);
  expect_same(tp, back, true);
  EXPECT_EQ(back.sections, std::vector<std::string>{"roundtrip"});

  // The same program in inches.
  d.inches = true;
  std::istringstream inch(write_gcode(tp, d, {}, o));
  const Toolpath back_in = read_gcode(inch, "roundtrip.nc", reader_options_for(d, &pump));
  ASSERT_EQ(back_in.moves.size(), tp.moves.size());
  for (std::size_t i = 0; i < tp.moves.size(); ++i)
    EXPECT_LE((back_in.moves[i].end - tp.moves[i].end).cwiseAbs().maxCoeff(), 0.0127 + 1e-9)
        << "half a unit of three decimals of an inch";
  EXPECT_TRUE(near_rel(back_in.commanded_volume_mm3(), tp.commanded_volume_mm3(), 2e-3));
}

TEST(GcodeReaderRoundTrip, FilamentProgramReadsBack) {
  const Extruder drive = filament_drive();
  const Toolpath tp = hand_toolpath(30.0, false);
  const GcodeDialect d;
  GcodeOptions o;
  o.extruder = &drive;
  const std::string program = write_gcode(tp, d, {}, o);
  ASSERT_NE(program.find("M83"), std::string::npos);
  std::istringstream in(program);
  ReadStats st;
  const Toolpath back = read_gcode(in, "roundtrip.nc", reader_options_for(d, &drive), &st);
  EXPECT_EQ(st.warning_count(), 0u) << (st.messages.empty() ? "" : st.messages[0]);
  expect_same(tp, back, false);
}

TEST(GcodeReaderRoundTrip, ArcProgramFollowsTheCircle) {
  // A circle of 144 chords, written as a few G3 arcs within 0.05 mm, read back as chords within 0.01 mm.
  const Extruder drive = filament_drive();
  const Vector3d c(250, 150, 5);
  const double r = 100.0;
  Toolpath tp;
  tp.sections = {"base"};
  tp.layers.push_back(ToolpathLayer{});
  tp.layers[0].z_mm = 5;
  tp.layers[0].height_mm = 5;
  tp.layers[0].section = 0;
  const auto on_circle = [&](int k) {
    const double a = 2 * kPi * k / 144;
    return Vector3d(c.x() + r * std::cos(a), c.y() + r * std::sin(a), 5);
  };
  Move travel;
  travel.end = on_circle(0);
  travel.feed_mm_s = 200;
  tp.moves.push_back(travel);
  for (int k = 0; k < 144; ++k) {
    Move m;
    m.kind = MoveKind::kPrint;
    m.start = on_circle(k);
    m.end = on_circle(k + 1);
    m.feed_mm_s = 50;
    m.volume_mm3 = 60.0 * m.length_mm();
    m.section = 0;
    m.layer = 0;
    tp.moves.push_back(m);
  }
  tp.index_layers();
  GcodeDialect d;
  d.arcs = true;
  GcodeOptions o;
  o.arc_tolerance_mm = {0.05};
  o.extruder = &drive;
  std::istringstream in(write_gcode(tp, d, {}, o));
  ReadStats st;
  const Toolpath back = read_gcode(in, "arcs.nc", reader_options_for(d, &drive), &st);
  EXPECT_GE(st.arcs, 2u);
  EXPECT_LE(st.arcs, 4u);
  EXPECT_GT(back.moves.size(), 144u) << "the arcs are linearised finer than the original chords";
  EXPECT_TRUE(near_rel(back.commanded_volume_mm3(), tp.commanded_volume_mm3(), 1e-3));
  for (const Move& m : back.moves) {
    if (m.kind != MoveKind::kPrint) continue;
    // Original chords sag 0.024 mm; the fitted arcs stay within 0.05 mm of them; rounding 0.001 mm.
    EXPECT_LT(std::abs((m.end - c).norm() - r), 0.08);
    EXPECT_LT(std::abs((0.5 * (m.start + m.end) - c).norm() - r), 0.09);
  }
  ASSERT_EQ(back.layers.size(), 1u);
  EXPECT_NEAR(back.layers[0].z_mm, 5.0, 1e-9);
}

// ---- PrusaSlicer ----

// A box sx × sy × sz mm standing on the bed, as an ASCII STL.
std::string box_stl(double sx, double sy, double sz) {
  const Vector3d v[8] = {{0, 0, 0},  {sx, 0, 0},  {sx, sy, 0},  {0, sy, 0},
                         {0, 0, sz}, {sx, 0, sz}, {sx, sy, sz}, {0, sy, sz}};
  const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                        {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  std::string out = "solid box\n";
  for (const auto& t : f) {
    const Vector3d n = (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).normalized();
    out += fmt::format(" facet normal {} {} {}\n  outer loop\n", n.x(), n.y(), n.z());
    for (const int i : t) out += fmt::format("   vertex {} {} {}\n", v[i].x(), v[i].y(), v[i].z());
    out += "  endloop\n endfacet\n";
  }
  return out + "endsolid box\n";
}

// What the program says about itself, found without the reader: layer change markers, the filament
// pushed out on moves in XY (E growing, absolute or relative, with G92 resets), the slicer's own total.
struct Facts {
  int layer_changes = 0;
  double extruded_mm = 0.0;
  double filament_used_mm = -1.0;
  double diameter_mm = -1.0;
};

Facts facts_of(const std::string& program) {
  Facts f;
  std::istringstream in(program);
  std::string line;
  bool relative = false;
  double e = 0.0;
  while (std::getline(in, line)) {
    if (line.rfind(";LAYER_CHANGE", 0) == 0) ++f.layer_changes;
    if (line.rfind("; filament used [mm] = ", 0) == 0) f.filament_used_mm = std::stod(line.substr(23));
    if (line.rfind("; filament_diameter = ", 0) == 0) f.diameter_mm = std::stod(line.substr(22));
    const std::string code = line.substr(0, line.find(';'));
    std::istringstream words(code);
    std::map<char, double> w;
    std::string word;
    while (words >> word)
      if (word.size() > 1) w[word[0]] = std::stod(word.substr(1));
    if (w.count('M') && w['M'] == 82) relative = false;
    if (w.count('M') && w['M'] == 83) relative = true;
    if (!w.count('G') || !w.count('E')) continue;
    if (w['G'] == 92) {
      e = w['E'];
      continue;
    }
    const double de = relative ? w['E'] : w['E'] - e;
    e = relative ? e + de : w['E'];
    if (de > 0 && (w.count('X') || w.count('Y'))) f.extruded_mm += de;
  }
  return f;
}

void expect_reads_as_sliced(const std::string& program) {
  const Facts f = facts_of(program);
  ASSERT_GT(f.layer_changes, 0);
  ASSERT_GT(f.diameter_mm, 0.0);
  ASSERT_GT(f.filament_used_mm, 0.0);
  ReaderOptions o;
  o.filament_diameter_mm = f.diameter_mm;
  std::istringstream in(program);
  ReadStats st;
  const Toolpath tp = read_gcode(in, "box.gcode", o, &st);
  for (const std::string& m : st.messages) ADD_FAILURE() << "warning: " << m;
  EXPECT_EQ(tp.layers.size(), static_cast<std::size_t>(f.layer_changes));
  EXPECT_EQ(st.layer_markers, static_cast<std::size_t>(f.layer_changes));
  const double area = kPi * f.diameter_mm * f.diameter_mm / 4.0;
  EXPECT_TRUE(near_rel(tp.commanded_volume_mm3(), area * f.extruded_mm, 1e-9))
      << tp.commanded_volume_mm3() << " vs " << area * f.extruded_mm;
  EXPECT_TRUE(near_rel(tp.commanded_volume_mm3(), area * f.filament_used_mm, 1e-3))
      << "PrusaSlicer's own total, " << f.filament_used_mm << " mm";
  std::map<Feature, int> features;
  int reverses = 0;
  int primes = 0;
  for (const Move& m : tp.moves) {
    if (m.kind == MoveKind::kPrint) {
      ++features[m.feature];
      EXPECT_GT(m.bead_width_mm, 0.3);
      EXPECT_LT(m.bead_width_mm, 1.0);
      // 0.3 mm layers; bridges are annotated 0.4 mm high (;HEIGHT:0.4 after ;TYPE:Bridge infill).
      const bool bridge = std::abs(m.layer_height_mm - 0.4) < 1e-3;
      EXPECT_TRUE(std::abs(m.layer_height_mm - 0.3) < 1e-3 || (bridge && m.feature == Feature::kFill))
          << m.layer_height_mm;
    }
    reverses += m.event == ExtruderEvent::kReverse;
    primes += m.event == ExtruderEvent::kPrime;
  }
  EXPECT_GT(features[Feature::kBoundary], 0);
  EXPECT_GT(features[Feature::kFill], 0);
  EXPECT_GT(features[Feature::kPrime], 0) << "the skirt";
  EXPECT_GT(reverses, 0);
  EXPECT_GT(primes, 0);
  for (const ToolpathLayer& l : tp.layers) EXPECT_NEAR(l.height_mm, 0.3, 1e-3);
  EXPECT_NEAR(tp.layers.back().z_mm, 2.4, 1e-3);
}

TEST(GcodeReaderPrusaSlicer, CommittedSampleReadsAsSliced) {
  // tests/data/prusa_box.gcode: PrusaSlicer 2.5.0, the 15 × 15 × 2.4 mm box of the test below.
  std::ifstream file(std::string(BEADTWIN_SOURCE_DIR) + "/tests/data/prusa_box.gcode");
  ASSERT_TRUE(file) << "tests/data/prusa_box.gcode";
  std::stringstream text;
  text << file.rdbuf();
  expect_reads_as_sliced(text.str());
}

TEST(GcodeReaderPrusaSlicer, FreshlySlicedBoxReadsAsSliced) {
  if (std::system("command -v prusa-slicer > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "prusa-slicer not installed";
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / fmt::format("beadtwin_prusa_{}", ::getpid());
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "box.stl") << box_stl(15, 15, 2.4);
  for (const char* e_mode : {"", "--use-relative-e-distances"}) {
    SCOPED_TRACE(*e_mode ? e_mode : "absolute E");
    const std::filesystem::path out = dir / "box.gcode";
    std::filesystem::remove(out);
    const std::string cmd = fmt::format(
        "prusa-slicer --export-gcode --output '{}' --layer-height 0.3 --first-layer-height 0.3 "
        "--fill-density 15% "
        "--top-solid-layers 2 --bottom-solid-layers 2 {} '{}' > '{}' 2>&1",
        out.string(), e_mode, (dir / "box.stl").string(), (dir / "log.txt").string());
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream file(out);
    ASSERT_TRUE(file);
    std::stringstream text;
    text << file.rdbuf();
    if (*e_mode) {
      ASSERT_NE(text.str().find("\nM83"), std::string::npos);
    }
    expect_reads_as_sliced(text.str());
  }
  std::filesystem::remove_all(dir);
}

// Slic3r (1.3, Debian's slic3r), a 10 mm ball at 0.3 mm layers with its default 3 mm filament: the
// program states the filament diameter only in its settings at the end, and the reader finds it there, so
// the volume is the filament Slic3r reports ("; filament used = 70.0mm") times π·1.5².
TEST(GcodeReaderSlic3r, CommittedSampleReadsWithTheProgramsFilament) {
  std::ifstream file(std::string(BEADTWIN_SOURCE_DIR) + "/tests/data/slic3r_ball.gcode");
  ASSERT_TRUE(file) << "tests/data/slic3r_ball.gcode";
  ReadStats stats;
  const Toolpath tp = read_gcode(file, "slic3r_ball.gcode", {}, &stats);
  EXPECT_NEAR(tp.commanded_volume_mm3(), 70.0 * kPi * 1.5 * 1.5, 0.05 * kPi * 2.25);  // 70.0 is rounded
  // Layers: 0.35 mm first, then 0.3 mm, up to the ball's 10 mm.
  ASSERT_GE(tp.layers.size(), 30u);
  EXPECT_NEAR(tp.layers.front().z_mm, 0.35, 1e-6);
  for (std::size_t i = 1; i < tp.layers.size(); ++i)
    EXPECT_NEAR(tp.layers[i].z_mm - tp.layers[i - 1].z_mm, 0.3, 1e-6);
  EXPECT_EQ(stats.warning_count(), 0u) << (stats.messages.empty() ? "" : stats.messages.front());
  // Told otherwise, the reader keeps the diameter it is given.
  std::ifstream again(std::string(BEADTWIN_SOURCE_DIR) + "/tests/data/slic3r_ball.gcode");
  ReaderOptions given;
  given.filament_diameter_from_program = false;
  EXPECT_NEAR(read_gcode(again, "slic3r_ball.gcode", given).commanded_volume_mm3(),
              70.0 * kPi * 1.75 * 1.75 / 4, 0.05 * kPi);
}

// ---- CuraEngine ----

// CuraEngine 4.13 (Debian's cura-engine) run on its own with Cura's fdmprinter definition: the box above
// at 0.3 mm layers, 15 % grid infill, 2.85 mm filament, absolute E. Its start code primes 3 mm of filament
// with the head standing 15 mm above the bed ("G1 F200 E3"), retracts 6.5 mm and feeds it back at the
// first layer. Run without the Cura front end, the header's totals are placeholders (";Filament used: 0m"),
// so the facts come from the moves: layer markers ";LAYER:n", filament pushed out on moves in XY, and
// filament fed with the head standing beyond what retractions drew back (the purge).
struct CuraFacts {
  int layer_count = -1;  // ";LAYER_COUNT:"
  int layer_markers = 0;
  double extruded_mm = 0.0;
  double purged_mm = 0.0;
  double time_elapsed_s = -1.0;  // the last ";TIME_ELAPSED:", Cura's estimate of the print time
};

CuraFacts cura_facts_of(const std::string& program) {
  CuraFacts f;
  std::istringstream in(program);
  double e = 0.0;
  double owed = 0.0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(";LAYER_COUNT:", 0) == 0) f.layer_count = std::stoi(line.substr(13));
    if (line.rfind(";LAYER:", 0) == 0) ++f.layer_markers;
    if (line.rfind(";TIME_ELAPSED:", 0) == 0) f.time_elapsed_s = std::stod(line.substr(14));
    std::istringstream words(line.substr(0, line.find(';')));
    std::map<char, double> w;
    for (std::string word; words >> word;)
      if (word.size() > 1) w[word[0]] = std::stod(word.substr(1));
    if (!w.count('G') || !w.count('E')) continue;
    if (w['G'] == 92) {
      e = w['E'];
      continue;
    }
    const double de = w['E'] - e;  // absolute E (M82)
    e = w['E'];
    if (w.count('X') || w.count('Y')) {
      if (de > 0) f.extruded_mm += de;
    } else if (de < 0) {
      owed -= de;
    } else {
      const double refill = std::min(de, owed);
      owed -= refill;
      f.purged_mm += de - refill;
    }
  }
  return f;
}

void expect_reads_as_cura_sliced(const std::string& program) {
  const CuraFacts f = cura_facts_of(program);
  ASSERT_GT(f.layer_markers, 0);
  EXPECT_EQ(f.layer_count, f.layer_markers);
  ReaderOptions o;
  o.filament_diameter_mm = 2.85;  // Cura's programs do not say; fdmprinter's default
  std::istringstream in(program);
  ReadStats st;
  const Toolpath tp = read_gcode(in, "cura_box.gcode", o, &st);
  for (const std::string& m : st.messages) ADD_FAILURE() << "warning: " << m;
  // Layers from Z equal Cura's markers, though the purge stands 15 mm up.
  EXPECT_EQ(tp.layers.size(), static_cast<std::size_t>(f.layer_markers));
  EXPECT_EQ(st.layer_markers, static_cast<std::size_t>(f.layer_markers));
  for (const ToolpathLayer& l : tp.layers) EXPECT_NEAR(l.height_mm, 0.3, 1e-3);
  EXPECT_NEAR(tp.layers.back().z_mm, 2.4, 1e-3);
  // Every millimetre of filament is accounted for: laid on the paths, plus the purge.
  const double area = kPi * 2.85 * 2.85 / 4.0;
  EXPECT_GT(f.purged_mm, 0.0);
  EXPECT_TRUE(near_rel(tp.commanded_volume_mm3(), area * (f.extruded_mm + f.purged_mm), 1e-9))
      << tp.commanded_volume_mm3() << " vs " << area * (f.extruded_mm + f.purged_mm);
  // The purge is a prime with the head standing, counted with the first layer.
  double purge = 0.0;
  for (const Move& m : tp.moves) {
    if (m.kind == MoveKind::kPrint || !m.deposits()) continue;
    EXPECT_EQ(m.event, ExtruderEvent::kPrime);
    EXPECT_EQ(m.layer, 0);
    EXPECT_NEAR(m.layer_height_mm, 0.3, 1e-9);  // the deposit lays it as a puddle of the first layer's height
    purge += m.volume_mm3;
  }
  EXPECT_NEAR(purge, area * f.purged_mm, 1e-9);
  std::map<Feature, int> features;
  for (const Move& m : tp.moves)
    if (m.kind == MoveKind::kPrint) ++features[m.feature];
  EXPECT_GT(features[Feature::kBoundary], 0) << "WALL-OUTER, WALL-INNER";
  EXPECT_GT(features[Feature::kFill], 0) << "SKIN, FILL";
  EXPECT_GT(features[Feature::kPrime], 0) << "SKIRT";
}

TEST(GcodeReaderCuraEngine, CommittedSampleReadsAsSliced) {
  std::ifstream file(std::string(BEADTWIN_SOURCE_DIR) + "/tests/data/cura_box.gcode");
  ASSERT_TRUE(file) << "tests/data/cura_box.gcode";
  std::stringstream text;
  text << file.rdbuf();
  expect_reads_as_cura_sliced(text.str());
}

// Debian's cura-engine comes without Cura's machine definitions (they are in the `cura` package, with
// the Qt front end); the test slices afresh when both are there. BEADTWIN_CURA_DEFINITIONS may name the
// folder that holds fdmprinter.def.json.
TEST(GcodeReaderCuraEngine, FreshlySlicedBoxReadsAsSliced) {
  if (std::system("command -v CuraEngine > /dev/null 2>&1") != 0) GTEST_SKIP() << "CuraEngine not installed";
  std::filesystem::path definitions = "/usr/share/cura/resources/definitions";
  if (const char* d = std::getenv("BEADTWIN_CURA_DEFINITIONS")) definitions = d;
  if (!std::filesystem::exists(definitions / "fdmprinter.def.json"))
    GTEST_SKIP() << "no fdmprinter.def.json in " << definitions << " (set BEADTWIN_CURA_DEFINITIONS)";
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / fmt::format("beadtwin_cura_{}", ::getpid());
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "box.stl") << box_stl(15, 15, 2.4);
  const std::filesystem::path out = dir / "box.gcode";
  const std::string cmd = fmt::format(
      "CuraEngine slice -j '{}' -s layer_height=0.3 -s layer_height_0=0.3 -s infill_sparse_density=15 "
      "-l '{}' -o '{}' > '{}' 2>&1",
      (definitions / "fdmprinter.def.json").string(), (dir / "box.stl").string(), out.string(),
      (dir / "log.txt").string());
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream file(out);
  ASSERT_TRUE(file);
  std::stringstream text;
  text << file.rdbuf();
  expect_reads_as_cura_sliced(text.str());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace beadtwin::gcode
