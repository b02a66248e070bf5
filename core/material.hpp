// Material and machine data as the physics reads them: typed, in internal units, already
// validated. The scenario loader fills them from scenarios/data/materials/*.yaml and
// scenarios/data/machines/*.yaml.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.hpp"

namespace beadtwin {

// How the reptation (welding) time shifts with temperature (thermal/fusion.hpp, docs/physics.md fusion
// window): WLF from the glass transition to a material's limit above it and Arrhenius beyond (amorphous
// polymers), or Arrhenius throughout.
enum class HealingLaw : std::uint8_t { kWlf, kArrhenius };
inline constexpr EnumName<HealingLaw> kHealingLawNames[] = {{HealingLaw::kWlf, "wlf"},
                                                            {HealingLaw::kArrhenius, "arrhenius"}};
constexpr std::span<const EnumName<HealingLaw>> enum_names(HealingLaw) {
  return kHealingLawNames;
}

// How the plausible values of an input spread (docs/physics.md, uncertainty of the verdicts): uniform between
// two ends, uniform in the logarithm between them (an input known to within a factor, spanning decades), or
// normal about the file's value with a standard deviation.
enum class Spread : std::uint8_t { kUniform, kLogUniform, kNormal };
inline constexpr EnumName<Spread> kSpreadNames[] = {
    {Spread::kUniform, "uniform"}, {Spread::kLogUniform, "log-uniform"}, {Spread::kNormal, "normal"}};
constexpr std::span<const EnumName<Spread>> enum_names(Spread) {
  return kSpreadNames;
}

// The plausible values of one input that decides the fusion verdicts, as its file's `ranges:` block gives
// them, in the key's internal units (or as factors on its value where `scale`).
struct InputRange {
  std::string
      key;  // the input's key in its file: "emissivity", "fusion.reptation_time", "environment.ambient"
  Spread spread = Spread::kUniform;
  double lo = 0.0, hi = 0.0;  // uniform, log-uniform: the ends, lo <= value <= hi (factors: lo <= 1 <= hi)
  double sigma = 0.0;         // normal: the standard deviation about the value (a factor's: about 1)
  bool scale = false;         // lo, hi and sigma are factors on the value
};
// The range of `key` in `ranges`, or nullptr.
const InputRange* find_range(std::span<const InputRange> ranges, std::string_view key);

// A print material's thermal and fusion properties, SI with temperatures in °C.
struct Material {
  std::string name;
  std::string description = "-";
  std::string sources;  // where the values come from, as the material file says (free text)
  double density_kg_m3 = 1140.0;
  double specific_heat_J_kgK = 1640.0;
  // When not empty, the specific heat by temperature instead: (°C, J/kg·K) points in increasing temperature,
  // linear between them and constant beyond the first and the last.
  std::vector<std::pair<double, double>> specific_heat_by_temp;
  double specific_heat_at(double temp_c) const;  // c_p at `temp_c` (°C), J/kg·K
  // ∫ c_p dT from `from_c` to `to_c`, J/kg.
  double enthalpy_J_kg(double from_c, double to_c) const;
  // Orthotropic conductivity: along the bead, across it (in the layer plane), through the layer thickness.
  double conductivity_along_W_mK = 0.17;
  double conductivity_across_W_mK = 0.17;
  double conductivity_through_W_mK = 0.17;
  double emissivity = 0.85;
  double deposition_temp_c = 200.0;  // temperature of the bead as it leaves the nozzle
  double glass_transition_c = 110.0;
  // Fusion window (docs/physics.md, fusion window).
  // The support of a new bead (thermal/support.hpp): the material under it softer than softening_temp_c
  // (NaN: the glass transition) flows as a viscous layer, its zero-shear viscosity viscosity_ref_Pa_s at
  // healing_ref_temp_c shifted with temperature as the reptation time is; the bead is too hot where that
  // layer slumps by more than max_slump times the layer height as it lands.
  double softening_temp_c = std::numeric_limits<double>::quiet_NaN();
  double viscosity_ref_Pa_s = 1e5;
  double max_slump = 0.1;
  HealingLaw healing_law = HealingLaw::kWlf;
  double healing_ref_temp_c = 200.0;  // T_ref of the reptation time
  double reptation_time_ref_s = 1.0;  // t_w at T_ref
  // WLF shift referred to the glass transition: log10 a(T) = −C1 (T − T_g) / (C2 + T − T_g), from T_g up to
  // T_g + wlf_range_k; the universal constants of Williams, Landel and Ferry (1955) by default.
  double wlf_c1 = 17.44;
  double wlf_c2_k = 51.6;
  double wlf_range_k = 100.0;
  double healing_activation_J_mol = 150e3;  // E_a of the Arrhenius shift (above the WLF range, or throughout)
  double healing_min_temp_c = 110.0;        // below this the interface does not heal at all (glassy)
  double required_healing = 0.9;            // degree of healing D_h below which the interface is too cold
  double price_per_kg = 0.0;
  std::vector<InputRange> ranges;  // the plausible ranges of the inputs above that decide the verdicts
};

// What surrounds the print: the air and the build table.
struct Environment {
  double ambient_c = 18.0;        // the air's temperature
  double bed_temp_c = 65.0;       // the table's temperature, held
  bool bed_insulated = false;     // true: adiabatic table instead of one held at bed_temp_c
  double convection_W_m2K = 7.0;  // natural convection on free faces
  // When not empty, the convection coefficient by height above the table instead: (height mm, W/m²K)
  // points in increasing height, linear between them and constant beyond the first and the last (a part in
  // an enclosure whose air is stiller, or a fan, at some heights).
  std::vector<std::pair<double, double>> convection_by_height;
  double convection_at(double height_mm) const;  // at `height_mm` above the table, W/m²K
  double bed_contact_W_m2K = 100.0;              // contact conductance between the first layer and the table
  // Forced convection on free faces with the part-cooling fan (or air knife) at full output, W/m²K; at an
  // output s (0..1) the faces lose by max(h, s · fan_convection_W_m2K). 0: the machine has none.
  double fan_convection_W_m2K = 0.0;
  std::vector<InputRange> ranges;  // the plausible ranges of the inputs above (keys environment.*)
};

}  // namespace beadtwin
