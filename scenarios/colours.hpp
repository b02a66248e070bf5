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
// A diverging map for a signed length over the part, such as the stock against the CAD: white at
// `white_mm`, deepening to blue at white_mm − half_range_mm and below (short: undercut) and to red at
// white_mm + half_range_mm and above (excess). ColorBrewer's RdBu, five classes, interpolated in sRGB
// between its stops (as matplotlib does). Precondition: half_range_mm > 0.
render::Rgb deviation_colour(double value_mm, double white_mm, double half_range_mm);
// "#rrggbb" for HTML.
std::string hex(const render::Rgb& c);

}  // namespace beadtwin::scenarios
