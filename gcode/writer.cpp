#include "gcode/writer.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <span>

#include <fmt/format.h>

#include "gcode/macro_loops.hpp"

#include "core/units.hpp"
#include "gcode/arc_fit.hpp"

namespace beadtwin::gcode {

std::string program_number(double value, int decimals) {
  std::string s = fmt::format("{:.{}f}", value, decimals);
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  return s == "-0" ? "0" : s;
}
namespace {

class Writer {
 public:
  Writer(const GcodeDialect& d) : d_(d), scale_(d.inches ? 1.0 / kMmPerInch : 1.0) {}

  std::string& out() { return out_; }

  void line(std::string_view text) {
    out_ += text;
    out_ += '\n';
  }

  std::string num(double mm) const { return program_number(mm * scale_, d_.decimals); }

  // True when the last blocks written put the head at `p` (as the program's numbers round it).
  bool at(const Eigen::Vector3d& p) const {
    for (int a = 0; a < 3; ++a)
      if (last_[a] != num(p[a])) return false;
    return true;
  }

  // Modal move: only axes that changed, F only when it changed, then `words` (extruder words). Returns false
  // (and writes nothing) when no axis changes as the program rounds it.
  bool move(const char* code, const Eigen::Vector3d& to, double feed_mm_s, std::string_view words = {}) {
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
    if (!any) return false;
    feed(blk, feed_mm_s);
    blk += words;
    line(blk);
    return true;
  }

  // A block that moves no axis (an extruder's feed in place): `words`, then F when it changed.
  void in_place(std::string_view code, std::string_view words, double feed_mm_s, std::string_view comment) {
    std::string blk(code);
    blk += words;
    feed(blk, feed_mm_s);
    blk += fmt::format(" ({})", comment);
    line(blk);
  }

  // A number as written, back in mm.
  double parse_mm(const std::string& s) const {
    double v = 0.0;
    std::from_chars(s.data(), s.data() + s.size(), v);
    return v / scale_;
  }

  // Arc in the XY plane from the current position (which must be set) to `to` about `centre`. X and Y are
  // always written; I and J are taken from the start as written, so the centre the controller computes is
  // off by at most half a unit of the last decimal.
  void arc(bool clockwise, const Eigen::Vector2d& to, const Eigen::Vector2d& centre, double feed_mm_s,
           std::string_view words = {}) {
    const Eigen::Vector2d from(written_mm(0), written_mm(1));
    std::string blk = clockwise ? "G2" : "G3";
    for (int a = 0; a < 2; ++a) {
      last_[a] = num(to[a]);
      blk += fmt::format(" {}{}", "XY"[a], last_[a]);
    }
    blk += fmt::format(" I{} J{}", num(centre.x() - from.x()), num(centre.y() - from.y()));
    feed(blk, feed_mm_s);
    blk += words;
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
  double written_mm(int axis) const { return parse_mm(last_[axis]); }

  const GcodeDialect& d_;
  double scale_;
  std::string out_;
  std::string last_[3];
  std::string last_f_;
};

bool is_event(const Move& m, ExtruderEvent e) {
  return m.kind == MoveKind::kDwell && m.event == e;
}

// A dwell's P word: whole milliseconds, which Fanuc (G04 P, no decimal point) and Marlin/RepRap (G4 P)
// both read.
long dwell_ms(double seconds) {
  return std::lround(seconds * 1000.0);
}

std::string code_or_comment(const std::string& code, std::string_view what) {
  return code.empty() ? fmt::format("({})", what) : fmt::format("{} ({})", code, what);
}

// What the program tells the extruder (GcodeOptions::extruder set): the pump or screw speed, or the
// filament lengths; prime and reverse.
class ExtruderWords {
 public:
  // The words of one block, applied by commit() once the block is written.
  struct Words {
    std::string text;
    std::string rpm;          // speed word value after the block
    double e_exact_mm = 0;    // exact filament total after the block
    double e_written_mm = 0;  // filament total as written after the block
  };

