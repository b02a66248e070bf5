// The `ranges:` block of a material or machine file: the plausible values of the inputs that decide the
// fusion verdicts (thermal/uncertainty.hpp), keyed by the same key paths as the values they spread:
//
//   ranges:
//     emissivity: [0.80, 0.95]                                     # uniform between the ends
//     conductivity: {scale: [0.8, 1.2]}                            # factors on the value(s)
//     fusion.reptation_time: {range: [0.2 s, 20 s], distribution: log-uniform}
//     deposition_temp: {distribution: normal, sigma: 5}            # about the value; kelvin
//
// Nested maps (fusion: {reptation_time: ...}) read as the dotted keys. Every range must contain its value
// (a scale range 1) unless a variant set the value, which moves the range to centre on it (its width kept
// for a temperature or a fraction, its factors about its middle for a coefficient); a key that takes no
// range, a range whose ends are the wrong way round, an unknown distribution or word fail with the file,
// line, column and key.
#pragma once

#include <span>
#include <string_view>
#include <vector>

#include "core/material.hpp"
#include "core/units.hpp"
#include "scenarios/input/yaml_reader.hpp"

namespace beadtwin::scenarios {

// An input that takes a range: its key, the dimension its ends are written in, its value (after any
// variant's setting), whether only factors on it are read (`why`: the reason, for the message), and whether
// a variant set its value.
struct RangeKey {
  std::string_view key;
  Dimension dim = Dimension::kDimensionless;
  double value = 0.0;
  bool scale_only = false;
  std::string_view why = {};
  bool overridden = false;
};

// Reads `r`'s `ranges:` block (marking it taken); keys outside `keys` fail. Sets each key's `overridden`
// from `r`'s variant settings.
std::vector<InputRange> read_ranges(BlockReader& r, std::vector<RangeKey> keys);

}  // namespace beadtwin::scenarios
