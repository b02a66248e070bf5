// A variant's parameters as report.json lists them, from their declarations (core/param.hpp): each section
// key with its value as the run used it (derived values resolved), the key's last part carrying the
// internal unit of a quantity ("layer_height_mm", "speed_mm_s", "fill.angle_deg"), nested by the key's dots.
#pragma once

#include <nlohmann/json.hpp>

#include "core/param.hpp"
#include "scenarios/input/scenario.hpp"

namespace beadtwin::scenarios {

// A declared value as JSON: a number, a whole number, true/false, text, a list, or null when unset.
nlohmann::json to_json(const ParamValue& value);

// The name a declared key's last part has in the report: with the internal unit of its dimension unless
// it already ends with it ("prime_rpm").
std::string report_name(std::string_view leaf, Dimension dim);

// The variant's parameters: machine and material names, the part or the program read, the voxel size, the
// settings its variant and the command line made, and each section's parameters.
nlohmann::json parameters_json(const Variant& v);

}  // namespace beadtwin::scenarios
