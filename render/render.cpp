#include "render/render.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "render/pixels.hpp"
#include "render/shading.hpp"
#include "render/surface.hpp"
#include "sim/embree.hpp"

namespace beadtwin::render {

namespace {

constexpr int kMaxImageSide = 16384;
constexpr int kMaxSamples = 1024;
constexpr double kSurfaceFill = 0.5;  // the part's surface: voxels at least half full are inside
constexpr int kMaxOcclusionSamples = 64;
constexpr double kMaxKeyRadiusDeg = 20.0;

using namespace shading;  // NOLINT: the renderer is the shading module's one user

// --- Inputs ---

void validate(const RenderOptions& o) {
  std::string problems;
  const auto add = [&](const std::string& problem) { problems += (problems.empty() ? "" : "; ") + problem; };
  const auto in_range = [&](const char* name, double value, double lo, double hi) {
    if (!(value >= lo && value <= hi))
      add(std::string(name) + " must be in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " +
          std::to_string(value));
  };
  in_range("width", o.width, 1, kMaxImageSide);
  in_range("height", o.height, 1, kMaxImageSide);
  in_range("samples_per_pixel", o.samples_per_pixel, 1, kMaxSamples);
  in_range("key_light_radius_deg", o.key_light_radius_deg, 0.0, kMaxKeyRadiusDeg);
  in_range("ambient_occlusion_samples", o.ambient_occlusion_samples, 1, kMaxOcclusionSamples);
  if (!(o.ambient_occlusion_distance_mm >= 0.0 && std::isfinite(o.ambient_occlusion_distance_mm)))
    add("ambient_occlusion_distance_mm must be >= 0 (0: automatic), got " +
        std::to_string(o.ambient_occlusion_distance_mm));
  if (o.cut && !(o.cut->normal.norm() > 0.0f && o.cut->normal.allFinite() && o.cut->point.allFinite()))
    add("a cutaway needs a finite point and a non-zero normal");
  if (!problems.empty()) throw InputError({}, "render options", problems);
}

}  // namespace

// --- The scene ---

namespace {

// One Embree quad per primitive of the mesh (SurfaceMesh::quads): a lone triangle a, b, c as the quad a, b,
// c, c, whose second half has no area; a quad's two triangles (a, b, d), (c, d, b) as the quad a, b, c, d.
PreparedScene build_scene(const SurfaceMesh& mesh) {
  embree::Device device;
  embree::Geometry geometry(device, RTC_GEOMETRY_TYPE_QUAD);
  auto points = geometry.new_buffer<std::array<float, 3>>(RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          mesh.points.size());
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    points[i] = {mesh.points[i].x(), mesh.points[i].y(), mesh.points[i].z()};
  const std::size_t lone = mesh.triangles.size() - 2 * mesh.quads;
  auto index = geometry.new_buffer<std::array<std::uint32_t, 4>>(RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4,
                                                                 lone + mesh.quads);
  for (std::size_t t = 0; t < lone; ++t) {
    const auto& c = mesh.triangles[t];
    index[t] = {c[0], c[1], c[2], c[2]};
  }
  for (std::size_t k = 0; k < mesh.quads; ++k) {
    const auto& first = mesh.triangles[lone + 2 * k];  // a, b, d
    index[lone + k] = {first[0], first[1], mesh.triangles[lone + 2 * k + 1][0], first[2]};
  }
  geometry.commit();

  embree::Scene scene(device);
  // Robust: no cracks along shared edges, where a sparkle of background would show through the part. It
  // costs a few per cent of a frame; the build quality changes frame times by less than that
  // (docs/PERFORMANCE.md).
  scene.set_flags(RTC_SCENE_FLAG_ROBUST);
  scene.set_build_quality(RTC_BUILD_QUALITY_MEDIUM);
  scene.attach(geometry);
  scene.commit();
  return {std::move(device), std::move(scene)};
}

// The deposit's surface, after the checks the deposit's overloads share.
SurfaceMesh checked_surface(const sim::Deposit& deposit) {
  if (!deposit.fill) throw InputError("nothing was deposited: the deposit has no fill grid");
  BT_CHECK(deposit.layer != nullptr);
  return extract_surface(*deposit.fill, kSurfaceFill);
}

// The picture of `deposit`'s surface coloured by `albedo`, the material under each point found in `labels`;
// with `values`, also each pixel's value and depth.
FieldPicture render_surface(const PreparedDeposit& deposit, const openvdb::Int32Grid& labels,
                            const Albedo& albedo, const RenderOptions& options, bool values) {
  const pixels::PictureSetup setup(deposit, options);
  const pixels::Tiles tiles(options.width, options.height);
  FieldPicture picture;
  picture.image = Image(options.width, options.height);
  const std::size_t count =
      static_cast<std::size_t>(options.width) * static_cast<std::size_t>(options.height);
  if (values) {
    picture.values.resize(count);
    picture.depth.resize(count);
  }
  pixels::RayCounter rays;
  tiles.parallel([&](int tile) {
    pixels::PixelSampler sampler(setup);
    Probes probes(labels, albedo.field());
    const auto n = static_cast<float>(sampler.samples_per_pixel());
    pixels::SrgbEncoder encode;
    for (int y = tiles.y0(tile); y < tiles.y1(tile); ++y) {
      const Vec3 background = setup.background(y);
      for (int x = tiles.x0(tile); x < tiles.x1(tile); ++x) {
        // What the first of its samples on the part shows, and how far it is: NaN when none is.
        float value = std::numeric_limits<float>::quiet_NaN(), depth = value;
        Vec3 c = background;
        if (sampler.trace(x, y)) {
          // The background's share is summed apart, so a pixel of background alone is exactly `background`,
          // as outside the reach.
          Vec3 part = Vec3::Zero();
          float share = 0.0f;
          for (const Sample& s : sampler.samples()) {
            if (!s.on_part) {
              share += sampler.background_share(s);
              continue;
            }
            float v = 0.0f;
            part += sampler.light(s).radiance(albedo(s.point, -s.geometric, probes, v));
            if (std::isnan(depth)) value = v, depth = s.t;
          }
          c = part / n + (share / n) * background;
        }
        picture.image.set(x, y, encode(c));
        if (values) {
          const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(options.width) +
                                static_cast<std::size_t>(x);
          picture.values[i] = value;
          picture.depth[i] = depth;
        }
      }
    }
    rays.add(sampler);
  });
  picture.stats = rays.stats(options);
  picture.mm_per_pixel = setup.mm_per_pixel();
  return picture;
}

Image render_image(const PreparedDeposit& deposit, const openvdb::Int32Grid& labels, const Albedo& albedo,
                   const RenderOptions& options, RenderStats* stats) {
  FieldPicture picture = render_surface(deposit, labels, albedo, options, false);
  if (stats != nullptr) *stats = picture.stats;
  return std::move(picture.image);
}

}  // namespace

// --- PreparedDeposit ---

PreparedDeposit::PreparedDeposit(const sim::Deposit& deposit)
    : PreparedDeposit(deposit, checked_surface(deposit)) {}

PreparedDeposit::PreparedDeposit(const sim::Deposit& deposit, SurfaceMesh surface)
    : surface_(std::move(surface)), layers_(deposit.layer), fill_(deposit.fill) {
  BT_CHECK(layers_ != nullptr);
  BT_CHECK(fill_ != nullptr);
  BT_CHECK(!surface_.triangles.empty());
  voxel_size_mm_ = layers_->voxelSize()[0];
  scene_ = std::make_unique<PreparedScene>(build_scene(surface_));
}

PreparedDeposit::~PreparedDeposit() = default;
PreparedDeposit::PreparedDeposit(PreparedDeposit&&) noexcept = default;
PreparedDeposit& PreparedDeposit::operator=(PreparedDeposit&&) noexcept = default;

// --- A picture traced once, coloured later ---

namespace {

// A pixel's sample that found no voxel under it (the field's value there is NaN).
const openvdb::Coord kNoVoxel(std::numeric_limits<openvdb::Int32>::max());

// Whether `a` and `b` are active on the same voxels (and neither on a tile above them): every leaf of `a`
// has a leaf of `b` at its place with the same active voxels, and both have as many.
bool same_active_voxels(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
  if (a.tree().activeTileCount() != 0 || b.tree().activeTileCount() != 0) return false;
  if (a.activeVoxelCount() != b.activeVoxelCount()) return false;
  for (auto leaf = a.tree().cbeginLeaf(); leaf; ++leaf) {
    if (leaf->isEmpty()) continue;
    const auto* other = b.tree().probeConstLeaf(leaf->origin());
    if (other == nullptr || other->getValueMask() != leaf->getValueMask()) return false;
  }
  return true;
}

}  // namespace

struct TracedPicture::Traced {
  // One pixel: where its voxels start in its tile's list (they end where the next pixel's start), the light
  // its samples on the part send that no colour filters, the background's share (the samples off the part
  // and how much of the background each sees), and the depth of its first sample on the part (NaN: none).
  struct Pixel {
    std::uint32_t first = 0;
    float untinted = 0.0f, share = 0.0f, depth = 0.0f;
  };
  // One voxel of a pixel's samples: the point of the first of them (where a field of points is taken), and
  // the light they send that the colour filters.
  struct Voxel {
    openvdb::Coord ijk;
    Vec3 point;
    Vec3 tinted;
  };
  // A tile's pixels, row by row, and their voxels in the order their first samples came.
  struct Tile {
    std::vector<Pixel> pixels;
    std::vector<Voxel> voxels;
  };

