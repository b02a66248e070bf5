// The thermal mesh (docs/physics.md, heat transfer in the part): control volumes that follow the beads, built
// from the deposit's voxels.
//
// Consecutive depositing moves that join end to start form one bead (a chain). A chain is cut along its
// length into pieces of about `cell_length_mm`, each piece across its width into `cells_across` strips (an
// odd number, so there is a centre strip and two edges) and through its height into `cells_through` slices.
// Each voxel of the deposit belongs to the cell of the move whose material it mostly is (the deposit's move
// grid): its place along, across and through that move's bead picks the piece, strip and slice. A cell is
// therefore a piece of a real bead, including the material that bead pushed into the gaps below it, and it
// is born when that material landed (the fill-weighted mean of its voxels' deposition times).
//
// From the voxels' faces:
//  - two cells share a face where voxels of both touch: the oriented sum of those faces is the contact's area
//    vector (its length the area, its direction the normal), exact for a planar contact however the
//    staircase of voxels runs;
//  - a cell's open surface is where its material faces the outside air. Per voxel, the faces towards air
//    (weighted by the voxel's fill, and the fill drop towards a less full voxel of the same cell, so a
//    surface halfway through a voxel counts once) are summed as vectors and the vector's length is the
//    voxel's area: a wall at 45° to the grid counts its true area rather than the staircase's √2 times
//    it. Faces towards an enclosed gap between beads (Deposit::gaps) do not see the air and count nowhere;
//  - voxels in the lowest row of the deposit rest on the table through their bottom faces.
// Faces between two cells are open surface of the older one until the younger is born.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include "core/memory.hpp"
#include "core/toolpath.hpp"
#include "sim/deposit.hpp"
#include "thermal/support.hpp"

namespace beadtwin::thermal {

// How the beads are cut into cells.
struct MeshOptions {
  int cells_across = 3;         // strips across a bead, odd, 1..15
  int cells_through = 1;        // slices through a bead's height, 1..15
  double cell_length_mm = 0.0;  // piece length along a bead; 0: two bead widths, longer when needed (below)
  // With cell_length_mm 0: pieces are made longer, all by one factor, so that the mesh has at most about
  // this many cells. A desktop print's beads are half a millimetre wide and kilometres long: at two bead
  // widths a 16-hour print would be millions of cells, and the heat solve's cost grows with them.
  std::size_t max_automatic_cells = 250'000;
};

// One control volume: a piece of one bead's material.
struct ThermalCell {
  double volume_mm3 = 0.0;
  Eigen::Vector3d centroid_mm = Eigen::Vector3d::Zero();
  double birth_s = 0.0;  // when its material landed
  // The bead's direction in plan, as an axis (its sign means nothing): the "along" of the conductivity.
  Eigen::Vector2d along = Eigen::Vector2d::UnitX();
  double open_area_mm2 = 0.0;  // surface that faces the outside air for good
  // The half cell behind that surface: over its open faces, the sum of area × depth (from the centroid to
  // the face along its normal n) × the squares of n's components along the bead, across it in plan and
  // through the layer, mm³. Divided by the conductivities in those directions and summed, it is the area
  // times the conduction resistance between the centre and the surface (thermal/surface.hpp). Zero: the
  // surface is at the cell's temperature.
  Eigen::Vector3d open_depth_mm3 = Eigen::Vector3d::Zero();
  double table_area_mm2 = 0.0;  // surface resting on the table, which lies under the centroid at table_z_mm
  std::size_t move = 0;         // the first move (index into Toolpath::moves) that laid its material
  // Born this much hotter than the material's deposition temperature, K: where the program commands another
  // nozzle temperature for this bead than for most of the print (set by solve_thermal; 0 otherwise).
  double deposition_offset_k = 0.0;
  int layer = -1;  // that move's toolpath layer
};

// A contact between two cells through the voxel faces they share.
struct ThermalLink {
  std::uint32_t a = 0, b = 0;  // cells; a < b, so a is born no later than b
  // Oriented area of the shared faces, from a towards b, mm² (length: the area, direction: the normal).
  Eigen::Vector3d area_vector_mm2 = Eigen::Vector3d::Zero();
  double faces_mm2 = 0.0;  // the voxel faces' total area (the staircase's, without orientation)
  // The area-weighted centre of the shared faces, mm: where each cell's half of the contact ends (the face
  // is open surface of a while b is not yet born). NaN: halfway between the centroids along the normal.
  Eigen::Vector3d face_centroid_mm = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  // The contact's area: the area vector's length, or for a contact that wraps round a corner (whose faces
  // partly cancel in the sum) at least the faces' area over √3, which a planar staircase never falls below.
  double area_mm2() const;
  // True where b lands on or against a as a separate bead (another chain, or a part of the same chain that
  // is not its neighbour, such as where a closed loop meets its start): an interface that must fuse.
  // False inside one bead (strips, slices and consecutive pieces).
  bool interface = false;
};

// The cells, their contacts and the voxels each cell holds.
struct ThermalMesh {
  double voxel_size_mm = 0.0;
  double table_z_mm = 0.0;            // the bottom of the deposit's lowest voxel row
  std::vector<ThermalCell> cells;     // by birth time (ties: by chain, piece, strip, slice)
  std::vector<ThermalLink> links;     // by (a, b)
  std::vector<SupportCell> support;   // per cell: what the too-hot verdict measures (support_cells)
  openvdb::Int32Grid::Ptr cell_grid;  // index of the cell each material voxel belongs to; -1 elsewhere
  openvdb::MaskGrid::ConstPtr gaps;   // the deposit's enclosed gaps (shared; may be null): they see no air
  std::size_t chains = 0;
  // With an automatic cell length: how many times two bead widths the pieces were made (1: not longer).
  double cell_length_factor = 1.0;
  std::vector<std::string> notes;  // what the mesh chose for the user (longer cells, ...)
};

// Builds the mesh of `deposit` (made from `toolpath`). Throws InputError for options out of range (naming the
// option); a deposit without material gives an empty mesh. Deterministic: independent of the thread count.
ThermalMesh build_thermal_mesh(const Toolpath& toolpath, const sim::Deposit& deposit,
                               const MeshOptions& options = {});

// How many cells build_thermal_mesh would make for `toolpath` with `options` before any lumping, known
// from the toolpath alone (a pass over its moves): what the thermal stage will hold grows with it.
std::size_t planned_cell_count(const Toolpath& toolpath, const MeshOptions& options = {});

// What the thermal stage holds for `deposit` made from `toolpath`, bytes: its cells while the heat is solved
// (planned_cell_count, fixed bytes) and its grid of the cell each voxel is in (as large as the deposit's
// layer grid: volume bytes at its voxel size).
MemoryCost thermal_cost(const Toolpath& toolpath, const sim::Deposit& deposit,
                        const MeshOptions& options = {});

}  // namespace beadtwin::thermal
