// What slicers say in G-code comments, for the G-code reader (gcode/block_reader.hpp): layer changes,
// layer heights, extrusion widths and what a move is for.
//
// Read from comments (without their delimiters, as the lexer keeps them; matched case-sensitively):
//   layer markers   `LAYER_CHANGE` (PrusaSlicer), `LAYER:<n>` (Cura), `BEGINNING LAYER...` (ORNL Slicer 2),
//                   and beadtwin's own `LAYER <n> SECTION <name> Z <z> HEIGHT <h> ...`
//   heights         `HEIGHT:<mm>` (PrusaSlicer), the HEIGHT of beadtwin's layer comment (program units)
//   widths          `WIDTH:<mm>` (PrusaSlicer)
//   features        `TYPE:<name>` (PrusaSlicer, Cura), ORNL Slicer 2's region comments (`PERIMETER`, `INSET`,
//                   `INFILL`, `SKIN`, `SKELETON`, `SUPPORT`), beadtwin's own `BOUNDARY PASS <n>` and feature
//                   names (`fill`, `raft`, `lead-in`, ...; not `prime` or `reverse`, which also name events)
//
// Slicer feature types map to the Feature the patent names as best as fits: perimeters are boundary passes
// (the external one pass 0, inner ones pass -1: their number is not known), infill of every kind is fill,
// gap fill is a thin wall, skirts, wipe and prime towers are primes, brims and rafts are rafts; support
// material and custom code are kUnknown.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/toolpath.hpp"

namespace beadtwin::gcode {

// What one comment says.
struct Annotation {
  bool layer_marker = false;
  std::optional<double> height;          // layer height, mm or program units (below)
  bool height_in_program_units = false;  // beadtwin's comments are written in the program's units
  std::optional<double> width_mm;        // extrusion width
  std::optional<Feature> feature;        // what the moves after it are for
  int pass = -1;                         // boundary pass, with feature kBoundary
  std::string unknown_type;              // a TYPE: name that maps to no feature (feature is kUnknown)
  std::string malformed;                 // an annotation whose number could not be read
};

// The annotation in one comment; all fields empty when it holds none.
Annotation read_annotation(std::string_view comment);

}  // namespace beadtwin::gcode
