// Temperature snapshots as files other programs open:
//  - OpenVDB (Blender, Houdini, ParaView with its VDB reader): grid `temperature_c`, °C, on the deposit's
//    voxels (each voxel holds its thermal cell's temperature; voxels whose cell is not yet born are left
//    out), file metadata time_s, length_unit = mm;
//  - VTK XML PolyData (.vtp, ParaView without plugins): one point per born thermal cell at its centroid (mm),
//    with point data temperature_c, volume_mm3, layer and birth_s; draw them as points or Point Gaussians.
// Both writers are atomic and throw std::runtime_error naming the path when the file cannot be written.
#pragma once

#include <filesystem>

#include "thermal/heat.hpp"
#include "thermal/mesh.hpp"

namespace beadtwin::thermal {

// Writes `snapshot` (one temperature per cell of `mesh`, NaN for a cell not yet born) on the voxels of
// `mesh.cell_grid`, which must be set, to the OpenVDB file `path`.
void write_temperature_vdb(const ThermalMesh& mesh, const TemperatureSnapshot& snapshot,
                           const std::filesystem::path& path);
// Writes `snapshot` (as above) as the points of the VTK file `path`, one per born cell; returns how many.
std::size_t write_temperature_vtp(const ThermalMesh& mesh, const TemperatureSnapshot& snapshot,
                                  const std::filesystem::path& path);

}  // namespace beadtwin::thermal
