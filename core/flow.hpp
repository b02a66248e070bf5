// Flow to extruder commands: how much material a bead takes per second, and what the extruder must do to
// deliver it (docs/physics.md, bead cross-section).
//
// A bead of width w and height h laid at speed v takes Q = A(w, h) v, with A the flattened stadium section
// of core/bead.hpp. A gear pump or screw delivers a fixed displacement per revolution, so its speed is
// RPM = 60 Q / D. A filament extruder feeds a filament of diameter d_f at v_e, delivering Q = π d_f² v_e / 4
// (Negrău, Pancu and Grebenișan 2023, eq. 1); the E length per mm of path follows from equating it with Q = A
// v_x (eq. 3). The section there is a central rectangle of width b_p between two half circles of diameter h,
// A = π h² / 4 + b_p h: the same stadium as core/bead.hpp with b_p = w − h.
//
// Limits are checked, never applied: flow_excess and worst_flow_excess report how far a demand is above
// the extruder's maximum flow or RPM, and the caller decides what to do.
#pragma once

#include <cstdint>
#include <string_view>

#include "core/enum_names.hpp"
#include "core/toolpath.hpp"

namespace beadtwin {

enum class ExtruderKind : std::uint8_t {
  kGearPump,  // melt pump: displacement per revolution of the gears
  kScrew,     // extruder screw: displacement per revolution of the screw
  kFilament,  // filament drive (E words, eq. 1)
};

inline constexpr EnumName<ExtruderKind> kExtruderKindNames[] = {{ExtruderKind::kGearPump, "gear_pump"},
                                                                {ExtruderKind::kScrew, "screw"},
                                                                {ExtruderKind::kFilament, "filament"}};
constexpr std::span<const EnumName<ExtruderKind>> enum_names(ExtruderKind) {
  return kExtruderKindNames;
}
// The kind's name in machine files and messages: gear_pump, screw or filament.
inline std::string_view to_string(ExtruderKind kind) {
  return name_of(kind);
}

// What the machine's extruder can do. Inputs give the displacement in cm³/rev; it is kept in mm³/rev
// (1 cm³ = 1000 mm³) inside.
struct Extruder {
  ExtruderKind kind = ExtruderKind::kGearPump;
  // Material delivered per revolution, mm³/rev. Required for a gear pump or screw; for a filament drive
  // optional (the filament one turn of the drive gear feeds): without it a filament extruder has no RPM.
  double displacement_mm3_per_rev = 0.0;
  double filament_diameter_mm = 0.0;  // d_f of eqs. 1 and 3; required for kFilament only
  double max_rpm = 0.0;               // highest pump, screw or drive speed, rev/min; 0: no limit
  double max_flow_mm3_s = 0.0;        // highest volumetric flow the extruder melts, mm³/s; 0: no limit
  // A filament drive that the program can only switch on and off (melt on / melt off codes, no E words)
  // feeds its filament at this constant v_e, mm/s: Q = π d_f² v_e / 4 while the melt is on, and the head's
  // feed sets the bead, A = Q / v (seed 002 eqs. 1, 12, Table 1). 0: no such drive. kFilament only.
  double constant_feed_mm_s = 0.0;

  bool has_rpm() const { return displacement_mm3_per_rev > 0.0; }
  bool has_constant_feed() const { return constant_feed_mm_s > 0.0; }
  // Whether programs carry its commands: speed words for a pump or screw of known displacement, E words for
  // a filament drive.
  bool has_commands() const { return has_rpm() || kind == ExtruderKind::kFilament; }
};

// Throws InputError (key "extruder") naming every problem found: a gear pump or screw without a positive
// displacement, a filament extruder without a positive filament diameter, negative limits, a constant feed
// that is negative or belongs to a pump or screw.
void validate(const Extruder& extruder);

// Q = A(w, h) v, mm³/s, for a bead of width w and height h (mm) laid at v (mm/s). Precondition: 0 < h <= w.
double bead_flow_mm3_s(double width_mm, double height_mm, double speed_mm_s);

// Pump, screw or drive speed (rev/min) that delivers `flow_mm3_s`, and its inverse. Precondition:
// extruder.has_rpm().
double rpm_for_flow(const Extruder& extruder, double flow_mm3_s);
double flow_for_rpm(const Extruder& extruder, double rpm);

// Filament section π d_f² / 4, mm². Precondition: kind kFilament with a positive diameter.
double filament_area_mm2(const Extruder& extruder);
// Filament feed v_e (mm/s) that delivers `flow_mm3_s` (eq. 1 solved for v_e), and its inverse (eq. 1).
double filament_feed_mm_s(const Extruder& extruder, double flow_mm3_s);
double flow_for_filament_feed(const Extruder& extruder, double filament_feed_mm_s);
// Filament length per mm of path, v_e / v_x, for a bead of width w and height h (eq. 3 with b_p = w − h);
// the E word of a move is this times its length. Precondition: 0 < h <= w.
double e_per_mm(const Extruder& extruder, double width_mm, double height_mm);
// The width of the bead laid at `e_per_mm` filament per mm of path and height h (inverse of e_per_mm).
double bead_width_for_e_per_mm(const Extruder& extruder, double e_per_mm, double height_mm);

// Path speed v_x (mm/s) at which a constant flow Q lays a bead of height h whose central rectangle is
// b_p wide (eq. 2 solved for v_x): v_x = Q / (π h² / 4 + b_p h). As the height grows along a layer of
// varying thickness, h = h0 + m x, the speed drops and the flow stays constant. Preconditions: h > 0,
// b_p >= 0.
double speed_for_height(double flow_mm3_s, double central_width_mm, double height_mm);
// The same for a filament fed at the constant v_e (eq. 12):
// v_x = π d_f² v_e / (4 h (π h / 4 + b_p)).
double speed_for_height(const Extruder& filament, double filament_feed_mm_s, double central_width_mm,
                        double height_mm);

// How far a demand is above the extruder's limits.
struct FlowExcess {
  // The larger of flow / max_flow and RPM / max_RPM (limits of 0 are left out); above 1: exceeded.
  double ratio = 0.0;
  double flow_mm3_s = 0.0;   // the flow demanded
  double rpm = 0.0;          // the speed it takes (0 when the extruder has no RPM)
  std::string_view limit;    // "max_flow" or "max_rpm": the limit `ratio` is taken against; empty: none
  std::ptrdiff_t move = -1;  // index into Toolpath::moves (worst_flow_excess); -1 otherwise

  bool exceeded() const { return ratio > 1.0; }
};

// How far a demand of `flow_mm3_s` (mm³/s) is above `extruder`'s limits.
FlowExcess flow_excess(const Extruder& extruder, double flow_mm3_s);

// The flow a move commands, mm³/s: a moving move's volume per length at its commanded feed (what the pump
// must deliver while the head cruises), a dwell's volume over its duration; 0 for moves without material.
double commanded_flow_mm3_s(const Move& move);

// The move with the largest excess over the extruder's limits (ratio 0 and move -1 when nothing flows or
// nothing is limited). Coast moves are left out: the pump is off, their material is what the nozzle's
// pressure pushes out.
FlowExcess worst_flow_excess(const Extruder& extruder, const Toolpath& toolpath);

}  // namespace beadtwin
