// Fanuc macro print programs (seed 002, section 2.7): layers that repeat the same path one layer height
// higher are written once, inside a WHILE loop that steps a #variable for Z, as hand-written parameterised
// print programs do. The program stays what the plain one commands, block for block.
#pragma once

#include <string>

namespace beadtwin::gcode {

// Rewrites a program from write_gcode: every run of at least `min_layers` consecutive layers whose blocks
// are the same but for Z, which rises by one constant step from layer to layer, becomes
//
//   #100=0
//   WHILE [#100 LT <layers>] DO 1
//     #101=<first Z>+#100*<step>
//     <the layer's blocks, with Z<z> written Z#101 or Z[#101+<offset>]>
//     #100=#100+1
//   END 1
//
// Everything else passes through unchanged.
std::string loop_repeated_layers(const std::string& program, int min_layers = 3);

}  // namespace beadtwin::gcode
