// Print programs from a Toolpath: readable G-code for a roller gantry machine, with comments naming the
// section, layer and feature of every block.
#pragma once

#include <string>
#include <vector>

#include "core/flow.hpp"
#include "core/melt_settings.hpp"
#include "core/toolpath.hpp"
#include "gcode/dialect.hpp"

namespace beadtwin::gcode {

// What the program's opening comments name: the scenario with its variant, the machine with its material
// (an empty scenario or machine leaves that line out).
struct GcodeHeader {
  std::string program_name;  // in the O line; empty: BEADTWIN
  std::string scenario;
  std::string variant;
  std::string machine;
  std::string material;
};

// Choices for one program that belong neither to the machine's dialect nor to the header comments.
struct GcodeOptions {
  // Arc chord tolerance per section (indexed by Move::section), mm; patent paragraph (45). With
  // GcodeDialect::arcs, runs of print moves are written as G2/G3 arcs that stay within this distance of the
  // moves (gcode/arc_fit.hpp). A missing entry, 0 or a dialect without arcs writes straight moves only.
  std::vector<double> arc_tolerance_mm;
  // The machine's extruder. Without it (nullptr) the program carries no extruder words: melt events are the
  // dialect's codes, other timed dwells plain G4 blocks. With a gear pump or screw, the speed word
  // (dialect.rpm_word, rev/min) goes with every melt on and every print move where the speed changes; with
  // a filament extruder, every print move gets its E length (M83, relative extrusion, eq. 3). Coast moves
  // get neither: the pump is off.
  const Extruder* extruder = nullptr;
  // Melt settings per section (indexed by Move::section), as given to apply_melt_settings: the reverse RPM
  // and set at control. A missing entry: the defaults.
  std::vector<MeltSettings> melt;
};

// A number as print programs write it: `decimals` places, trailing zeros dropped ("12.500" -> "12.5",
// "3.000" -> "3", "-0" -> "0").
std::string program_number(double value, int decimals);

// The whole program as text. Feeds are per minute (F in mm/min or in/min). Melt events become the dialect's
// codes; a comment block at each layer change names the section, layer, Z and layer time.
//
// Arcs (dialect.arcs and a positive tolerance for the move's section) replace runs of consecutive print
// moves that share Z, section, layer, feature, pass, feed, bead width, roller state and volume per length;
// travel, dwells and extruder events end a run. Each arc block writes X and Y, then I and J (the centre
// relative to the arc's start, in the program's units), and F when the feed changes.
//
// Prime and reverse (core/melt_settings.hpp; slicer/melt_events.hpp plans them), with an extruder:
//   prime    The melt on starts the pump at the priming speed; the prime code (if any), then G4 P<prime
//            time>; the first print move sets the bead's speed. A filament machine feeds the prime's length
//            in place, G1 E<length> F<feed>.
//   reverse  The reverse code with the reverse speed, G4 P<reverse time> and the reverse-off code; without
//            the delay (duration 0) the reverse goes on while the head moves on (coast and travel) and is
//            turned off before the next melt on or print move. A filament machine with a displacement draws
//            the filament back in place, G1 E-<length> F<feed>, instead of the dwell.
//   set at control
//            Only the prime code or reverse code: the controller supplies times and speeds.
// Dwells are G4 P<whole milliseconds>, which Fanuc and Marlin/RepRap controllers both read. Codes left empty
// in the dialect are written as comments.
std::string write_gcode(const Toolpath& toolpath, const GcodeDialect& dialect, const GcodeHeader& header,
                        const GcodeOptions& options = {});

}  // namespace beadtwin::gcode
