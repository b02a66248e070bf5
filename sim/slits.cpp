#include "sim/slits.hpp"

#include <vector>

namespace beadtwin::sim {

void fill_slits(openvdb::FloatGrid& fill, double solid_fill) {
  const auto acc = fill.getConstAccessor();
  const auto full = [&](const openvdb::Coord& ijk) { return acc.getValue(ijk) >= solid_fill; };
  openvdb::MaskGrid slits(false);
  auto slit = slits.getAccessor();
  for (auto it = fill.cbeginValueOn(); it; ++it) {
    if (*it < solid_fill) continue;
    for (int axis = 0; axis < 3; ++axis) {
      openvdb::Coord gap = it.getCoord(), beyond = gap;
      gap[axis] += 1;
      beyond[axis] += 2;
      if (!full(gap) && full(beyond)) slit.setValueOn(gap);
    }
  }
  std::vector<openvdb::Coord> inside;
  for (auto it = slits.cbeginValueOn(); it; ++it) {
    bool closed = true;
    for (int axis = 0; axis < 3 && closed; ++axis)
      for (const int step : {-1, 1}) {
        openvdb::Coord next = it.getCoord();
        next[axis] += step;
        closed = closed && (full(next) || slit.isValueOn(next));
      }
    if (closed) inside.push_back(it.getCoord());
  }
  auto write = fill.getAccessor();
  for (const openvdb::Coord& ijk : inside) write.setValue(ijk, 1.0f);
}

}  // namespace beadtwin::sim
