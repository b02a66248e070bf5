// Print programs from a Toolpath: readable G-code for a roller gantry machine, with comments naming the
// section, layer and feature of every block.
#pragma once

#include <string>

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
};

struct GcodeHeader {
  std::string program_name;
  std::string scenario;
  std::string variant;
  std::string machine;
  std::string material;
};

// The whole program as text. Feeds are per minute (F in mm/min or in/min). Melt events become the dialect's
// codes; a comment block at each layer change names the section, layer, Z and layer time.
std::string write_gcode(const Toolpath& toolpath, const GcodeDialect& dialect, const GcodeHeader& header);

}  // namespace beadtwin::slicer
