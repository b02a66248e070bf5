// The render stage: headless images of the deposited part.
//
// A PreparedDeposit holds the deposit's fill-fraction isosurface (the part as printed, with the ridges the
// beads leave) and Embree's acceleration structure over it, built once; render_deposit() ray traces it from
// one of the standard views (camera.hpp) as often as asked, and colours every surface point by the toolpath
// layer of the material under it, through a function the caller supplies — so a per-layer verdict (fine, too
// hot, too cold) is drawn on the part's own shape — or by the surface point itself (a quantity mapped over
// the surface, such as the deviation from the CAD). The overloads taking a sim::Deposit prepare it for one
// picture.
//
// Shading: a key light from the upper left behind the viewer, a small disc whose soft shadows fall on the
// part and on the bed it stands on; a sky/ground ambient term darkened by ambient occlusion, which brings
// out the grooves between beads and layers; a rim light; on a vertical background gradient. Supersampled
// with deterministic stratified (correlated multi-jittered) samples for the pixel, the light and the
// occlusion, all a pure function of the pixel and the sample's index, and parallel over tiles: the image is
// the same for any number of threads.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "render/camera.hpp"
#include "render/image.hpp"
#include "render/surface.hpp"
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

// A cutaway: the plane through `point` (mm) with unit `normal`; the half the normal points into is taken
// away, and where the plane passes through material the cut face shows the inside (its voids, its beads'
// interfaces, the field coloured on it).
struct Cutaway {
  Eigen::Vector3f point = Eigen::Vector3f::Zero();
  Eigen::Vector3f normal = -Eigen::Vector3f::UnitY();
};

// How a picture is rendered: its size, camera, light, shadows and sampling.
struct RenderOptions {
  int width = 1280;  // pixels, 1..16384
  int height = 800;  // pixels, 1..16384
  // The camera: a standard view or the user's (camera.hpp), framed on `frame` within `margins`.
  CameraSpec camera;
  // The box the camera frames, mm; empty: the part's surface. Pictures that compare (variants side by side,
  // the frames of a growing part) share one.
  Eigen::AlignedBox3f frame;
  Margins margins;
  std::optional<Cutaway> cut;
  // Background: display sRGB at the top of the image and at the bottom, a vertical gradient in between.
  Rgb background{0.95f, 0.96f, 0.97f};
  Rgb background_bottom{0.78f, 0.80f, 0.83f};
  bool shadows = true;        // shadows of the key light on the part
  bool ground_shadow = true;  // the part's shadow on the bed under it, darkening the background
  // Angular radius of the key light seen from the part, degrees, 0..20: a disc, sampled with one shadow ray
  // per sample, so shadows (on the part and on the bed) have a penumbra that widens with the distance from
  // the edge casting them. 0: a point light, hard shadows.
  double key_light_radius_deg = 2.0;
  // Ambient occlusion: the sky/ground light reaching a point is scaled by the fraction of cosine-weighted
  // rays around its normal that meet no part of the surface within ambient_occlusion_distance_mm, which
  // darkens the grooves between beads and layers and the inside corners, not open faces.
  bool ambient_occlusion = true;
  // How far an occluder still darkens, mm (>= 0). 0: automatic, 4 voxels of the deposit — two layer heights
  // at the deposit's default voxel size (half a layer height): a groove between beads is dark, a face that
  // sees the part only farther away (across a box) is not.
  double ambient_occlusion_distance_mm = 0.0;
  int ambient_occlusion_samples = 1;  // rays per sample, 1..64; samples_per_pixel of them average per pixel
  // Stratified samples per pixel, 1..1024; 1 takes the pixel centre. Each traces one camera ray and, where
  // it meets the part, one shadow ray and ambient_occlusion_samples occlusion rays.
  int samples_per_pixel = 8;
  // Colour (display sRGB) where no layer is found under the surface (a hole in the layer grid).
  Rgb unknown_layer{0.55f, 0.55f, 0.55f};
};

// The rays one rendering cast.
struct RenderStats {
  std::uint64_t primary_rays = 0;  // camera rays: width * height * samples_per_pixel
  // Of those, the rays of pixels outside the outline of the part's bounding box and its shadow's on the
  // image: they cannot meet either, and are answered as background without being traced.
  std::uint64_t primary_rays_outside = 0;
  std::uint64_t shadow_rays = 0;     // towards the key light, from the part and from the bed in the part's
                                     // shadow's reach
  std::uint64_t occlusion_rays = 0;  // ambient occlusion
  std::uint64_t rays() const { return primary_rays + shadow_rays + occlusion_rays; }
  std::uint64_t rays_traced() const { return rays() - primary_rays_outside; }
};

// Embree's device and scene over a PreparedDeposit's surface (render.cpp).
struct PreparedScene;

// A deposit ready to be rendered many times: its surface extracted and the ray tracing structure built.
// Keeps the deposit's fill and layer grids (shared, so the deposit itself may go); not copyable.
class PreparedDeposit {
 public:
  // Extracts the surface at fill fraction 0.5 (extract_surface) and builds the scene. Throws
  // InputError("nothing was deposited: ...") when the fill grid is missing, empty or has no surface — never
  // an empty picture. A deposit without a layer grid is a bug (InternalError).
  explicit PreparedDeposit(const sim::Deposit& deposit);
  // The same with a surface already extracted from `deposit` (or made from it: cut, say).
  PreparedDeposit(const sim::Deposit& deposit, SurfaceMesh surface);
  ~PreparedDeposit();
  PreparedDeposit(PreparedDeposit&&) noexcept;
  PreparedDeposit& operator=(PreparedDeposit&&) noexcept;
  PreparedDeposit(const PreparedDeposit&) = delete;
  PreparedDeposit& operator=(const PreparedDeposit&) = delete;

