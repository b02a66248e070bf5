#include "scenarios/colours.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

#include <fmt/format.h>

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
  }
  return {0.5f, 0.5f, 0.5f};
}

render::Rgb section_colour(int section) {
  static constexpr render::Rgb kPalette[] = {
      {0.27f, 0.47f, 0.67f}, {0.93f, 0.40f, 0.47f}, {0.13f, 0.53f, 0.20f}, {0.80f, 0.73f, 0.27f},
      {0.40f, 0.80f, 0.93f}, {0.67f, 0.20f, 0.47f}, {0.73f, 0.73f, 0.73f}};
  if (section < 0) return {0.5f, 0.5f, 0.5f};
  return kPalette[static_cast<std::size_t>(section) % std::size(kPalette)];
}

render::Rgb deviation_colour(double value_mm, double white_mm, double half_range_mm) {
  // RdBu (Brewer 2002), from blue to red: #0571b0 #92c5de #f7f7f7 #f4a582 #ca0020.
  static constexpr render::Rgb kStops[] = {{0.020f, 0.443f, 0.690f},
                                           {0.573f, 0.773f, 0.871f},
                                           {0.969f, 0.969f, 0.969f},
                                           {0.957f, 0.647f, 0.510f},
                                           {0.792f, 0.000f, 0.125f}};
  constexpr double kLast = static_cast<double>(std::size(kStops) - 1);
  const double t =
      std::isfinite(value_mm) ? std::clamp(0.5 + 0.5 * (value_mm - white_mm) / half_range_mm, 0.0, 1.0) : 0.5;
  const double at = t * kLast;
  const auto i = static_cast<std::size_t>(std::min(std::floor(at), kLast - 1));
  const auto f = static_cast<float>(at - static_cast<double>(i));
  const auto mix = [f](float a, float b) { return (1 - f) * a + f * b; };
  const render::Rgb& a = kStops[i];
  const render::Rgb& b = kStops[i + 1];
  return {mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b)};
}

std::string hex(const render::Rgb& c) {
  const auto byte = [](float v) { return static_cast<int>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  return fmt::format("#{:02x}{:02x}{:02x}", byte(c.r), byte(c.g), byte(c.b));
}

}  // namespace beadtwin::scenarios