  ExtruderWords(Writer& w, const GcodeDialect& d, const GcodeOptions& o)
      : w_(w), d_(d), o_(o), e_(*o.extruder) {}

  void header() const {
    if (!filament()) return;
    if (d_.absolute_e) {
      w_.line("M82 (absolute extrusion)");
      w_.line("G92 E0");
    } else {
      w_.line("M83 (relative extrusion)");
    }
  }

  // Writes the dwell moves[i] when it is an extruder event written the extruder's way; false otherwise.
  bool dwell(const std::vector<Move>& moves, std::size_t i) {
    const Move& m = moves[i];
    end_reverse();
    switch (m.event) {
      case ExtruderEvent::kMeltOn:
        melt_on(moves, i);
        return true;
      case ExtruderEvent::kMeltOff:
        rpm_.clear();
        w_.line(code_or_comment(d_.melt_off, "melt off"));
        return true;
      case ExtruderEvent::kPrime:
        prime(m);
        return true;
      case ExtruderEvent::kReverse:
        reverse(m);
        return true;
      default:
        return false;
    }
  }

  // A reverse that goes on while the head moves on ends before the next print move that is not a coast.
  void before_move(const Move& m) {
    if (m.kind == MoveKind::kPrint && m.feature != Feature::kCoast) end_reverse();
  }

  // Words for a block of print move `m` (or of a run sharing its flow) laying `volume_mm3`: the speed word
  // when the speed changes, the E length on a filament machine. Coast moves get none: the pump is off.
  Words words(const Move& m, double volume_mm3) const {
    Words x{{}, rpm_, e_exact_mm_, e_written_mm_};
    if (m.kind != MoveKind::kPrint || m.feature == Feature::kCoast || !m.deposits()) return x;
    if (speed_words()) {
      const std::string rpm = program_number(rpm_for_flow(e_, commanded_flow_mm3_s(m)), kRpmDecimals);
      if (rpm != rpm_) x.text += fmt::format(" {}{}", d_.rpm_word, rpm);
      x.rpm = rpm;
    }
    if (filament()) x.text += " E" + filament_word(x, volume_mm3 / filament_area_mm2(e_));
    return x;
  }

  // After a block: its words count only when it was written; its filament is carried on when it was not.
  void commit(const Words& x, bool written) {
    e_exact_mm_ = x.e_exact_mm;
    if (!written) return;
    rpm_ = x.rpm;
    e_written_mm_ = x.e_written_mm;
  }

  void end_reverse() {
    if (!reversing_) return;
    reversing_ = false;
    w_.line(code_or_comment(d_.reverse_off, "reverse off"));
  }

 private:
  static constexpr int kRpmDecimals = 1;

  bool filament() const { return e_.kind == ExtruderKind::kFilament; }
  bool speed_words() const { return !filament() && e_.has_rpm() && !d_.rpm_word.empty(); }

  const MeltSettings& settings(const Move& m) const {
    static const MeltSettings kDefaults;
    if (m.section < 0 || static_cast<std::size_t>(m.section) >= o_.melt.size()) return kDefaults;
    return o_.melt[static_cast<std::size_t>(m.section)];
  }

  // The filament word for `length_mm` more: relative, and rounded so that the written total stays within
  // half a unit of the last decimal of the exact total.
  std::string filament_word(Words& x, double length_mm) const {
    x.e_exact_mm += length_mm;
    if (d_.absolute_e) {
      // The total so far, as written.
      const std::string e = w_.num(x.e_exact_mm);
      x.e_written_mm = w_.parse_mm(e);
      return e;
    }
    const std::string e = w_.num(x.e_exact_mm - x.e_written_mm);
    x.e_written_mm += w_.parse_mm(e);
    return e;
  }

  // Filament `length_mm` fed (or, negative, drawn back) with the head standing, over `duration_s`.
  void filament_in_place(double length_mm, double duration_s, std::string_view what) {
    Words x{{}, rpm_, e_exact_mm_, e_written_mm_};
    const std::string e = filament_word(x, length_mm);
    w_.in_place("G1", " E" + e, std::abs(length_mm) / duration_s, what);
    commit(x, true);
  }

