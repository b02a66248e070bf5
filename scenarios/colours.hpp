// The colours the runner paints on the part and the report's legends show: one definition for both.
#pragma once

#include <string>

#include "render/image.hpp"
#include "thermal/fusion.hpp"

namespace beadtwin::scenarios {

// Fusion verdicts: green fuses, red too hot, blue too cold, grey no interface (first layer).
render::Rgb verdict_colour(thermal::Verdict verdict);
// Distinct colours for sections: the pictures' categorical palette (render::category_colour, Okabe & Ito,
// colour-blind safe), so the report's legends match the pictures. Deviation maps use
// render::ColourMap::diverging() in both.
render::Rgb section_colour(int section);
// "#rrggbb" for HTML.
std::string hex(const render::Rgb& c);

}  // namespace beadtwin::scenarios
