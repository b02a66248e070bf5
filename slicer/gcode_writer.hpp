// Print programs from a Toolpath: readable G-code for a roller gantry machine, with comments naming the
// section, layer and feature of every block.
#pragma once

#include <string>
#include <vector>

#include "core/toolpath.hpp"

namespace beadtwin::slicer {

struct GcodeDialect {
  std::string name = "gantry";
  bool inches = false;           // G20 and inch coordinates/feeds, else G21 and mm
  std::string melt_on = "M23";   // extruder feed on (the M23/M24 convention of Fanuc macro print programs)
  std::string melt_off = "M24";  // extruder feed off
  std::string roller_down = "";  // optional code to engage the compression roller
  std::string roller_up = "";
  int decimals = 3;
  bool arcs =
      false;  // the controller takes G2/G3 in the XY plane (G17) with I/J centre offsets from the start
};

struct GcodeHeader {
  std::string program_name;
  std::string scenario;
  std::string variant;
  std::string machine;
  std::string material;
};

// Choices for one program that belong neither to the machine's dialect nor to the header comments.
struct GcodeOptions {
  // Arc chord tolerance per section (indexed by Move::section), mm; patent paragraph (45). With
  // GcodeDialect::arcs, runs of print moves are written as G2/G3 arcs that stay within this distance of the
  // moves (slicer/arc_fit.hpp). A missing entry, 0 or a dialect without arcs writes straight moves only.
  std::vector<double> arc_tolerance_mm;
};

// The whole program as text. Feeds are per minute (F in mm/min or in/min). Melt events become the dialect's
// codes; a comment block at each layer change names the section, layer, Z and layer time.
//
// Arcs (dialect.arcs and a positive tolerance for the move's section) replace runs of consecutive print
// moves that share Z, section, layer, feature, pass, feed, bead width, roller state and volume per length;
// travel, dwells and extruder events end a run. Each arc block writes X and Y, then I and J (the centre
// relative to the arc's start, in the program's units), and F when the feed changes.
std::string write_gcode(const Toolpath& toolpath, const GcodeDialect& dialect, const GcodeHeader& header,
                        const GcodeOptions& options = {});

}  // namespace beadtwin::slicer