  // The flow the pump starts at: the prime's (unless the controller sets it), else the bead's first.
  double flow_at_melt_on(const std::vector<Move>& moves, std::size_t i) const {
    for (std::size_t j = i + 1; j < moves.size(); ++j) {
      const Move& m = moves[j];
      if (is_event(m, ExtruderEvent::kMeltOff) || is_event(m, ExtruderEvent::kMeltOn)) break;
      if (is_event(m, ExtruderEvent::kPrime)) {
        if (!settings(m).set_at_control && m.deposits() && m.duration_s > 0) return commanded_flow_mm3_s(m);
        continue;
      }
      if (m.kind == MoveKind::kPrint && m.feature != Feature::kCoast && m.deposits())
        return commanded_flow_mm3_s(m);
    }
    return 0.0;
  }

  void melt_on(const std::vector<Move>& moves, std::size_t i) {
    if (d_.melt_on.empty()) {
      w_.line("(melt on)");
      return;
    }
    std::string blk = d_.melt_on;
    const double flow = speed_words() ? flow_at_melt_on(moves, i) : 0.0;
    if (flow > 0) {
      rpm_ = program_number(rpm_for_flow(e_, flow), kRpmDecimals);
      blk += fmt::format(" {}{}", d_.rpm_word, rpm_);
    }
    w_.line(blk + " (melt on)");
  }

  void prime(const Move& m) {
    if (settings(m).set_at_control) {
      w_.line(code_or_comment(d_.prime_code, "prime, set at control"));
      return;
    }
    if (!d_.prime_code.empty()) w_.line(fmt::format("{} (prime)", d_.prime_code));
    if (m.duration_s <= 0) return;
    if (filament() && m.deposits()) {
      filament_in_place(m.volume_mm3 / filament_area_mm2(e_), m.duration_s, "prime");
      return;
    }
    if (speed_words() && m.deposits()) {
      const std::string rpm = program_number(rpm_for_flow(e_, commanded_flow_mm3_s(m)), kRpmDecimals);
      if (rpm != rpm_) w_.line(d_.rpm_word + rpm);
      rpm_ = rpm;
    }
    w_.line(fmt::format("G4 P{} (prime)", dwell_ms(m.duration_s)));
  }

  void reverse(const Move& m) {
    const MeltSettings& s = settings(m);
    if (s.set_at_control) {
      w_.line(code_or_comment(d_.reverse_on, "reverse, set at control"));
      return;
    }
    const bool speed = speed_words() && s.reverse_rpm > 0;
    const std::string rpm = program_number(s.reverse_rpm, kRpmDecimals);
    if (d_.reverse_on.empty())
      w_.line(speed ? fmt::format("(reverse at {} rpm)", rpm) : std::string("(reverse)"));
    else
      w_.line(speed ? fmt::format("{} {}{} (reverse)", d_.reverse_on, d_.rpm_word, rpm)
                    : fmt::format("{} (reverse)", d_.reverse_on));
    rpm_.clear();  // the next melt on sets the speed again
    if (m.duration_s <= 0) {
      reversing_ = true;  // on while the head moves on
      return;
    }
    const double drawn_mm3 = e_.has_rpm() ? flow_for_rpm(e_, s.reverse_rpm) * m.duration_s : 0.0;
    if (filament() && drawn_mm3 > 0)
      filament_in_place(-drawn_mm3 / filament_area_mm2(e_), m.duration_s, "reverse");
    else
      w_.line(fmt::format("G4 P{} (reverse)", dwell_ms(m.duration_s)));
    w_.line(code_or_comment(d_.reverse_off, "reverse off"));
  }

