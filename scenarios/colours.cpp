#include "scenarios/colours.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "render/colormap.hpp"

namespace beadtwin::scenarios {

render::Rgb verdict_colour(thermal::Verdict v) {
  switch (v) {
    case thermal::Verdict::kOk:
      return {0.36f, 0.68f, 0.42f};
    case thermal::Verdict::kTooHot:
      return {0.85f, 0.28f, 0.23f};
    case thermal::Verdict::kTooCold:
      return {0.23f, 0.45f, 0.79f};
    case thermal::Verdict::kNoInterface:
      return {0.60f, 0.64f, 0.68f};
    case thermal::Verdict::kMarginal:
      return {0.93f, 0.66f, 0.18f};
  }
  return {0.5f, 0.5f, 0.5f};
}

render::Rgb section_colour(int section) {
  return render::category_colour(section);
}

std::string hex(const render::Rgb& c) {
  const auto byte = [](float v) { return static_cast<int>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  return fmt::format("#{:02x}{:02x}{:02x}", byte(c.r), byte(c.g), byte(c.b));
}

}  // namespace beadtwin::scenarios
