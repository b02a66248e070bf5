#include "slicer/gcode_writer.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <span>

#include <fmt/format.h>

#include "core/units.hpp"
#include "slicer/arc_fit.hpp"

namespace beadtwin::slicer {
namespace {

class Writer {
 public:
  Writer(const GcodeDialect& d) : d_(d), scale_(d.inches ? 1.0 / kMmPerInch : 1.0) {}

  std::string& out() { return out_; }

  void line(std::string_view text) {
    out_ += text;
    out_ += '\n';
  }

  std::string num(double mm) const {
    std::string s = fmt::format("{:.{}f}", mm * scale_, d_.decimals);
    // Trim trailing zeros for readability ("12.500" -> "12.5", "3.000" -> "3").
    if (s.find('.') != std::string::npos) {
      while (s.back() == '0') s.pop_back();
      if (s.back() == '.') s.pop_back();
    }
    if (s == "-0") s = "0";
    return s;
  }

  // True when the last blocks written put the head at `p` (as the program's numbers round it).
  bool at(const Eigen::Vector3d& p) const {
    for (int a = 0; a < 3; ++a)
      if (last_[a] != num(p[a])) return false;
    return true;
  }

  // Modal move: only axes that changed, F only when it changed.
  void move(const char* code, const Eigen::Vector3d& to, double feed_mm_s, std::string_view comment = {}) {
    std::string blk = code;
    bool any = false;
    for (int a = 0; a < 3; ++a) {
      const std::string v = num(to[a]);
      if (v != last_[a]) {
        blk += fmt::format(" {}{}", "XYZ"[a], v);
        last_[a] = v;
        any = true;
      }
    }
    if (!any) return;
    feed(blk, feed_mm_s);
    if (!comment.empty()) blk += fmt::format(" ({})", comment);
    line(blk);
  }

  // Arc in the XY plane from the current position (which must be set) to `to` about `centre`. X and Y are
  // always written; I and J are taken from the start as written, so the centre the controller computes is
  // off by at most half a unit of the last decimal.
  void arc(bool clockwise, const Eigen::Vector2d& to, const Eigen::Vector2d& centre, double feed_mm_s) {
    const Eigen::Vector2d from(written_mm(0), written_mm(1));
    std::string blk = clockwise ? "G2" : "G3";
    for (int a = 0; a < 2; ++a) {
      last_[a] = num(to[a]);
      blk += fmt::format(" {}{}", "XY"[a], last_[a]);
    }
    blk += fmt::format(" I{} J{}", num(centre.x() - from.x()), num(centre.y() - from.y()));
    feed(blk, feed_mm_s);
    line(blk);
  }

 private:
  void feed(std::string& blk, double feed_mm_s) {
    const std::string f = num(feed_mm_s * 60.0);
    if (f != last_f_) {
      blk += " F" + f;
      last_f_ = f;
    }
  }

  // The last value written on an axis, back in mm.
  double written_mm(int axis) const {
    const std::string& s = last_[axis];
    double v = 0.0;
    std::from_chars(s.data(), s.data() + s.size(), v);
    return v / scale_;
  }

