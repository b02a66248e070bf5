// The colours the runner paints on the part and the report's legends show: one definition for both.
#pragma once

#include <string>

#include "render/image.hpp"
#include "thermal/thermal.hpp"

namespace beadtwin::scenarios {

// Fusion verdicts: green fuses, red too hot, blue too cold, grey no interface (first layer).
render::Rgb verdict_colour(thermal::Verdict verdict);
// Distinct colours for sections (a qualitative palette that stays apart for colour-blind readers).
render::Rgb section_colour(int section);
// "#rrggbb" for HTML.
std::string hex(const render::Rgb& c);

}  // namespace beadtwin::scenarios
