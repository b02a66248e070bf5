// What an open face of the part sees of the sky (docs/physics.md, cooling: radiation view factors): for each
// thermal cell, the share of its open surface's radiation that leaves for the surroundings at the air's
// temperature (the sky view factor), the share that falls on the table, and (the rest) on the part's other
// faces. The view factors come from rays traced with Embree against the part as deposited so far.
//
// Geometry. The part is the deposit's voxels (ThermalMesh::cell_grid): its occluders are the voxel faces
// towards the outside air (the finished part's surface, staircase and all; a ray from outside never reaches
// an enclosed gap), each with the toolpath layer of its cell. A layer's faces join the scene when every cell
// of that layer is born; the layer being printed does not yet hide anything. The table is the plane z =
// ThermalMesh::table_z_mm, of no edge: a ray going down that meets no voxel face ends on it.
//
// Samples. A cell's surface for good (its voxel faces towards the outside air: not towards another cell,
// an enclosed gap or the table) is sampled at up to `faces_per_cell` of its faces, spread evenly over them in
// the order (direction, then voxel); the cell's rays_per_cell rays are shared equally among its samples,
// each casting its share over its hemisphere, cosine-weighted by a fixed stratified pattern (a spiral of
// equal areas on the unit disk, turned by a hash of the cell and sample), so that the fraction of rays that
// escape is the sample's view factor and the result is the same on every run and thread count. A cell's view
// factor is the mean over its samples.
//
// When. A cell's views are first found when its layer joins the scene, and again whenever the height of the
// scene's top above the cell's centroid has grown by the factor 1 + regrow since they were last found: a
// face's view of walls rising around it changes with the angle they subtend, so the number of updates per
// cell grows with the logarithm of the part's height in layers, not with the layers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "thermal/mesh.hpp"

namespace beadtwin::thermal {

// How many rays and how often.
struct ViewFactorOptions {
  int rays_per_cell = 32;  // rays cast per cell at each update, >= faces_per_cell
  int faces_per_cell = 4;  // sample faces per cell, >= 1
  double regrow = 0.25;    // relative growth of the height above a cell that updates its views, > 0
};

// A cell's view of its surroundings, as fractions of its surface for good's hemisphere (sky + table <= 1).
struct CellView {
  float sky = 1.0f;    // the sky view factor: to the surroundings at the air's temperature
  float table = 0.0f;  // to the table
};

// One cell's views found anew.
struct ViewChange {
  std::uint32_t cell = 0;
  CellView view;
};

// The view factors of a mesh's cells as the part grows. Not copyable; one solve's, used from one thread (its
// updates trace rays on TBB's threads).
class SkyView {
 public:
  // Prepares the samples and the layers' occluders of `mesh` (a mesh without its cell grid has no geometry:
  // every update is empty, every cell keeps CellView{}). Preconditions: `mesh` outlives the SkyView;
  // options.faces_per_cell >= 1, rays_per_cell >= faces_per_cell, regrow > 0.
  SkyView(const ThermalMesh& mesh, const ViewFactorOptions& options = {});
  ~SkyView();
  SkyView(const SkyView&) = delete;
  SkyView& operator=(const SkyView&) = delete;

  // Cells [0, born) are born (born never decreases between calls): adds the layers now complete to the
  // scene and returns the cells whose views were found anew (in increasing cell order), and their views.
  std::vector<ViewChange> update(std::size_t born);

  std::size_t rays_cast() const;  // since construction
  std::size_t updates() const;    // cell view computations since construction

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace beadtwin::thermal