  openvdb::FloatGrid::ConstPtr fill;
  int width = 0, height = 0;
  float samples = 1.0f;
  Vec3 top, bottom;
  std::vector<Tile> tiles;
  RenderStats stats;
  double mm_per_pixel = 0.0;
};

TracedPicture::TracedPicture(const PreparedDeposit& deposit, const RenderOptions& options)
    : traced_(std::make_unique<Traced>()) {
  validate(options);
  Traced& t = *traced_;
  t.fill = deposit.shared_fill();
  t.width = options.width;
  t.height = options.height;
  t.samples = static_cast<float>(options.samples_per_pixel);
  t.top = to_linear(options.background);
  t.bottom = to_linear(options.background_bottom);
  const pixels::PictureSetup setup(deposit, options);
  const pixels::Tiles tiles(options.width, options.height);
  t.tiles.resize(static_cast<std::size_t>(tiles.count()));
  pixels::RayCounter rays;
  tiles.parallel([&](int tile) {
    pixels::PixelSampler sampler(setup);
    FieldProbe voxels(deposit.fill());
    Traced::Tile& out = t.tiles[static_cast<std::size_t>(tile)];
    out.pixels.reserve(static_cast<std::size_t>(tiles.x1(tile) - tiles.x0(tile)) *
                       static_cast<std::size_t>(tiles.y1(tile) - tiles.y0(tile)));
    for (int y = tiles.y0(tile); y < tiles.y1(tile); ++y)
      for (int x = tiles.x0(tile); x < tiles.x1(tile); ++x) {
        Traced::Pixel& pixel = out.pixels.emplace_back();
        pixel.first = static_cast<std::uint32_t>(out.voxels.size());
        pixel.depth = std::numeric_limits<float>::quiet_NaN();
        if (!sampler.trace(x, y)) {
          pixel.share = t.samples;  // the background alone
          continue;
        }
        for (const Sample& s : sampler.samples()) {
          if (!s.on_part) {
            pixel.share += sampler.background_share(s);
            continue;
          }
          const SampleLight light = sampler.light(s);
          const openvdb::Coord ijk = voxels.voxel_at(s.point, -s.geometric).value_or(kNoVoxel);
          const auto mine = out.voxels.begin() + pixel.first;
          const auto it =
              std::find_if(mine, out.voxels.end(), [&](const Traced::Voxel& v) { return v.ijk == ijk; });
          if (it == out.voxels.end())
            out.voxels.push_back({ijk, s.point, light.tinted});
          else
            it->tinted += light.tinted;
          pixel.untinted += light.untinted;
          if (std::isnan(pixel.depth)) pixel.depth = s.t;
        }
      }
    rays.add(sampler);
  });
  t.stats = rays.stats(options);
  t.mm_per_pixel = setup.mm_per_pixel();
}

TracedPicture::~TracedPicture() = default;
TracedPicture::TracedPicture(TracedPicture&&) noexcept = default;
TracedPicture& TracedPicture::operator=(TracedPicture&&) noexcept = default;

bool TracedPicture::colours(const SurfaceField& field) const {
  if (field.voxels == nullptr) return static_cast<bool>(field.at_point);
  return field.voxels->transform() == traced_->fill->transform() &&
         same_active_voxels(*field.voxels, *traced_->fill);
}

FieldPicture TracedPicture::colour(const SurfaceField& field) const {
  BT_CHECK(static_cast<bool>(field.colour));
  BT_CHECK(colours(field));
  const Traced& t = *traced_;
  const pixels::Tiles tiles(t.width, t.height);
  FieldPicture picture;
  picture.image = Image(t.width, t.height);
  const std::size_t count = static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height);
  picture.values.resize(count);
  picture.depth.resize(count);
  tiles.parallel([&](int tile) {
    const Traced::Tile& in = t.tiles[static_cast<std::size_t>(tile)];
    // Unregistered with the field's tree, as the probes' (render/surface.hpp).
    std::optional<openvdb::FloatGrid::ConstUnsafeAccessor> values;
    if (field.voxels != nullptr) values.emplace(field.voxels->getConstUnsafeAccessor());
    ValueColours albedo(field.colour);
    pixels::SrgbEncoder encode;
    std::size_t p = 0;
    for (int y = tiles.y0(tile); y < tiles.y1(tile); ++y) {
      const Vec3 background = pixels::background_row(t.top, t.bottom, y, t.height);
      for (int x = tiles.x0(tile); x < tiles.x1(tile); ++x, ++p) {
        const Traced::Pixel& pixel = in.pixels[p];
        const std::size_t end = p + 1 < in.pixels.size() ? in.pixels[p + 1].first : in.voxels.size();
        float value = std::numeric_limits<float>::quiet_NaN();
        Vec3 part = Vec3::Zero();
        for (std::size_t k = pixel.first; k < end; ++k) {
          const Traced::Voxel& v = in.voxels[k];
          const double at = !values             ? field.at_point(v.point.cast<double>())
                            : v.ijk == kNoVoxel ? std::numeric_limits<double>::quiet_NaN()
                                                : static_cast<double>(values->getValue(v.ijk));
          if (k == pixel.first) value = static_cast<float>(at);
          part += albedo(at).cwiseProduct(v.tinted);
        }
        part += Vec3::Constant(pixel.untinted);
        picture.image.set(x, y, encode(part / t.samples + (pixel.share / t.samples) * background));
        const std::size_t i =
            static_cast<std::size_t>(y) * static_cast<std::size_t>(t.width) + static_cast<std::size_t>(x);
        picture.values[i] = value;
        picture.depth[i] = pixel.depth;
      }
    }
  });
  picture.stats = t.stats;
  picture.mm_per_pixel = t.mm_per_pixel;
  return picture;
}

