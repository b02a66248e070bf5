// The G-code reader's options (gcode/block_reader.hpp, gcode/program_reader.hpp): what a program's codes mean
// on the machine that runs it, the modes it starts in and the limits on bad input; their validation; and
// the options that read back a program written in a given dialect (gcode/dialect.hpp).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/flow.hpp"
#include "gcode/dialect.hpp"

namespace beadtwin::gcode {

// Firmware and controller housekeeping that changes nothing the Toolpath records (temperatures, fans,
// motors, acceleration limits, progress, bed levelling, work offset G54...): read silently.
std::vector<std::string> default_ignored_codes();

// The addresses a pump or screw speed may be written with (ReaderOptions::rpm_word, GcodeDialect::rpm_word):
// the letters the reader gives no other meaning. G, M, N, O and T are codes, program and line numbers and
// tools; X, Y, Z, A, B and C axes; E and F the filament and the feed; I, J, K, R and P an arc's centre,
// radius and turns (P also a dwell's time); D M200's filament diameter; L a subprogram call's repeats. S is
// also a dwell's time (G4 S) and M200's switch: in those blocks it is not the speed.
inline constexpr std::array<std::string_view, 6> kSpeedWords = {"H", "Q", "S", "U", "V", "W"};

// What a program's codes mean on the machine that runs it, and the modes it starts in. A code is a letter
// and a number, "M23" or "M862.3".
struct ReaderOptions {
  // Extruder feed on (add "M3" for spindle-style pumps). Empty: the pump runs whenever S > 0.
  std::vector<std::string> melt_on = {"M23"};
  std::vector<std::string> melt_off = {"M24"};  // extruder feed off (add "M5")
  std::vector<std::string> heat_on = {"M27"};   // extruder heaters on
  std::vector<std::string> heat_off = {"M28"};  // extruder heaters off
  std::vector<std::string> roller_down;         // compression roller engaged
  std::vector<std::string> roller_up;           // compression roller lifted
  // Part-cooling fan (or air knife) on, its output S from 0 to fan_full (no S: full; a P word other than 0 or
  // 1 names another fan, which is left alone), and off.
  std::vector<std::string> fan_on = {"M106"};
  std::vector<std::string> fan_off = {"M107"};
  double fan_full = 255.0;
  // The hot end's target temperature, S in °C (M109's R likewise): the bead's temperature as it leaves the
  // nozzle (Move::nozzle_c). A T word other than T0 names another tool's heater, which is left alone; S0
  // (heater off) changes nothing for the beads still to come.
  std::vector<std::string> nozzle_temp = {"M104", "M109"};
  // The roller is engaged from the start (until a roller-up code): a roller machine whose programs carry no
  // roller codes rolls every bead.
  bool roller_down_at_start = false;
  std::vector<std::string> prime;        // a prime starts (its time: the G4 after it)
  std::vector<std::string> reverse_on;   // the pump turns backwards (its S is the reverse speed)
  std::vector<std::string> reverse_off;  // it stops turning backwards
  // The address of the pump or screw speed (rev/min), one of kSpeedWords; empty: programs carry no speed
  // word, and an S is a dwell's time or M200's switch only.
  std::string rpm_word = "S";
  std::vector<std::string> ignored = default_ignored_codes();

  bool inches = false;                 // units before any G20/G21
  bool absolute_e = true;              // E mode before any M82/M83 (or G90/G91)
  bool dwell_p_seconds = false;        // G4 P in seconds (Fanuc-style programs, ours) instead of milliseconds
  bool block_delete = true;            // the block delete switch: blocks starting with `/` are skipped
  long max_macro_steps = 10'000'000;   // macro programs: statements run before an endless loop is an error
  double filament_diameter_mm = 1.75;  // E times π d²/4 is the volume fed, unless E is volumetric
  // A program that states its filament diameter (PrusaSlicer and Slic3r write `; filament_diameter = d` in
  // the settings at its end) is read with that diameter: its E words were computed for it.
  bool filament_diameter_from_program = true;
  bool volumetric_e = false;  // E is volume (mm³, in³ under G20) from the start

  // The pump or screw (kGearPump, kScrew): turns the S word (rev/min) into flow; or a filament drive, whose
  // constant feed (if any) is the flow between melt on and melt off where moves carry no E word. Without
  // one, a pump program's print moves lay the default bead, or nothing when there is none.
  std::optional<Extruder> extruder;
  bool refill_after_retract = true;    // E fed after a retraction refills the nozzle before material is laid
  double default_bead_width_mm = 0.0;  // the bead a print move of unknown flow lays (0: none)
  double default_layer_height_mm = 0.0;  // its height, also when a layer's own cannot be found (0: none)
  double default_feed_mm_s = 25.0;       // feed of moves before the first F
  double rapid_feed_mm_s = 0.0;          // feed of G0 moves; 0: the programmed F (as Marlin does)

  double chord_tolerance_mm = 0.01;    // arcs become chords within this distance of the circle
  double max_coordinate_mm = 1e5;      // 100 m: anything farther is not a coordinate of this machine
  std::size_t max_moves = 20'000'000;  // a program making more moves is refused
  std::size_t max_messages = 20;       // warning messages kept (all are counted)
};

// Throws InputError (key "reader", the message naming each option "reader.<option>" at fault) for every
// problem found: a code that is not a letter and a number, a speed word that is not one of kSpeedWords, a
// filament diameter, chord tolerance or feed that is not positive, negative defaults, an extruder that does
// not validate.
void validate(const ReaderOptions& options);

// The options that read back a program written by write_gcode with `dialect` and, if any, `extruder`:
// its heat, melt, roller, prime and reverse codes, its speed word, G4 P in milliseconds, its units and rapid
// feed, the extruder's filament or pump.
ReaderOptions reader_options_for(const GcodeDialect& dialect, const Extruder* extruder);

}  // namespace beadtwin::gcode
