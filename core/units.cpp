#include "core/units.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <vector>

#include <fmt/format.h>

namespace beadtwin {
namespace {

// value_internal = value * scale + offset
struct UnitDef {
  std::string_view name;
  double scale;
  double offset = 0.0;
};

struct DimensionDef {
  Dimension dim;
  std::string_view name;
  std::vector<UnitDef> units;  // first one is the internal unit
};

constexpr double kIn3Mm3 = 25.4 * 25.4 * 25.4;

const std::vector<DimensionDef>& table() {
  static const std::vector<DimensionDef> t = {
      {Dimension::kLength,
       "length",
       {{"mm", 1}, {"cm", 10}, {"m", 1000}, {"um", 1e-3}, {"in", 25.4}, {"ft", 304.8}}},
      {Dimension::kArea,
       "area",
       {{"mm2", 1}, {"cm2", 100}, {"m2", 1e6}, {"in2", 25.4 * 25.4}, {"ft2", 304.8 * 304.8}}},
      {Dimension::kTemperature,
       "temperature",
       {{"C", 1},
        {"degC", 1},
        {"°C", 1},
        {"K", 1, -kKelvinOffset},
        {"F", 5.0 / 9.0, -32.0 * 5.0 / 9.0},
        {"degF", 5.0 / 9.0, -32.0 * 5.0 / 9.0}}},
      {Dimension::kTime, "time", {{"s", 1}, {"ms", 1e-3}, {"min", 60}, {"h", 3600}}},
      {Dimension::kMass, "mass", {{"kg", 1}, {"g", 1e-3}, {"lb", kKgPerLb}, {"t", 1000}}},
      {Dimension::kSpeed,
       "speed",
       {{"mm/s", 1},
        {"mm/min", 1.0 / 60},
        {"m/s", 1000},
        {"m/min", 1000.0 / 60},
        {"in/s", 25.4},
        {"in/min", 25.4 / 60},
        {"ipm", 25.4 / 60}}},
      {Dimension::kVolumeFlow,
       "volumetric flow",
       {{"mm3/s", 1},
        {"mm3/min", 1.0 / 60},
        {"cm3/s", 1000},
        {"cm3/min", 1000.0 / 60},
        {"cm3/h", 1000.0 / 3600},
        {"l/h", 1e6 / 3600},
        {"in3/s", kIn3Mm3},
        {"in3/min", kIn3Mm3 / 60}}},
      {Dimension::kMassFlow,
       "mass flow",
       {{"kg/s", 1},
        {"kg/h", 1.0 / 3600},
        {"g/s", 1e-3},
        {"g/min", 1e-3 / 60},
        {"lb/h", kKgPerLb / 3600},
        {"lb/min", kKgPerLb / 60}}},
      {Dimension::kVolume,
       "volume",
       {{"mm3", 1},
        {"cm3", 1000},
        {"l", 1e6},
        {"in3", kIn3Mm3},
        {"cm3/rev", 1000},
        {"mm3/rev", 1},
        {"in3/rev", kIn3Mm3}}},
      {Dimension::kAngle, "angle", {{"deg", 1}, {"°", 1}, {"rad", 180.0 / kPi}}},
      {Dimension::kFraction, "fraction", {{"", 1}, {"%", 0.01}}},
      {Dimension::kDensity,
       "density",
       {{"kg/m3", 1}, {"g/cm3", 1000}, {"lb/in3", kKgPerLb / (kIn3Mm3 * 1e-9)}}},
      {Dimension::kSpecificHeat,
       "specific heat",
       {{"J/kgK", 1}, {"J/(kg*K)", 1}, {"J/kg/K", 1}, {"kJ/kgK", 1000}, {"kJ/(kg*K)", 1000}}},
      {Dimension::kConductivity, "thermal conductivity", {{"W/mK", 1}, {"W/(m*K)", 1}, {"W/m/K", 1}}},
      {Dimension::kHeatTransferCoeff,
       "heat transfer coefficient",
       {{"W/m2K", 1}, {"W/(m2*K)", 1}, {"W/m2/K", 1}}},
      {Dimension::kRotationalSpeed,
       "rotational speed",
       {{"rpm", 1}, {"rev/min", 1}, {"rev/s", 60}, {"1/min", 1}}},
      {Dimension::kMolarEnergy, "molar energy", {{"J/mol", 1}, {"kJ/mol", 1000}}},
      {Dimension::kAcceleration,
       "acceleration",
       {{"mm/s2", 1}, {"m/s2", 1000}, {"in/s2", 25.4}, {"g0", 9806.65}}},
      {Dimension::kPressure,
       "pressure",
       {{"Pa", 1},
        {"mPa", 1e-3},
        {"kPa", 1e3},
        {"MPa", 1e6},
        {"bar", 1e5},
        {"psi", 6894.757293168},
        {"N/mm2", 1e6}}},
      {Dimension::kViscosity,
       "viscosity",
       {{"Pa*s", 1}, {"Pas", 1}, {"mPa*s", 1e-3}, {"mPas", 1e-3}, {"kPa*s", 1e3}, {"kPas", 1e3}}},
      {Dimension::kDimensionless, "number", {{"", 1}}},
  };
  return t;
}

const DimensionDef& def(Dimension dim) {
  for (const auto& d : table())
    if (d.dim == dim) return d;
  throw std::logic_error("unit table lacks a dimension");
}

// Spaces and the '·' and '^' decorations people write do not change a unit: "mm³/s", "mm^3/s", "mm3/s".
std::string normalise(std::string_view unit) {
  std::string out;
  for (std::size_t i = 0; i < unit.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(unit[i]);
    if (std::isspace(c) || c == '^') continue;
    if (c == 0xC2 && i + 1 < unit.size() && static_cast<unsigned char>(unit[i + 1]) == 0xB3) {  // ³
      out += '3';
      ++i;
      continue;
    }
    if (c == 0xC2 && i + 1 < unit.size() && static_cast<unsigned char>(unit[i + 1]) == 0xB2) {  // ²
      out += '2';
      ++i;
      continue;
    }
    if (c == 0xC2 && i + 1 < unit.size() && static_cast<unsigned char>(unit[i + 1]) == 0xB7) {  // ·
      ++i;
      continue;
    }
    out += static_cast<char>(c);
  }
  return out;
}

const UnitDef* find_unit(const DimensionDef& d, std::string_view unit) {
  const std::string n = normalise(unit);
  for (const auto& u : d.units)
    if (u.name == n) return &u;
  // Case-insensitive second chance for the common spellings ("IN", "Mm/S"), but not where case matters
  // between units of the same dimension (none of ours collide ignoring case except "K" temperature vs none).
  for (const auto& u : d.units) {
    if (u.name.size() != n.size()) continue;
    bool same = true;
    for (std::size_t i = 0; i < n.size() && same; ++i)
      same = std::tolower(static_cast<unsigned char>(n[i])) ==
             std::tolower(static_cast<unsigned char>(u.name[i]));
    if (same) return &u;
  }
  return nullptr;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

}  // namespace

std::string_view dimension_name(Dimension dim) {
  return def(dim).name;
}
std::string_view internal_unit(Dimension dim) {
  return def(dim).units.front().name;
}

std::string accepted_units(Dimension dim) {
  std::string out;
  for (const auto& u : def(dim).units) {
    if (u.name.empty()) continue;
    if (!out.empty()) out += ", ";
    out += u.name;
  }
  return out.empty() ? std::string("a plain number") : out;
}

double to_internal(double value, std::string_view unit, Dimension dim) {
  const DimensionDef& d = def(dim);
  const UnitDef* u = find_unit(d, unit);
  if (!u)
    throw QuantityError(
        fmt::format("unknown unit '{}' for a {}; expected one of: {}", unit, d.name, accepted_units(dim)));
  return value * u->scale + u->offset;
}

double from_internal(double value, std::string_view unit, Dimension dim) {
  const DimensionDef& d = def(dim);
  const UnitDef* u = find_unit(d, unit);
  if (!u)
    throw QuantityError(
        fmt::format("unknown unit '{}' for a {}; expected one of: {}", unit, d.name, accepted_units(dim)));
  return (value - u->offset) / u->scale;
}

double parse_quantity(std::string_view text, Dimension dim, std::string_view default_unit) {
  const std::string_view s = trim(text);
  if (s.empty()) throw QuantityError(fmt::format("expected a {} but found nothing", dimension_name(dim)));
  const char* first = s.data();
  const char* last = s.data() + s.size();
  if (*first == '+') ++first;  // from_chars rejects a leading '+'
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(first, last, value);
  if (ec != std::errc() || ptr == first)
    throw QuantityError(
        fmt::format("expected a {} such as '{}' but found '{}'", dimension_name(dim),
                    dim == Dimension::kDimensionless
                        ? std::string("3")
                        : fmt::format("10 {}", accepted_units(dim).substr(0, accepted_units(dim).find(','))),
                    s));
  if (!std::isfinite(value)) throw QuantityError(fmt::format("'{}' is not a finite number", s));
  const std::string_view unit = trim(std::string_view(ptr, static_cast<std::size_t>(last - ptr)));
  if (unit.empty()) {
    if (dim == Dimension::kFraction || dim == Dimension::kDimensionless) return value;
    return to_internal(value, default_unit.empty() ? internal_unit(dim) : default_unit, dim);
  }
  if (dim == Dimension::kDimensionless)
    throw QuantityError(fmt::format("expected a plain number but found '{}' with unit '{}'", s, unit));
  return to_internal(value, unit, dim);
}

}  // namespace beadtwin