std::size_t TracedPicture::memory_bytes() const {
  std::size_t bytes = sizeof(Traced);
  for (const Traced::Tile& tile : traced_->tiles)
    bytes += tile.pixels.capacity() * sizeof(Traced::Pixel) + tile.voxels.capacity() * sizeof(Traced::Voxel) +
             sizeof(Traced::Tile);
  return bytes;
}

// --- Rendering ---

Image render_deposit(const PreparedDeposit& deposit, const LayerColour& colour, const RenderOptions& options,
                     RenderStats* stats) {
  return render_deposit(deposit, deposit.layers(), colour, options, stats);
}

Image render_deposit(const PreparedDeposit& deposit, const openvdb::Int32Grid& labels,
                     const LayerColour& colour, const RenderOptions& options, RenderStats* stats) {
  validate(options);
  BT_CHECK(static_cast<bool>(colour));
  const Palette palette(labels, colour, options.unknown_layer);
  return render_image(deposit, labels, Albedo(palette), options, stats);
}

Image render_deposit(const PreparedDeposit& deposit, const SurfaceColour& colour,
                     const RenderOptions& options, RenderStats* stats) {
  validate(options);
  BT_CHECK(static_cast<bool>(colour));
  return render_image(deposit, deposit.layers(), Albedo(colour), options, stats);
}

FieldPicture render_field(const PreparedDeposit& deposit, const SurfaceField& field,
                          const RenderOptions& options) {
  validate(options);
  BT_CHECK(static_cast<bool>(field.colour));
  BT_CHECK(field.voxels != nullptr || static_cast<bool>(field.at_point));
  return render_surface(deposit, deposit.layers(), Albedo(field), options, true);
}

Image render_deposit(const sim::Deposit& deposit, const LayerColour& colour, const RenderOptions& options) {
  validate(options);
  BT_CHECK(static_cast<bool>(colour));
  return render_deposit(PreparedDeposit(deposit), colour, options);
}

Image render_deposit(const sim::Deposit& deposit, const openvdb::Int32Grid& labels, const LayerColour& colour,
                     const RenderOptions& options) {
  validate(options);
  BT_CHECK(static_cast<bool>(colour));
  return render_deposit(PreparedDeposit(deposit), labels, colour, options);
}

Image render_deposit(const sim::Deposit& deposit, const SurfaceColour& colour, const RenderOptions& options) {
  validate(options);
  BT_CHECK(static_cast<bool>(colour));
  return render_deposit(PreparedDeposit(deposit), colour, options);
}

}  // namespace beadtwin::render
