// Colour maps: how a quantity or a category becomes a colour on the part and in its legend.
//
// Sequential maps (viridis, inferno) for quantities that run one way (temperature, time, fill), a diverging
// map for signed quantities around zero (deviation from the CAD), and a qualitative palette for categories
// (sections, layers mod N) that stays apart for colour-blind readers. All colours are display sRGB, 0..1,
// as render::Image holds them. nice_ticks() and tick_labels() give a legend's round tick values and their
// shortest labels.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "render/image.hpp"

namespace beadtwin::render {

// The colour of a missing value (NaN): a neutral mid grey, apart from the ends and the white middle of
// every map here.
inline constexpr Rgb kNoValueGrey{0.55f, 0.55f, 0.55f};

// A continuous colour map over 0..1, built from published samples interpolated in CIELAB (see colormap.cpp
// for the sources and why CIELAB). A value type, cheap to copy (the sampled table is shared) and safe to
// call from many threads at once.
class ColourMap {
 public:
  enum class Kind {
    kSequential,  // lightness rises from 0 to 1
    kDiverging,   // dark blue at 0, near white at 0.5, dark red at 1
  };

  // Sequential, perceptually uniform, matplotlib's default (van der Walt & Smith 2015): dark blue-violet
  // #440154 at 0 to yellow #FDE725 at 1.
  static ColourMap viridis();
  // Sequential, perceptually uniform, for temperatures (van der Walt & Smith 2015): near black #000004 at 0
  // to pale yellow #FCFFA4 at 1.
  static ColourMap inferno();
  // Diverging for signed quantities: ColorBrewer RdBu, 9 classes (Brewer 2002), reversed so that 0 is blue
  // (#2166AC, negative), 0.5 near white (#F7F7F7) and 1 red (#B2182B, positive).
  static ColourMap diverging();

  // The colour at `t`, clamped to 0..1; NaN gives kNoValueGrey.
  Rgb at(double t) const;

  const std::string& name() const { return name_; }
  Kind kind() const { return kind_; }

 private:
  struct Stop {
    double t;    // position, 0..1, increasing
    Rgb colour;  // display sRGB
  };
  ColourMap(std::string name, Kind kind, const std::vector<Stop>& stops);

  std::string name_;
  Kind kind_;
  std::shared_ptr<const std::vector<Rgb>> table_;  // evenly spaced over 0..1, display sRGB
};

// The colour of category `index` (a section, a layer mod N): the Okabe & Ito (2008) colour-blind-safe palette
// without its black, seven colours cycled beyond the seventh. A negative index (no category) gives
// kNoValueGrey.
Rgb category_colour(int index);

// A linear scale from a quantity to a colour map: `lo` maps to 0, `hi` to 1, values outside are clamped.
// For a diverging map choose lo = -hi, so that 0 is the map's white middle. hi < lo reverses the map;
// lo == hi gives 0 below, 1 above and 0.5 at the value itself.
struct ScalarScale {
  double lo = 0.0;
  double hi = 1.0;
  ColourMap map = ColourMap::viridis();

  // Where `value` falls on the map, 0..1; NaN for a NaN value or a non-finite lo or hi.
  double fraction(double value) const;
  // map.at(fraction(value)): kNoValueGrey for NaN.
  Rgb colour(double value) const;
};

// Round tick values for an axis over [lo, hi]: the multiples of one step of 1, 2 or 5 x 10^n that lie inside
// [lo, hi], the most of them not above `max_count` (clamped to 2..10000), and at least 2 when lo < hi. When
// no step gives between 2 and max_count ticks (possible for max_count < 5 only) the step with the fewest
// ticks of at least 2 is taken. lo > hi are swapped; lo == hi gives the single tick {lo}; a non-finite lo or
// hi gives no ticks. A range too narrow for two distinct decimal ticks in double precision gives {lo, hi}.
std::vector<double> nice_ticks(double lo, double hi, int max_count);

// Labels for `ticks` with the fewest digits that tell them apart and still say each value to within a
// thousandth of the gap between neighbours: "0.25", "150", "-5"; all labels use the same notation and the
// same number of decimals. Scientific notation ("1.5e+04", "2e-06") only where it is shorter than the
// fixed one. Zero is "0" (never "-0"); NaN and infinities are "nan", "inf" and "-inf".
std::vector<std::string> tick_labels(const std::vector<double>& ticks);

}  // namespace beadtwin::render
