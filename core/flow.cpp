#include "core/flow.hpp"

#include <fmt/format.h>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/units.hpp"

namespace beadtwin {

void validate(const Extruder& e) {
  std::string problems;
  const auto problem = [&](const std::string& text) { problems += (problems.empty() ? "" : "; ") + text; };
  if (e.kind != ExtruderKind::kFilament && !(e.displacement_mm3_per_rev > 0))
    problem(fmt::format("displacement of a {} must be positive, got {} mm3/rev", to_string(e.kind),
                        e.displacement_mm3_per_rev));
  if (e.kind == ExtruderKind::kFilament && !(e.filament_diameter_mm > 0))
    problem(fmt::format("filament diameter must be positive, got {} mm", e.filament_diameter_mm));
  if (!(e.displacement_mm3_per_rev >= 0))
    problem(fmt::format("displacement must not be negative, got {} mm3/rev", e.displacement_mm3_per_rev));
  if (!(e.max_rpm >= 0)) problem(fmt::format("max RPM must not be negative, got {}", e.max_rpm));
  if (!(e.max_flow_mm3_s >= 0))
    problem(fmt::format("max flow must not be negative, got {} mm3/s", e.max_flow_mm3_s));
  if (!(e.constant_feed_mm_s >= 0))
    problem(fmt::format("constant filament feed must not be negative, got {} mm/s", e.constant_feed_mm_s));
  if (e.constant_feed_mm_s > 0 && e.kind != ExtruderKind::kFilament)
    problem(fmt::format("a constant filament feed needs a filament extruder, not a {}", to_string(e.kind)));
  if (!problems.empty()) throw InputError({}, "extruder", problems);
}

double bead_flow_mm3_s(double width_mm, double height_mm, double speed_mm_s) {
  return bead_area_mm2(width_mm, height_mm) * speed_mm_s;
}

double rpm_for_flow(const Extruder& e, double flow_mm3_s) {
  BT_CHECK_OP(e.displacement_mm3_per_rev, >, 0.0);
  return 60.0 * flow_mm3_s / e.displacement_mm3_per_rev;
}

double flow_for_rpm(const Extruder& e, double rpm) {
  BT_CHECK_OP(e.displacement_mm3_per_rev, >, 0.0);
  return e.displacement_mm3_per_rev * rpm / 60.0;
}

double filament_area_mm2(const Extruder& e) {
  BT_CHECK(e.kind == ExtruderKind::kFilament);
  BT_CHECK_OP(e.filament_diameter_mm, >, 0.0);
  return kPi * e.filament_diameter_mm * e.filament_diameter_mm / 4.0;
}

double filament_feed_mm_s(const Extruder& e, double flow_mm3_s) {
  return flow_mm3_s / filament_area_mm2(e);
}

double flow_for_filament_feed(const Extruder& e, double filament_feed_mm_s) {
  return filament_area_mm2(e) * filament_feed_mm_s;
}

double e_per_mm(const Extruder& e, double width_mm, double height_mm) {
  return bead_area_mm2(width_mm, height_mm) / filament_area_mm2(e);
}

double bead_width_for_e_per_mm(const Extruder& e, double e_per_mm, double height_mm) {
  return bead_width_mm(e_per_mm * filament_area_mm2(e), height_mm);
}

double speed_for_height(double flow_mm3_s, double central_width_mm, double height_mm) {
  BT_CHECK_OP(height_mm, >, 0.0);
  BT_CHECK_OP(central_width_mm, >=, 0.0);
  return flow_mm3_s / (kPi * height_mm * height_mm / 4.0 + central_width_mm * height_mm);
}

double speed_for_height(const Extruder& filament, double filament_feed_mm_s, double central_width_mm,
                        double height_mm) {
  return speed_for_height(flow_for_filament_feed(filament, filament_feed_mm_s), central_width_mm, height_mm);
}

FlowExcess flow_excess(const Extruder& e, double flow_mm3_s) {
  FlowExcess x;
  x.flow_mm3_s = flow_mm3_s;
  if (e.has_rpm()) x.rpm = rpm_for_flow(e, flow_mm3_s);
  if (e.max_flow_mm3_s > 0) {
    x.ratio = flow_mm3_s / e.max_flow_mm3_s;
    x.limit = "max_flow";
  }
  if (e.max_rpm > 0 && e.has_rpm() && x.rpm / e.max_rpm > x.ratio) {
    x.ratio = x.rpm / e.max_rpm;
    x.limit = "max_rpm";
  }
  return x;
}

double commanded_flow_mm3_s(const Move& m) {
  if (!m.deposits()) return 0.0;
  if (m.kind == MoveKind::kDwell) return m.duration_s > 0 ? m.volume_mm3 / m.duration_s : 0.0;
  const double length = m.length_mm();
  return length > 0 ? m.volume_mm3 / length * m.feed_mm_s : 0.0;
}

FlowExcess worst_flow_excess(const Extruder& e, const Toolpath& tp) {
  FlowExcess worst;
  for (std::size_t i = 0; i < tp.moves.size(); ++i) {
    const Move& m = tp.moves[i];
    if (m.feature == Feature::kCoast || !m.deposits()) continue;
    FlowExcess x = flow_excess(e, commanded_flow_mm3_s(m));
    if (x.ratio > worst.ratio) {
      x.move = static_cast<std::ptrdiff_t>(i);
      worst = x;
    }
  }
  return worst;
}

}  // namespace beadtwin
