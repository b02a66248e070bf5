// A comparison sheet: pictures of the same size side by side, each with a caption above it (the variant's
// name), on a white page — the variants of a scenario drawn from the same camera on the same colour scale,
// so that a person compares them at a glance.
#pragma once

#include <string>
#include <vector>

#include "render/image.hpp"

namespace beadtwin::render {

// Lays `tiles` (all of one size, at least one) out in rows of up to `columns` (0: as many as make the sheet
// nearest to 16:9), each under its caption (UTF-8; bold, dark grey). Throws InputError for no tiles, tiles
// of different sizes or captions that do not match them one to one, and std::runtime_error when no font is
// found (text.hpp).
Image compose_sheet(const std::vector<Image>& tiles, const std::vector<std::string>& captions,
                    int columns = 0);

}  // namespace beadtwin::render
