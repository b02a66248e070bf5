#include "core/bead.hpp"

#include "core/error.hpp"
#include "core/units.hpp"

namespace beadtwin {

double bead_area_mm2(double width_mm, double height_mm) {
  BT_CHECK_OP(height_mm, >, 0.0);
  BT_CHECK_OP(width_mm, >=, height_mm);
  return height_mm * (width_mm - height_mm) + kPi * height_mm * height_mm / 4.0;
}

double bead_width_mm(double area_mm2, double height_mm) {
  BT_CHECK_OP(height_mm, >, 0.0);
  // Below π h²/4 the formula would give w < h: no flattened bead has that area.
  BT_CHECK_OP(area_mm2, >=, kPi * height_mm * height_mm / 4.0 * (1.0 - 1e-12));
  return area_mm2 / height_mm + height_mm * (1.0 - kPi / 4.0);
}

}  // namespace beadtwin
