// Quantities with units (units at the edge: converted when read, one system inside).
//
// Inside beadtwin there is one unit system: mm, s, kg, °C (K only inside formulas), W, degrees for angles,
// plain fractions for ratios. Text such as "0.83 in", "240 C", "150 lb/h", "45 deg" or "10 %" is converted
// here, where input is read, and nowhere else.
#pragma once

#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace beadtwin {

// What a quantity measures, and so its internal unit (beside each).
enum class Dimension {
  kLength,             // mm
  kArea,               // mm²
  kTemperature,        // °C (absolute)
  kTime,               // s
  kMass,               // kg
  kSpeed,              // mm/s
  kVolumeFlow,         // mm³/s
  kMassFlow,           // kg/s
  kVolume,             // mm³
  kAngle,              // degrees
  kFraction,           // 1 (so "10 %" is 0.1)
  kDensity,            // kg/m³
  kSpecificHeat,       // J/(kg·K)
  kConductivity,       // W/(m·K)
  kHeatTransferCoeff,  // W/(m²·K)
  kRotationalSpeed,    // rev/min
  kMolarEnergy,        // J/mol
  kAcceleration,       // mm/s²
  kPressure,           // Pa
  kViscosity,          // Pa·s
  kDimensionless,      // plain number, no unit allowed
};

// Human name of a dimension ("length", "temperature"...).
std::string_view dimension_name(Dimension dim);
// Internal unit of a dimension ("mm", "C", ...).
std::string_view internal_unit(Dimension dim);
// Units accepted for a dimension, for messages and docs.
std::string accepted_units(Dimension dim);

// Thrown by parse_quantity; callers that know the file and key rethrow it as an InputError.
class QuantityError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Parses "<number> [unit]" into the internal unit of `dim`. A bare number takes `default_unit` (which must
// be a unit of `dim`, or empty for "the internal unit"). Throws QuantityError naming what was expected.
double parse_quantity(std::string_view text, Dimension dim, std::string_view default_unit = {});

// Converts `value` given in `unit` into the internal unit of `dim`. Throws QuantityError on an unknown unit.
double to_internal(double value, std::string_view unit, Dimension dim);

// Converts `value` in the internal unit of `dim` into `unit`.
double from_internal(double value, std::string_view unit, Dimension dim);

// Handy constants for code that must state a unit (for example writers in inches).
inline constexpr double kMmPerInch = 25.4;
inline constexpr double kKgPerLb = 0.45359237;
inline constexpr double kKelvinOffset = 273.15;
inline constexpr double kPi = 3.14159265358979323846;

}  // namespace beadtwin
