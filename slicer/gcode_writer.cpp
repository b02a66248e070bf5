#include "slicer/gcode_writer.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/units.hpp"

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
    const std::string f = num(feed_mm_s * 60.0);
    if (f != last_f_) {
      blk += " F" + f;
      last_f_ = f;
    }
    if (!comment.empty()) blk += fmt::format(" ({})", comment);
    line(blk);
  }

 private:
  const GcodeDialect& d_;
  double scale_;
  std::string out_;
  std::string last_[3];
  std::string last_f_;
};

}  // namespace

std::string write_gcode(const Toolpath& tp, const GcodeDialect& d, const GcodeHeader& h) {
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
  int layer = -1;
  Feature feature = Feature::kUnknown;
  int pass = -2;
  bool roller = false;
  for (const Move& m : tp.moves) {
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
    w.move(m.kind == MoveKind::kTravel ? "G0" : "G1", m.end, m.feed_mm_s);
  }
  w.line(d.melt_off);
  w.line("M30");
  w.line("%");
  return std::move(w.out());
}

}  // namespace beadtwin::slicer
