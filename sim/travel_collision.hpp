// Travel moves against the part as it stands: how deep the nozzle's tip runs into material already laid,
// which the deposit reports as a collision (sim/defects.hpp, DefectKind::kCollision).
#pragma once

#include <openvdb/openvdb.h>

#include "core/toolpath.hpp"

namespace beadtwin::sim {

// How deep a travel move runs into material standing above the nozzle's tip, mm (0 when clear): the fill
// (fraction, voxels of `voxel_size_mm`, deposit_transform) is read along the move every voxel, under the
// tip's centre and four points on its rim (`nozzle_diameter_mm`; 0: the centre only), up to four voxels
// above the tip: material within reach of the tip, not a whole tall part above a travel below it.
double travel_collision_mm(const Move& move, const openvdb::FloatGrid& fill, double voxel_size_mm,
                           double nozzle_diameter_mm);

}  // namespace beadtwin::sim