  const GcodeDialect& d_;
  double scale_;
  std::string out_;
  std::string last_[3];
  std::string last_f_;
};

bool near(double a, double b, double rel) {
  return std::abs(a - b) <= rel * std::max(std::abs(a), std::abs(b));
}

// Whether print move `b` may share an arc run with the print move `a` just before it.
bool continues_run(const Move& a, const Move& b) {
  constexpr double kSamePoint = 1e-9;  // mm
  if (b.kind != MoveKind::kPrint || (b.start - a.end).norm() > kSamePoint) return false;
  if (std::abs(b.end.z() - a.end.z()) > kSamePoint || std::abs(b.start.z() - b.end.z()) > kSamePoint)
    return false;
  if (b.section != a.section || b.layer != a.layer || b.feature != a.feature || b.pass != a.pass)
    return false;
  if (b.roller_down != a.roller_down || b.feed_mm_s != a.feed_mm_s || b.bead_width_mm != a.bead_width_mm)
    return false;
  const double la = a.length_mm();
  const double lb = b.length_mm();
  return la > 0.0 && lb > 0.0 && near(a.volume_mm3 / la, b.volume_mm3 / lb, 1e-6);
}

// End (exclusive) of the arc run starting at print move `first`.
std::size_t run_end(const std::vector<Move>& moves, std::size_t first) {
  const Move& m = moves[first];
  if (m.kind != MoveKind::kPrint || std::abs(m.start.z() - m.end.z()) > 1e-9 || !(m.length_mm() > 0.0))
    return first + 1;
  std::size_t end = first + 1;
  while (end < moves.size() && continues_run(moves[end - 1], moves[end])) ++end;
  return end;
}

// A run of print moves as fitted arcs and lines; lines are the original moves, written as before.
void write_run(Writer& w, std::span<const Move> run, double tolerance_mm) {
  std::vector<Eigen::Vector2d> points;
  points.reserve(run.size() + 1);
  points.push_back(run.front().start.head<2>());
  for (const Move& m : run) points.push_back(m.end.head<2>());
  for (const PathPiece& p : fit_arcs(points, tolerance_mm)) {
    const Move& m = run[p.last_point - 1];
    if (p.is_arc())
      w.arc(p.kind == PieceKind::kArcCw, p.end, p.centre, m.feed_mm_s);
    else
      w.move("G1", m.end, m.feed_mm_s);
  }
}

double arc_tolerance_mm(const GcodeDialect& d, const GcodeOptions& o, const Move& m) {
  if (!d.arcs || m.section < 0 || static_cast<std::size_t>(m.section) >= o.arc_tolerance_mm.size())
    return 0.0;
  return o.arc_tolerance_mm[static_cast<std::size_t>(m.section)];
}

}  // namespace

std::string write_gcode(const Toolpath& tp, const GcodeDialect& d, const GcodeHeader& h,
                        const GcodeOptions& o) {
  Writer w(d);
  w.line(fmt::format("%"));
  w.line(fmt::format("O1000 ({})", h.program_name.empty() ? "BEADTWIN" : h.program_name));
  w.line(fmt::format("(beadtwin {} print program, dialect {})", BEADTWIN_VERSION, d.name));
  if (!h.scenario.empty()) w.line(fmt::format("(scenario: {}, variant: {})", h.scenario, h.variant));
  if (!h.machine.empty()) w.line(fmt::format("(machine: {}, material: {})", h.machine, h.material));
  w.line(fmt::format("(layers: {}, print time: {:.0f} s, commanded volume: {:.0f} cm3)", tp.layers.size(),
                     tp.total_time_s(), tp.commanded_volume_mm3() / 1000.0));
  w.line(d.inches ? "G20 (inch)" : "G21 (mm)");
  w.line("G90 (absolute)");
  if (d.arcs) w.line("G17 (XY plane for arcs)");
  int layer = -1;
  Feature feature = Feature::kUnknown;
  int pass = -2;
  bool roller = false;
  for (std::size_t i = 0; i < tp.moves.size();) {
    const Move& m = tp.moves[i];
    if (m.layer != layer && m.layer >= 0) {
      layer = m.layer;
      const ToolpathLayer& l = tp.layers[static_cast<std::size_t>(layer)];
      const std::string& section =
          l.section >= 0 ? tp.sections[static_cast<std::size_t>(l.section)] : std::string("-");
      w.line(fmt::format("(LAYER {} SECTION {} Z {} HEIGHT {} TIME {:.1f} S)", layer, section, w.num(l.z_mm),
                         w.num(l.height_mm), l.duration_s()));
      feature = Feature::kUnknown;
      pass = -2;
    }
    if (m.kind == MoveKind::kDwell) {
      if (m.event == ExtruderEvent::kMeltOn)
        w.line(fmt::format("{} (melt on)", d.melt_on));
      else if (m.event == ExtruderEvent::kMeltOff)
        w.line(fmt::format("{} (melt off)", d.melt_off));
      else if (m.duration_s > 0)
        w.line(fmt::format("G4 P{:.3f} ({})", m.duration_s, to_string(m.event)));
      ++i;
      continue;
    }
    if (m.kind == MoveKind::kPrint && (m.feature != feature || m.pass != pass)) {
      feature = m.feature;
      pass = m.pass;
      if (m.feature == Feature::kBoundary)
        w.line(fmt::format("(BOUNDARY PASS {})", m.pass + 1));
      else
        w.line(fmt::format("({})", to_string(m.feature)));
    }
    if (m.kind == MoveKind::kPrint && m.roller_down != roller && !d.roller_down.empty()) {
      w.line(m.roller_down ? d.roller_down : d.roller_up);
      roller = m.roller_down;
    }
    // A run shares layer, feature, pass and roller state, so the comments and codes above cover all of it.
    const double tolerance = arc_tolerance_mm(d, o, m);
    const std::size_t end = tolerance > 0.0 && w.at(m.start) ? run_end(tp.moves, i) : i + 1;
    if (end - i >= 3) {
      write_run(w, std::span<const Move>(tp.moves).subspan(i, end - i), tolerance);
      i = end;
    } else {
      w.move(m.kind == MoveKind::kTravel ? "G0" : "G1", m.end, m.feed_mm_s);
      ++i;
    }
  }
  w.line(d.melt_off);
  w.line("M30");
  w.line("%");
  return std::move(w.out());
}

}  // namespace beadtwin::slicer
