// The render stage: headless images of the deposited part.
//
// render_deposit() takes the deposit's fill-fraction isosurface (the part as printed, with the ridges the
// beads leave), ray traces it with Embree from one of the standard views (camera.hpp) and colours every
// surface point by the toolpath layer of the material under it, through a function the caller supplies —
// so a per-layer verdict (fine, too hot, too cold) is drawn on the part's own shape — or by the surface
// point itself (a quantity mapped over the surface, such as the deviation from the CAD). Shading: a key light
// from the upper left behind the viewer with hard shadows, a sky/ground ambient term and a rim light, on a
// vertical background gradient that also catches the part's shadow on the bed. Supersampled with
// deterministic stratified jitter and parallel over rows: the image is the same for any number of threads.
#pragma once

#include <functional>

#include "render/camera.hpp"
#include "render/image.hpp"
#include "sim/deposit.hpp"

namespace beadtwin::render {

// Colour (display sRGB) of the material laid in toolpath layer `layer` (>= 0). Called once per layer
// present in the deposit, on the calling thread, before the rendering starts.
using LayerColour = std::function<Rgb(int layer)>;

// Colour (display sRGB) of the part's surface at `point_mm` (machine frame, mm, a point of the fill
// isosurface), whose material lies in toolpath layer `layer` (-1 where none is found under it) — for maps of
// a quantity over the surface, such as the deviation from the CAD. Called for every shading sample, from the
// rendering's worker threads at once: it must be safe to call concurrently (read-only state, or an accessor
// made per call or per thread) and return the same colour for the same arguments, so the image stays the
// same for any number of threads.
using SurfaceColour = std::function<Rgb(const Eigen::Vector3d& point_mm, int layer)>;

struct RenderOptions {
  int width = 1280;  // pixels, 1..16384
  int height = 800;  // pixels, 1..16384
  View view = View::kIsometric;
  // Background: display sRGB at the top of the image and at the bottom, a vertical gradient in between.
  Rgb background{0.95f, 0.96f, 0.97f};
  Rgb background_bottom{0.78f, 0.80f, 0.83f};
  bool shadows = true;        // hard shadows of the key light on the part
  bool ground_shadow = true;  // the part's shadow on the bed under it, darkening the background
  // Stratified jittered samples per pixel, 1..1024; 1 takes the pixel centre.
  int samples_per_pixel = 4;
  // Isometric view: 1..120 degrees of perspective, or 0 for orthographic. The top and front views are
  // always orthographic, as drawings are.
  double field_of_view_deg = 30.0;
  // Colour (display sRGB) where no layer is found under the surface (a hole in the layer grid).
  Rgb unknown_layer{0.55f, 0.55f, 0.55f};
};

// Renders `deposit` (fill, layer grids; their transforms give the machine frame in mm) coloured by
// `colour`. Throws InputError("nothing was deposited: ...") when the fill grid is missing, empty or has no
// surface at fill fraction 0.5 — never an empty picture — and InputError naming the options that are out
// of range. A deposit without a layer grid, or an empty `colour`, is a bug (InternalError).
Image render_deposit(const sim::Deposit& deposit, const LayerColour& colour,
                     const RenderOptions& options = {});
// The same, coloured by `labels` instead of the layer grid: any grid of non-negative integers on the
// deposit's material voxels (the thermal cells, say); `colour` is called once per label present.
Image render_deposit(const sim::Deposit& deposit, const openvdb::Int32Grid& labels, const LayerColour& colour,
                     const RenderOptions& options = {});
// The same, coloured point by point by `colour` (RenderOptions::unknown_layer is not used: `colour` sees
// layer -1 and decides). An empty `colour` is a bug (InternalError).
Image render_deposit(const sim::Deposit& deposit, const SurfaceColour& colour,
                     const RenderOptions& options = {});

}  // namespace beadtwin::render
