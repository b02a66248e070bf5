#include "sim/bead_section.hpp"

#include <cmath>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "sim/deposit.hpp"

namespace beadtwin::sim {

double BeadProfile::area_mm2() const {
  return 4.0 * core_half_width_mm * radius_mm + kPi * radius_mm * radius_mm;
}

double BeadProfile::revolved_volume_mm3() const {
  // Pappus: the core rectangle (a × 2r) and the half-disc of the rim, each revolved about the axis.
  const double a = core_half_width_mm;
  const double r = radius_mm;
  return 2.0 * kPi * a * a * r + kPi * kPi * r * r * a + 4.0 / 3.0 * kPi * r * r * r;
}

BeadProfile moving_bead_profile(double area_mm2, double height_mm) {
  BT_CHECK_OP(area_mm2, >, 0.0);
  BT_CHECK_OP(height_mm, >, 0.0);
  const double round_area = kPi * height_mm * height_mm / 4.0;
  if (area_mm2 < round_area) return {0.0, std::sqrt(area_mm2 / kPi)};
  const double width = bead_width_mm(area_mm2, height_mm);
  return {std::max(0.0, (width - height_mm) / 2.0), height_mm / 2.0};
}

BeadProfile puddle_profile(double volume_mm3, double height_mm) {
  BT_CHECK_OP(volume_mm3, >, 0.0);
  BT_CHECK_OP(height_mm, >, 0.0);
  const double r = height_mm / 2.0;
  const double sphere = 4.0 / 3.0 * kPi * r * r * r;
  if (volume_mm3 <= sphere) return {0.0, std::cbrt(volume_mm3 / (4.0 / 3.0 * kPi))};
  // 2π r a² + π² r² a + (4/3 π r³ − V) = 0, the positive root.
  const double qa = 2.0 * kPi * r;
  const double qb = kPi * kPi * r * r;
  const double qc = sphere - volume_mm3;
  const double a = (-qb + std::sqrt(qb * qb - 4.0 * qa * qc)) / (2.0 * qa);
  return {a, r};
}

}  // namespace beadtwin::sim
