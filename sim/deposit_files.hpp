// The deposit's voxel fields as files other programs open: OpenVDB for Blender and Houdini, VTK XML for
// ParaView. (The deposit's outer surface as a mesh is sim/skin.hpp.)
//
// Both hold the same three fields per voxel that holds material (sim/deposit.hpp):
//   fill    fraction of the voxel holding material, 0..1
//   time_s  time the material the voxel mostly holds landed, s from the start of the print
//   layer   toolpath layer of that material (-1 for moves without a layer)
// Lengths are mm in the machine frame; voxel (i,j,k) spans [i, i+1) · voxel_size_mm along x (likewise y, z).
// Both writers are atomic: the file appears complete or not at all. They throw std::invalid_argument for a
// deposit without material (an empty file helps nobody) and std::runtime_error when the file cannot be
// written, both naming the path.
#pragma once

#include <cstddef>
#include <filesystem>

#include "sim/deposit.hpp"

namespace beadtwin::sim {

// OpenVDB file with grids fill (a fog volume), density (the fill grid again, under the name Blender's and
// Houdini's volume shaders render by default; written as an instance, so it takes no space), time_s and
// layer, and file metadata creator = beadtwin, length_unit = mm, voxel_size_mm. The deposit's grids are not
// renamed: the file gets shallow copies.
void write_deposit_vdb(const Deposit& deposit, const std::filesystem::path& path);

// Writes `grids` to an OpenVDB file atomically, with `meta` and the file metadata creator = beadtwin and
// length_unit = mm (what every beadtwin VDB carries). Throws std::runtime_error naming `path` when it cannot.
void write_vdb(const openvdb::GridPtrVec& grids, openvdb::MetaMap meta, const std::filesystem::path& path);

// What write_deposit_vtu wrote.
struct VtuCounts {
  std::size_t cells = 0;   // one per voxel that holds material
  std::size_t points = 0;  // voxel corners, each shared by the cells that meet there
};

// VTK XML UnstructuredGrid (.vtu), which ParaView reads without plugins: one VTK_VOXEL cell per voxel that
// holds material, corner points shared between neighbouring cells, cell data fill, time_s and layer.
// A deposit is sparse (a thin shell in a large box), so no dense image of its bounding box is written.
// Appended raw binary data with UInt64 block headers, little-endian; connectivity and offsets are Int32
// when they fit, else Int64. Written as a stream: memory beyond the deposit is one index per corner point.
VtuCounts write_deposit_vtu(const Deposit& deposit, const std::filesystem::path& path);

}  // namespace beadtwin::sim
