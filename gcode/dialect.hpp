// A machine's G-code dialect: the codes, units and number format its print programs use. The writer writes
// programs in it (gcode/writer.hpp); reader_options_for (gcode/reader_options.hpp) reads such a program back.
#pragma once

#include <string>

namespace beadtwin::gcode {

struct GcodeDialect {
  std::string name = "gantry";
  bool inches = false;           // G20 and inch coordinates/feeds, else G21 and mm
  std::string melt_on = "M23";   // extruder feed on (the M23/M24 convention of Fanuc macro print programs);
  std::string melt_off = "M24";  // extruder feed off; empty: a comment (desktop machines extrude by E)
  std::string heat_on = "";      // extruder heaters on (seed 002's M27), written at the program's start
  std::string heat_off = "";     // heaters off (M28), at its end
  std::string roller_down = "";  // optional code to engage the compression roller
  std::string roller_up = "";
  // Part-cooling fan (desktop printers) or air knife on, with its output in the S word (0 to fan_full:
  // M106 S0-255 in Marlin, Klipper and Prusa firmware; no S: full), and off.
  std::string fan_on = "M106";
  std::string fan_off = "M107";
  double fan_full = 255.0;
  // Codes that set the hot end's temperature, separated by spaces (M104 S215, M109 S215 or R215 in Marlin,
  // Klipper and Prusa firmware): read, never written. The reader takes their S as the bead's temperature;
  // empty: they are housekeeping and the beads are laid at the material's deposition_temp (a pellet
  // extruder whose bead is measured colder than its set point).
  std::string nozzle_temp = "M104 M109";
  int decimals = 3;
  // Fanuc macro program (seed 002): layers repeating one path are written once in a WHILE loop
  // (gcode/macro_loops.hpp).
  bool macro_loops = false;
  // Filament machines: E as the running total (M82, Marlin/RepRap absolute extrusion) instead of per move
  // (M83).
  bool absolute_e = false;
  bool arcs =
      false;  // the controller takes G2/G3 in the XY plane (G17) with I/J centre offsets from the start
  // Written only with an extruder (GcodeOptions::extruder):
  // Address of the pump or screw speed, rev/min: one of kSpeedWords (gcode/reader_options.hpp), the letters
  // the reader gives no other meaning; empty: never written.
  std::string rpm_word = "S";
  std::string prime_code = "";   // starts a prime (patent (51)); empty: a comment
  std::string reverse_on = "";   // pump or screw turns backwards (patent (52)); empty: a comment
  std::string reverse_off = "";  // it stops turning backwards; empty: a comment
  // A controller that runs G0 at its rapid traverse whatever the F word (CNC controllers: Fanuc, Siemens;
  // ISO 6983-1's positioning at rapid traverse) moves at this speed, mm/s; 0: G0 moves at the programmed
  // feed, as Marlin and RepRap firmware run it. Travel slower than the rapid traverse is written as G1.
  double rapid_feed_mm_s = 0.0;
};

}  // namespace beadtwin::gcode