  Writer& w_;
  const GcodeDialect& d_;
  const GcodeOptions& o_;
  const Extruder& e_;
  std::string rpm_;  // speed word value in force; empty: unknown (pump off)
  double e_exact_mm_ = 0.0;
  double e_written_mm_ = 0.0;
  bool reversing_ = false;
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

// A run of print moves as fitted arcs and lines; lines are the original moves, written as before. A
// piece's extruder words carry the material of the moves it replaces.
void write_run(Writer& w, std::span<const Move> run, double tolerance_mm, ExtruderWords* x) {
  std::vector<Eigen::Vector2d> points;
  points.reserve(run.size() + 1);
  points.push_back(run.front().start.head<2>());
  for (const Move& m : run) points.push_back(m.end.head<2>());
  std::size_t first = 0;  // first move of the piece
  for (const PathPiece& p : fit_arcs(points, tolerance_mm)) {
    const Move& m = run[p.last_point - 1];
    double volume = 0.0;
    for (std::size_t k = first; k < p.last_point; ++k) volume += run[k].volume_mm3;
    first = p.last_point;
    const ExtruderWords::Words words = x ? x->words(m, volume) : ExtruderWords::Words{};
    bool written = true;
    if (p.is_arc())
      w.arc(p.kind == PieceKind::kArcCw, p.end, p.centre, m.feed_mm_s, words.text);
    else
      written = w.move("G1", m.end, m.feed_mm_s, words.text);
    if (x) x->commit(words, written);
  }
}

// The motion code of a move: G0 for travel, unless the controller's G0 runs at its rapid traverse and the
// move asks for less (then G1, which keeps the feed).
const char* motion_code(const GcodeDialect& d, const Move& m) {
  if (m.kind != MoveKind::kTravel) return "G1";
  return d.rapid_feed_mm_s > 0.0 && m.feed_mm_s < d.rapid_feed_mm_s * (1.0 - 1e-9) ? "G1" : "G0";
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
  // Heaters on for the program and off at its end (seed 002's M27/M28), unless the toolpath switches them.
  const bool heat_events = std::any_of(tp.moves.begin(), tp.moves.end(), [](const Move& m) {
    return m.event == ExtruderEvent::kHeatOn || m.event == ExtruderEvent::kHeatOff;
  });
  if (!d.heat_on.empty() && !heat_events) w.line(d.heat_on + " (heaters on)");
  if (d.arcs) w.line("G17 (XY plane for arcs)");
  std::optional<ExtruderWords> x;
  if (o.extruder) {
    x.emplace(w, d, o);
    x->header();
  }
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
      if (x && x->dwell(tp.moves, i)) {
        ++i;
        continue;
      }
      if (m.event == ExtruderEvent::kMeltOn)
        w.line(code_or_comment(d.melt_on, "melt on"));
      else if (m.event == ExtruderEvent::kMeltOff)
        w.line(code_or_comment(d.melt_off, "melt off"));
      else if (m.event == ExtruderEvent::kHeatOn)
        w.line(code_or_comment(d.heat_on, "heaters on"));
      else if (m.event == ExtruderEvent::kHeatOff)
        w.line(code_or_comment(d.heat_off, "heaters off"));
      else if (m.duration_s > 0)
        w.line(fmt::format("G4 P{} ({})", dwell_ms(m.duration_s), to_string(m.event)));
      ++i;
      continue;
    }
    if (x) x->before_move(m);
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
      write_run(w, std::span<const Move>(tp.moves).subspan(i, end - i), tolerance, x ? &*x : nullptr);
      i = end;
    } else if (x) {
      const ExtruderWords::Words words = x->words(m, m.volume_mm3);
      x->commit(words, w.move(motion_code(d, m), m.end, m.feed_mm_s, words.text));
      ++i;
    } else {
      w.move(motion_code(d, m), m.end, m.feed_mm_s);
      ++i;
    }
  }
  if (x) x->end_reverse();
  w.line(d.melt_off.empty() ? "(end of program)" : fmt::format("{} (end of program)", d.melt_off));
  if (!d.heat_off.empty() && !heat_events) w.line(d.heat_off + " (heaters off)");
  w.line("M30");
  w.line("%");
  if (d.macro_loops) return loop_repeated_layers(w.out());
  return std::move(w.out());
}

}  // namespace beadtwin::gcode