  const SurfaceMesh& surface() const { return surface_; }
  const openvdb::Int32Grid& layers() const { return *layers_; }
  const openvdb::FloatGrid& fill() const { return *fill_; }
  const openvdb::FloatGrid::ConstPtr& shared_fill() const { return fill_; }
  double voxel_size_mm() const { return voxel_size_mm_; }
  const PreparedScene& scene() const { return *scene_; }

 private:
  SurfaceMesh surface_;
  openvdb::Int32Grid::ConstPtr layers_;
  openvdb::FloatGrid::ConstPtr fill_;
  double voxel_size_mm_ = 0.0;
  std::unique_ptr<PreparedScene> scene_;
};

// Renders `deposit` coloured by `colour` through its layer grid. Throws InputError naming the options that
// are out of range; an empty `colour` is a bug (InternalError). `stats`, when given, receives the rays
// traced.
Image render_deposit(const PreparedDeposit& deposit, const LayerColour& colour,
                     const RenderOptions& options = {}, RenderStats* stats = nullptr);
// The same, coloured by `labels` instead of the layer grid: any grid of non-negative integers on the
// deposit's material voxels (the thermal cells, say); `colour` is called once per label present.
Image render_deposit(const PreparedDeposit& deposit, const openvdb::Int32Grid& labels,
                     const LayerColour& colour, const RenderOptions& options = {},
                     RenderStats* stats = nullptr);
// The same, coloured point by point by `colour` (RenderOptions::unknown_layer is not used: `colour` sees
// layer -1 and decides).
Image render_deposit(const PreparedDeposit& deposit, const SurfaceColour& colour,
                     const RenderOptions& options = {}, RenderStats* stats = nullptr);

// What colours the part in render_field: a value at every surface point and the colour of a value. The
// value is that of the material voxel under the point (found as for the layer grid: half a voxel inside,
// else the nearest voxel of the grid around it) in `voxels`, or `at_point`'s; NaN where there is none.
// Both functions are called from the rendering's threads at once: they must be safe to call concurrently
// and give the same answer for the same arguments.
struct SurfaceField {
  const openvdb::FloatGrid* voxels = nullptr;  // active on the material voxels
  std::function<double(const Eigen::Vector3d& point_mm)> at_point;
  std::function<Rgb(double value)> colour;  // display sRGB; NaN must have a colour too
};

// A picture of a field, with what it shows pixel by pixel for those who post-process (EXR).
struct FieldPicture {
  Image image;
  // Per pixel, row by row from the top: the field's value and the distance from the eye along the ray, mm,
  // of the first sample of the pixel that met the part; NaN where none did.
  std::vector<float> values;
  std::vector<float> depth;
  double mm_per_pixel = 0.0;  // the image's scale at the centre of the framed box (a scale bar's)
  RenderStats stats;
};

// Renders `deposit` coloured by `field`. Throws InputError naming options out of range (and a cutaway whose
// normal is zero); a field without a colour or without a value (neither voxels nor at_point) is a bug.
FieldPicture render_field(const PreparedDeposit& deposit, const SurfaceField& field,
                          const RenderOptions& options = {});

// One picture's rays traced once, to be coloured by several fields (the pictures of one view of a part: its
// sections, its fusion verdicts, its substrate temperature, its stock over the CAD) without tracing them
// again: for every pixel the light each of its samples receives and the voxel of the deposit's fill under
// each (the voxel render_field takes a field's value from, when the field is active on the fill's voxels).
// A pixel's samples on the same voxel are kept as one, with the point of the first of them, so it holds
// about 40 bytes a pixel and as many again for each voxel it shows: some 40 MB for a 1280 x 800 picture of
// a part filling half of it. It keeps the deposit's fill grid (shared), not the deposit.
class TracedPicture {
 public:
  // Traces `deposit` as render_field would with `options`. Throws InputError naming options out of range.
  TracedPicture(const PreparedDeposit& deposit, const RenderOptions& options);
  ~TracedPicture();
  TracedPicture(TracedPicture&&) noexcept;
  TracedPicture& operator=(TracedPicture&&) noexcept;

  // Whether `field` can be coloured here: a field of voxels active on exactly the fill's voxels, with its
  // transform (as the pictures' fields are, made over the fill's voxels), or of points.
  bool colours(const SurfaceField& field) const;
  // The picture render_field would draw of `field` (colours() must hold), with the same values and depths.
  // Of voxels: the same colours but for rounding (each voxel's colour multiplies the sum of its samples'
  // light), rarely one step of 255 apart. Of points: the colour of a pixel's samples on one voxel is taken
  // at the first of them (the light is still each sample's): a colour that changes within a pixel is not
  // smoothed across it.
  FieldPicture colour(const SurfaceField& field) const;

  std::size_t memory_bytes() const;  // what it holds, bytes

 private:
  struct Traced;
  std::unique_ptr<Traced> traced_;
};

// The same for a deposit prepared for this one picture (the options are checked first, then the surface).
Image render_deposit(const sim::Deposit& deposit, const LayerColour& colour,
                     const RenderOptions& options = {});
Image render_deposit(const sim::Deposit& deposit, const openvdb::Int32Grid& labels, const LayerColour& colour,
                     const RenderOptions& options = {});
Image render_deposit(const sim::Deposit& deposit, const SurfaceColour& colour,
                     const RenderOptions& options = {});

}  // namespace beadtwin::render
