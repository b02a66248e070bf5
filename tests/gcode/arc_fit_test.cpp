#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/toolpath.hpp"
#include "core/units.hpp"
#include "gcode/arc_fit.hpp"
#include "gcode/writer.hpp"

namespace beadtwin::gcode {
namespace {

using Eigen::Vector2d;
constexpr double kPi = std::numbers::pi;

// A closed regular polygon on a circle: segments + 1 points, the last on the first, counter-clockwise
// unless `clockwise`.
std::vector<Vector2d> circle(int segments, double r, const Vector2d& c = Vector2d::Zero(),
                             bool clockwise = false) {
  std::vector<Vector2d> pts;
  for (int k = 0; k <= segments; ++k) {
    const double a = (clockwise ? -2.0 : 2.0) * kPi * k / segments;
    pts.push_back(c + r * Vector2d(std::cos(a), std::sin(a)));
  }
  return pts;
}

double distance_to_segment(const Vector2d& q, const Vector2d& a, const Vector2d& b) {
  const Vector2d ab = b - a;
  const double s = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (q - (a + s * ab)).norm();
}

// Distance from q to the arc from s to e about c, turning clockwise or counter-clockwise: to the circle
// where q lies within the arc's angle, else to the nearer end.
double distance_to_arc(const Vector2d& q, const Vector2d& s, const Vector2d& e, const Vector2d& c, bool cw) {
  const auto along = [&](const Vector2d& p) {
    double d = std::atan2(p.y() - c.y(), p.x() - c.x()) - std::atan2(s.y() - c.y(), s.x() - c.x());
    if (cw) d = -d;
    d = std::fmod(d, 2 * kPi);
    return d < 0 ? d + 2 * kPi : d;
  };
  if (along(q) <= along(e)) return std::abs((q - c).norm() - (s - c).norm());
  return std::min((q - s).norm(), (q - e).norm());
}

// Checks that the pieces chain through the points and returns the largest distance of a point or segment
// midpoint from the piece that replaces it.
double worst_error(const std::vector<Vector2d>& pts, const std::vector<PathPiece>& pieces) {
  double worst = 0.0;
  std::size_t from = 0;
  for (const PathPiece& p : pieces) {
    EXPECT_GT(p.last_point, from);
    if (p.last_point <= from || p.last_point >= pts.size()) return 1e9;
    EXPECT_EQ(p.end, pts[p.last_point]);
    if (p.is_arc()) {
      EXPECT_GE(p.last_point - from, 3u) << "an arc replaces at least 3 segments";
      EXPECT_NEAR((pts[from] - p.centre).norm(), (p.end - p.centre).norm(), 1e-9);
    } else {
      EXPECT_EQ(p.last_point, from + 1) << "a line is one original segment";
    }
    const auto dist = [&](const Vector2d& q) {
      return p.is_arc() ? distance_to_arc(q, pts[from], p.end, p.centre, p.kind == PieceKind::kArcCw)
                        : distance_to_segment(q, pts[from], p.end);
    };
    for (std::size_t k = from; k <= p.last_point; ++k) {
      worst = std::max(worst, dist(pts[k]));
      if (k < p.last_point) worst = std::max(worst, dist(0.5 * (pts[k] + pts[k + 1])));
    }
    from = p.last_point;
  }
  EXPECT_EQ(from, pts.size() - 1) << "the pieces end on the last point";
  return worst;
}

std::size_t count(const std::vector<PathPiece>& pieces, PieceKind kind) {
  return static_cast<std::size_t>(
      std::count_if(pieces.begin(), pieces.end(), [&](const PathPiece& p) { return p.kind == kind; }));
}

TEST(ArcFit, CircleBecomesAFewArcsWithinTheTolerance) {
  // 144 segments of radius 100: chords sag 100 (1 - cos 1.25°) = 0.024 mm from the circle.
  const Vector2d c(30, -20);
  const std::vector<Vector2d> pts = circle(144, 100.0, c);
  const std::vector<PathPiece> pieces = fit_arcs(pts, 0.05);
  EXPECT_EQ(count(pieces, PieceKind::kLine), 0u);
  EXPECT_GE(count(pieces, PieceKind::kArcCcw), 2u) << "a full circle is at least two arcs";
  EXPECT_LE(count(pieces, PieceKind::kArcCcw), 4u);
  EXPECT_LE(worst_error(pts, pieces), 0.05);
  for (const PathPiece& p : pieces) EXPECT_LT((p.centre - c).norm(), 0.05);

  // The same circle clockwise gives clockwise arcs.
  const std::vector<Vector2d> cw = circle(144, 100.0, c, true);
  const std::vector<PathPiece> cw_pieces = fit_arcs(cw, 0.05);
  EXPECT_EQ(cw_pieces.size(), count(cw_pieces, PieceKind::kArcCw));
  EXPECT_LE(cw_pieces.size(), 4u);
  EXPECT_LE(worst_error(cw, cw_pieces), 0.05);
}

TEST(ArcFit, SegmentMidpointsCountAgainstTheTolerance) {
  // 72 segments of radius 100: vertices lie on the circle but the chords sag 100 (1 - cos 2.5°) = 0.095 mm
  // between them. An arc through the vertices is 0.095 mm off the toolpath: too far for 0.05, fine for 0.1.
  const std::vector<Vector2d> pts = circle(72, 100.0);
  const std::vector<PathPiece> tight = fit_arcs(pts, 0.05);
  EXPECT_EQ(tight.size(), 72u);
  EXPECT_EQ(count(tight, PieceKind::kLine), 72u);
  const std::vector<PathPiece> loose = fit_arcs(pts, 0.1);
  EXPECT_EQ(count(loose, PieceKind::kLine), 0u);
  EXPECT_LE(loose.size(), 4u);
  EXPECT_LE(worst_error(pts, loose), 0.1);
}

TEST(ArcFit, SquareStaysLines) {
  // The corners of a square lie on a circle; its edges' midpoints are 20.7 mm inside it, and it turns
  // 90° at each corner.
  const std::vector<Vector2d> square = {{0, 0}, {100, 0}, {100, 100}, {0, 100}, {0, 0}};
  for (const double tol : {0.05, 5.0}) {
    const std::vector<PathPiece> pieces = fit_arcs(square, tol);
    EXPECT_EQ(pieces.size(), 4u) << tol;
    EXPECT_EQ(count(pieces, PieceKind::kLine), 4u) << tol;
    EXPECT_EQ(worst_error(square, pieces), 0.0);
  }
  // A regular octagon: corners on a circle, edges' midpoints 7.6 mm inside it.
  const std::vector<Vector2d> octagon = circle(8, 100.0);
  const std::vector<PathPiece> octagon_pieces = fit_arcs(octagon, 0.05);
  EXPECT_EQ(count(octagon_pieces, PieceKind::kLine), 8u);
  EXPECT_LT(worst_error(octagon, octagon_pieces), 1e-9);
  // Edges cut into 5 collinear segments each: straight runs stay lines too.
  std::vector<Vector2d> fine;
  for (std::size_t e = 0; e < 4; ++e)
    for (int k = 0; k < 5; ++k) fine.push_back(square[e] + (square[e + 1] - square[e]) * (k / 5.0));
  fine.push_back(square[0]);
  const std::vector<PathPiece> pieces = fit_arcs(fine, 0.05);
  EXPECT_EQ(count(pieces, PieceKind::kLine), 20u);
}

TEST(ArcFit, SCurveGetsArcsOfBothDirectionsNeverAcrossTheInflection) {
  // A left quarter circle (centre (0, 50)) then a right one (centre (100, 50)), radius 50, 2° steps; tangent
  // at the inflection, point 45.
  std::vector<Vector2d> pts;
  for (int k = 0; k <= 45; ++k) {
    const double a = 2.0 * k * kPi / 180.0;
    pts.emplace_back(50 * std::sin(a), 50 - 50 * std::cos(a));
  }
  for (int k = 1; k <= 45; ++k) {
    const double a = kPi - 2.0 * k * kPi / 180.0;
    pts.emplace_back(100 + 50 * std::cos(a), 50 + 50 * std::sin(a));
  }
  // Which way the polyline turns at each vertex (+1 left, -1 right, 0 straight or an end).
  std::vector<int> turn(pts.size(), 0);
  for (std::size_t k = 1; k + 1 < pts.size(); ++k) {
    const Vector2d u = pts[k] - pts[k - 1];
    const Vector2d w = pts[k + 1] - pts[k];
    const double c = u.x() * w.y() - u.y() * w.x();
    turn[k] = c > 1e-9 ? 1 : (c < -1e-9 ? -1 : 0);
  }
  ASSERT_EQ(turn[44], 1);
  ASSERT_EQ(turn[46], -1);
  // Beyond about 0.06 mm an arc could bend on past the inflection and still stay within the tolerance; the
  // turn direction forbids it: no arc keeps a vertex that turns against it.
  for (const double tol : {0.05, 0.5}) {
    const std::vector<PathPiece> pieces = fit_arcs(pts, tol);
    EXPECT_GE(count(pieces, PieceKind::kArcCcw), 1u) << tol;
    EXPECT_GE(count(pieces, PieceKind::kArcCw), 1u) << tol;
    std::size_t from = 0;
    for (const PathPiece& p : pieces) {
      const int against = p.kind == PieceKind::kArcCcw ? -1 : 1;
      for (std::size_t k = from + 1; p.is_arc() && k < p.last_point; ++k) {
        EXPECT_NE(turn[k], against) << "tolerance " << tol << ": arc " << from << ".." << p.last_point;
      }
      from = p.last_point;
    }
    EXPECT_LE(worst_error(pts, pieces), tol);
  }
}

TEST(ArcFit, NoToleranceMeansLines) {
  const std::vector<Vector2d> pts = circle(144, 100.0);
  for (const double tol : {0.0, -1.0}) {
    const std::vector<PathPiece> pieces = fit_arcs(pts, tol);
    ASSERT_EQ(pieces.size(), 144u);
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      EXPECT_EQ(pieces[k].kind, PieceKind::kLine);
      EXPECT_EQ(pieces[k].last_point, k + 1);
      EXPECT_EQ(pieces[k].end, pts[k + 1]);
    }
  }
  EXPECT_TRUE(fit_arcs(std::vector<Vector2d>{{1, 2}}, 0.05).empty());
}

TEST(ArcFit, NoisyCircleKeepsEveryArcWithinTheTolerance) {
  std::mt19937 rng(7);  // the generator's sequence is fixed by the standard; the mapping below is ours
  const auto noise = [&] { return 0.2 * (2.0 * static_cast<double>(rng()) / 4294967295.0 - 1.0); };

  // Uniform radial noise of up to 0.2 mm on every vertex, tolerance 0.05: lines or short arcs.
  std::vector<Vector2d> noisy = circle(360, 100.0);
  for (std::size_t k = 0; k + 1 < noisy.size(); ++k) noisy[k] *= 1.0 + noise() / 100.0;
  noisy.back() = noisy.front();
  const std::vector<PathPiece> pieces = fit_arcs(noisy, 0.05);
  EXPECT_GT(pieces.size(), 100u);
  EXPECT_LE(worst_error(noisy, pieces), 0.05);
  std::size_t start = 0;
  for (const PathPiece& p : pieces) {
    if (p.is_arc()) {
      EXPECT_LE(p.last_point - start, 12u) << "a long arc over noise " << start << ".." << p.last_point;
    }
    start = p.last_point;
  }

  // Every tenth vertex of a fine circle 0.2 mm off: arcs between them, broken at them.
  std::vector<Vector2d> bumpy = circle(360, 100.0);
  for (std::size_t k = 0; k < bumpy.size(); k += 10) bumpy[k] *= (k % 20 == 0 ? 100.2 : 99.8) / 100.0;
  bumpy.back() = bumpy.front();
  const std::vector<PathPiece> bumpy_pieces = fit_arcs(bumpy, 0.05);
  EXPECT_GE(count(bumpy_pieces, PieceKind::kArcCcw), 20u);
  EXPECT_LE(worst_error(bumpy, bumpy_pieces), 0.05);
  std::size_t from = 0;
  for (const PathPiece& p : bumpy_pieces) {
    if (p.is_arc()) {
      for (std::size_t k = from + 1; k < p.last_point; ++k) EXPECT_NE(k % 10, 0u) << "arc over bump " << k;
    }
    from = p.last_point;
  }
  // Without the bumps the same circle is two arcs.
  EXPECT_EQ(fit_arcs(circle(360, 100.0), 0.05).size(), 2u);
}

// ---- The writer ----

// One layer: a travel, melt on, a circle of print moves (boundary pass 1), melt off, a travel and a straight
// fill line cut into four moves.
constexpr int kCircleSegments = 144;
const Vector2d kCentre(250, 150);
constexpr double kRadius = 100.0;

Toolpath circle_toolpath() {
  Toolpath tp;
  tp.sections = {"base"};
  ToolpathLayer layer;
  layer.z_mm = 10;
  layer.height_mm = 5;
  layer.section = 0;
  tp.layers.push_back(layer);
  const auto add = [&](MoveKind kind, Feature feature, const Eigen::Vector3d& from,
                       const Eigen::Vector3d& to) {
    Move m;
    m.kind = kind;
    m.feature = feature;
    m.start = from;
    m.end = to;
    m.section = 0;
    m.layer = 0;
    m.feed_mm_s = kind == MoveKind::kTravel ? 200 : 50;
    if (kind == MoveKind::kPrint) {
      m.bead_width_mm = 20;
      m.layer_height_mm = 5;
      m.volume_mm3 = 100.0 * m.length_mm();
      m.pass = feature == Feature::kBoundary ? 0 : -1;
    }
    tp.moves.push_back(m);
  };
  const auto at = [](const Vector2d& p) { return Eigen::Vector3d(p.x(), p.y(), 10); };
  const std::vector<Vector2d> ring = circle(kCircleSegments, kRadius, kCentre);
  add(MoveKind::kTravel, Feature::kTravel, {0, 0, 50}, at(ring[0]));
  add(MoveKind::kDwell, Feature::kTravel, at(ring[0]), at(ring[0]));
  tp.moves.back().event = ExtruderEvent::kMeltOn;
  for (std::size_t k = 0; k + 1 < ring.size(); ++k)
    add(MoveKind::kPrint, Feature::kBoundary, at(ring[k]), at(ring[k + 1]));
  add(MoveKind::kDwell, Feature::kTravel, at(ring[0]), at(ring[0]));
  tp.moves.back().event = ExtruderEvent::kMeltOff;
  add(MoveKind::kTravel, Feature::kTravel, at(ring[0]), {0, 300, 10});
  add(MoveKind::kDwell, Feature::kTravel, {0, 300, 10}, {0, 300, 10});
  tp.moves.back().event = ExtruderEvent::kMeltOn;
  for (int k = 0; k < 4; ++k)
    add(MoveKind::kPrint, Feature::kFill, {50.0 * k, 300, 10}, {50.0 * (k + 1), 300, 10});
  add(MoveKind::kDwell, Feature::kTravel, {200, 300, 10}, {200, 300, 10});
  tp.moves.back().event = ExtruderEvent::kMeltOff;
  tp.index_layers();
  return tp;
}

// A written motion block in mm: G1, G2 or G3 from `start` to `end`, arcs about `centre`.
struct Block {
  int g = 1;
  Vector2d start = Vector2d::Zero();
  Vector2d end = Vector2d::Zero();
  Vector2d centre = Vector2d::Zero();
};

struct Parsed {
  bool g17 = false;
  int arcs = 0;
  std::vector<Vector2d> ij;   // as written, program units
  std::vector<Block> circle;  // motion blocks from "(BOUNDARY PASS 1)" to the melt off after it
  std::vector<std::string> arc_lines;
};

// Reads X Y I J of G0-G3 blocks (absolute X Y, incremental I J), in program units times `mm_per_unit`.
Parsed parse(const std::string& program, double mm_per_unit) {
  Parsed out;
  Vector2d pos = Vector2d::Zero();
  bool in_circle = false;
  std::istringstream in(program);
  std::string line;
  while (std::getline(in, line)) {
    if (line.find("(BOUNDARY PASS 1)") != std::string::npos) in_circle = true;
    if (line.rfind("M24", 0) == 0) in_circle = false;
    std::string code;
    int depth = 0;
    for (const char ch : line) {
      if (ch == '(') ++depth;
      if (depth == 0) code += ch;
      if (ch == ')') --depth;
    }
    std::map<char, double> words;
    std::istringstream ws(code);
    std::string w;
    while (ws >> w)
      if (w.size() >= 2 && std::isalpha(static_cast<unsigned char>(w[0])))
        words[w[0]] = std::stod(w.substr(1));
    if (!words.count('G')) continue;
    const int g = static_cast<int>(words['G']);
    if (g == 17) out.g17 = true;
    if (g > 3) continue;
    Block b;
    b.g = g;
    b.start = pos;
    b.end = pos;
    if (words.count('X')) b.end.x() = words['X'] * mm_per_unit;
    if (words.count('Y')) b.end.y() = words['Y'] * mm_per_unit;
    if (g >= 2) {
      ++out.arcs;
      out.arc_lines.push_back(line);
      EXPECT_TRUE(words.count('X') && words.count('Y') && words.count('I') && words.count('J')) << line;
      out.ij.emplace_back(words['I'], words['J']);
      b.centre = pos + mm_per_unit * out.ij.back();
    }
    if (in_circle && g >= 1) out.circle.push_back(b);
    pos = b.end;
  }
  return out;
}

// Walks the written blocks along the toolpath's vertices: each block starts where the one before ended and
// ends on a vertex further along, arcs are equally far from their centre at both ends, and every vertex
// and segment midpoint a block replaces lies within `tol` (+ `slack` for the program's rounding) of it.
void expect_follows(const std::vector<Vector2d>& pts, const std::vector<Block>& blocks, double tol,
                    double slack) {
  std::size_t v = 0;
  for (const Block& b : blocks) {
    EXPECT_LE((b.start - pts[v]).norm(), slack);
    std::size_t w = v + 1;
    while (w < pts.size() && (pts[w] - b.end).norm() > slack) ++w;
    ASSERT_LT(w, pts.size()) << "a block ends off the toolpath, after vertex " << v;
    if (b.g >= 2) {
      EXPECT_NEAR((b.start - b.centre).norm(), (b.end - b.centre).norm(), 2 * slack);
    }
    const auto dist = [&](const Vector2d& q) {
      return b.g >= 2 ? distance_to_arc(q, b.start, b.end, b.centre, b.g == 2)
                      : distance_to_segment(q, b.start, b.end);
    };
    for (std::size_t k = v; k <= w; ++k) {
      EXPECT_LE(dist(pts[k]), tol + slack) << "vertex " << k;
      if (k < w) {
        EXPECT_LE(dist(0.5 * (pts[k] + pts[k + 1])), tol + slack) << "midpoint after " << k;
      }
    }
    v = w;
  }
  EXPECT_EQ(v, pts.size() - 1) << "the blocks end where the circle ends";
}

TEST(GcodeArcs, CircleIsWrittenAsArcsWithinTheTolerance) {
  const Toolpath tp = circle_toolpath();
  const std::vector<Vector2d> ring = circle(kCircleSegments, kRadius, kCentre);
  GcodeDialect d;
  d.arcs = true;
  GcodeOptions o;
  o.arc_tolerance_mm = {0.05};
  const std::string g = write_gcode(tp, d, {"T", "sc", "v", "m", "x"}, o);
  const Parsed p = parse(g, 1.0);
  EXPECT_TRUE(p.g17);
  EXPECT_GE(p.arcs, 2);
  EXPECT_LE(p.arcs, 4);
  EXPECT_EQ(p.circle.size(), static_cast<std::size_t>(p.arcs)) << g;
  for (const Block& b : p.circle) EXPECT_EQ(b.g, 3) << "counter-clockwise";
  expect_follows(ring, p.circle, 0.05, 0.002);
  ASSERT_FALSE(p.arc_lines.empty());
  EXPECT_NE(p.arc_lines.front().find(" F3000"), std::string::npos) << p.arc_lines.front();
  // The comments and codes are all still there; the straight fill stays four G1 blocks.
  for (const char* s :
       {"(LAYER 0 SECTION base Z 10", "(BOUNDARY PASS 1)",
        "(fill)\nG1 X50 F3000\nG1 X100\nG1 X150\nG1 X200\n", "M23 (melt on)", "M24 (melt off)", "M30"})
    EXPECT_NE(g.find(s), std::string::npos) << s << "\n" << g;

  // Without arcs in the dialect, or without a tolerance, the same toolpath is all straight moves.
  GcodeDialect plain;
  const std::string lines = write_gcode(tp, plain, {}, o);
  const Parsed pl = parse(lines, 1.0);
  EXPECT_FALSE(pl.g17);
  EXPECT_EQ(pl.arcs, 0);
  EXPECT_EQ(pl.circle.size(), static_cast<std::size_t>(kCircleSegments));
  expect_follows(ring, pl.circle, 0.0, 0.002);
  EXPECT_EQ(parse(write_gcode(tp, d, {}), 1.0).arcs, 0);
  GcodeOptions zero;
  zero.arc_tolerance_mm = {0.0};
  EXPECT_EQ(parse(write_gcode(tp, d, {}, zero), 1.0).arcs, 0);
}

TEST(GcodeArcs, InchProgramsGiveCentresInInches) {
  const Toolpath tp = circle_toolpath();
  const std::vector<Vector2d> ring = circle(kCircleSegments, kRadius, kCentre);
  GcodeDialect d;
  d.arcs = true;
  GcodeOptions o;
  o.arc_tolerance_mm = {0.05};
  const Parsed mm = parse(write_gcode(tp, d, {}, o), 1.0);
  d.inches = true;
  const std::string g = write_gcode(tp, d, {}, o);
  EXPECT_NE(g.find("G20"), std::string::npos);
  const Parsed in = parse(g, kMmPerInch);
  ASSERT_EQ(in.ij.size(), mm.ij.size());
  ASSERT_FALSE(in.ij.empty());
  for (std::size_t k = 0; k < in.ij.size(); ++k) {
    EXPECT_GT(mm.ij[k].norm(), 50.0);
    EXPECT_NEAR(in.ij[k].x() * kMmPerInch, mm.ij[k].x(), 0.03) << k;
    EXPECT_NEAR(in.ij[k].y() * kMmPerInch, mm.ij[k].y(), 0.03) << k;
  }
  // Three decimals of an inch round to 0.0127 mm: the path still follows the circle within that.
  expect_follows(ring, in.circle, 0.05, 0.03);
}

}  // namespace
}  // namespace beadtwin::gcode
