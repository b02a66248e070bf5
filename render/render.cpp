#include "render/render.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#if defined(__x86_64__) || defined(__SSE2__)
#include <xmmintrin.h>
#define BEADTWIN_HAVE_MXCSR 1
#endif

#include "core/error.hpp"
#include "render/embree.hpp"
#include "render/shading.hpp"
#include "render/surface.hpp"

namespace beadtwin::render {

namespace {

constexpr int kMaxImageSide = 16384;
constexpr int kMaxSamples = 1024;
constexpr double kSurfaceFill = 0.5;  // the part's surface: voxels at least half full are inside
constexpr int kMaxOcclusionSamples = 64;
constexpr double kMaxKeyRadiusDeg = 20.0;
// The automatic ambient occlusion distance, in voxels (RenderOptions::ambient_occlusion_distance_mm).
constexpr double kAutoOcclusionVoxels = 4.0;
constexpr int kTile = 16;  // pixels on a side of the image's tiles, the rendering's unit of work

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

struct PreparedScene {
  embree::Device device;
  embree::Scene scene;
};

namespace {

PreparedScene build_scene(const SurfaceMesh& mesh) {
  embree::Device device;
  embree::Geometry geometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto points = geometry.new_buffer<std::array<float, 3>>(RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          mesh.points.size());
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    points[i] = {mesh.points[i].x(), mesh.points[i].y(), mesh.points[i].z()};
  auto triangles = geometry.new_buffer<std::array<std::uint32_t, 3>>(RTC_BUFFER_TYPE_INDEX, 0,
                                                                     RTC_FORMAT_UINT3, mesh.triangles.size());
  std::copy(mesh.triangles.begin(), mesh.triangles.end(), triangles.begin());
  geometry.commit();

  embree::Scene scene(device);
  // Robust: no cracks along shared edges, where a sparkle of background would show through the part. It
  // costs about 3 % of a frame; the build quality changes frame times by less than that
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

// Camera rays in float from three of the camera's own: a pinhole or orthographic camera's ray origins and
// directions (scaled to unit length along the view axis) are affine in the image position, so a ray costs a
// few multiply-adds and a normalisation. Checked against the camera at the fourth corner.
class RayGenerator {
 public:
  explicit RayGenerator(const Camera& camera) {
    const auto along_axis = [&](const Ray& r) {
      return Vec3(r.direction / r.direction.dot(camera.forward()));
    };
    const Ray r00 = camera.ray(0.0, 0.0), r10 = camera.ray(1.0, 0.0), r01 = camera.ray(0.0, 1.0);
    origin_ = r00.origin;
    origin_u_ = r10.origin - r00.origin;
    origin_v_ = r01.origin - r00.origin;
    direction_ = along_axis(r00);
    direction_u_ = along_axis(r10) - direction_;
    direction_v_ = along_axis(r01) - direction_;
    const Ray expected = camera.ray(1.0, 1.0), mine = (*this)(1.0f, 1.0f);
    const float scale = std::max(1.0f, expected.origin.cwiseAbs().maxCoeff());
    BT_CHECK_OP((mine.direction - expected.direction).norm(), <, 1e-4f);
    BT_CHECK_OP((mine.origin - expected.origin).norm(), <, 1e-5f * scale);
  }

  // The ray through image position (u, v), as Camera::ray.
  Ray operator()(float u, float v) const {
    return {origin_ + u * origin_u_ + v * origin_v_,
            (direction_ + u * direction_u_ + v * direction_v_).normalized()};
  }

 private:
  Vec3 origin_, origin_u_, origin_v_;
  Vec3 direction_, direction_u_, direction_v_;
};

// Embree runs fastest with denormals flushed to zero (FTZ and DAZ bits of MXCSR); set for the duration of
// one task, on its thread, and restored after.
class FlushDenormals {
 public:
#ifdef BEADTWIN_HAVE_MXCSR
  FlushDenormals() : saved_(_mm_getcsr()) {
    _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero);
  }
  ~FlushDenormals() {
    _mm_setcsr(saved_);
  }
  FlushDenormals(const FlushDenormals&) = delete;
  FlushDenormals& operator=(const FlushDenormals&) = delete;

 private:
  static constexpr unsigned kFlushToZero = 0x8000u;
  static constexpr unsigned kDenormalsAreZero = 0x0040u;
  unsigned saved_;
#else
  FlushDenormals() {}  // user-provided: a guard object is not an unused variable
#endif
};

// The pixels of one tile, on one thread: a pixel's camera rays are traced sixteen at a time (they start
// together and run alike, what packets are fastest for), then its samples' shadow rays together, then its
// occlusion rays.
class PixelSampler {
 public:
  // `reach`: the pixels (x right, y down, from the image's top left corner) whose rays may meet the part
  // or land in its shadow; the others are the background.
  PixelSampler(const Shader& shader, const RayGenerator& rays, const Patterns& patterns,
               const Eigen::AlignedBox2f& reach, const openvdb::Int32Grid& labels,
               const openvdb::FloatGrid* field, const openvdb::FloatGrid& fill, const RenderOptions& options)
      : shader_(shader),
        rays_(rays),
        patterns_(patterns),
        reach_(reach),
        probes_(labels, field),
        fill_(fill.getConstAccessor()),
        width_(options.width),
        height_(options.height),
        spp_(static_cast<std::uint32_t>(options.samples_per_pixel)) {
    samples_.reserve(spp_);
  }

  // The radiance (linear) of pixel (x, y), `background` where its rays miss the part; in `value` and
  // `depth` what the first of its samples on the part shows and how far it is (NaN when none is).
  Vec3 pixel(int x, int y, const Vec3& background, float& value, float& depth) {
    value = depth = std::numeric_limits<float>::quiet_NaN();
    const auto fx = static_cast<float>(x), fy = static_cast<float>(y);
    if (!reach_.intersects(
            Eigen::AlignedBox2f(Eigen::Vector2f(fx, fy), Eigen::Vector2f(fx + 1.0f, fy + 1.0f)))) {
      camera_rays_outside_ += spp_;
      return background;
    }
    samples_.clear();
    shadow_.clear();
    occlusion_.clear();
    const PixelShifts shifts(x, y);
    const float inverse_width = 1.0f / static_cast<float>(width_),
                inverse_height = 1.0f / static_cast<float>(height_);
    for (std::uint32_t first = 0; first < spp_; first += OcclusionBatch::kLanes) {
      const std::uint32_t n = std::min<std::uint32_t>(OcclusionBatch::kLanes, spp_ - first);
      std::array<Ray, OcclusionBatch::kLanes> rays;
      alignas(64) int valid[OcclusionBatch::kLanes];
      for (std::uint32_t i = 0; i < OcclusionBatch::kLanes; ++i) {
        valid[i] = i < n ? -1 : 0;
        if (i >= n) continue;
        const Eigen::Vector2f jitter =
            spp_ == 1 ? Eigen::Vector2f(0.5f, 0.5f) : patterns_.pixel.at(first + i, shifts.pixel);
        rays[i] = rays_((fx + jitter.x()) * inverse_width, (fy + jitter.y()) * inverse_height);
        set_lane(camera_rays_.ray, static_cast<int>(i), rays[i].origin, rays[i].direction,
                 std::numeric_limits<float>::infinity());
        camera_rays_.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        camera_rays_.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
        caps_[i] = false;
        if (const CutPlane* cut = shader_.cut()) clip(*cut, rays[i], static_cast<int>(i), valid[i]);
      }
      shader_.scene().intersect16(valid, camera_rays_, /*coherent=*/true);
      for (std::uint32_t i = 0; i < n; ++i)
        samples_.push_back(shader_.begin(rays[i], hit(static_cast<int>(i)), {patterns_, shifts, first + i},
                                         probes_, shadow_, occlusion_));
    }
    shadow_.trace(shader_.scene(), /*coherent=*/true);
    occlusion_.trace(shader_.scene(), /*coherent=*/false);
    shadow_rays_ += shadow_.size();
    occlusion_rays_ += occlusion_.size();

    // The background's share is summed apart, so a pixel of background alone is exactly `background`, as
    // outside the reach.
    Vec3 part = Vec3::Zero();
    float share = 0.0f;
    for (const Sample& s : samples_) {
      if (s.on_part) {
        part += shader_.finish(s, shadow_, occlusion_);
        if (std::isnan(depth)) value = s.value, depth = s.t;
      } else {
        share += shader_.background_share(s, shadow_);
      }
    }
    const auto n = static_cast<float>(spp_);
    return part / n + (share / n) * background;
  }

  std::uint64_t camera_rays_outside() const { return camera_rays_outside_; }
  std::uint64_t shadow_rays() const { return shadow_rays_; }
  std::uint64_t occlusion_rays() const { return occlusion_rays_; }

 private:
  // A cutaway: the ray traced only through the kept half; a ray that enters it through the cut face where
  // the face is material meets the face there (a cap, not traced).
  void clip(const CutPlane& cut, const Ray& ray, int lane, int& valid) {
    const auto [near, far] = cut.kept(ray.origin, ray.direction, std::numeric_limits<float>::infinity());
    if (near > far) {
      valid = 0;  // wholly in the half taken away: the background
      return;
    }
    if (near > 0.0f && cut.fill_at(ray.origin + near * ray.direction, fill_) >= 0.5f) {
      caps_[lane] = true;
      cap_t_[lane] = near;
      valid = 0;
      return;
    }
    camera_rays_.ray.tnear[lane] = near;
    camera_rays_.ray.tfar[lane] = far;
  }

  CameraHit hit(int lane) const {
    CameraHit h;
    if (caps_[lane]) {
      h.hit = true;
      h.cap = true;
      h.t = cap_t_[lane];
      h.face_normal = shader_.cut()->normal();
      return h;
    }
    h.hit = camera_rays_.hit.geomID[lane] != RTC_INVALID_GEOMETRY_ID;
    if (!h.hit) return h;
    h.t = camera_rays_.ray.tfar[lane];
    h.face_normal =
        Vec3(camera_rays_.hit.Ng_x[lane], camera_rays_.hit.Ng_y[lane], camera_rays_.hit.Ng_z[lane]);
    h.triangle = camera_rays_.hit.primID[lane];
    h.u = camera_rays_.hit.u[lane];
    h.v = camera_rays_.hit.v[lane];
    return h;
  }

  const Shader& shader_;
  const RayGenerator& rays_;
  const Patterns& patterns_;
  Eigen::AlignedBox2f reach_;
  Probes probes_;
  openvdb::FloatGrid::ConstAccessor fill_;
  std::array<bool, OcclusionBatch::kLanes> caps_{};
  std::array<float, OcclusionBatch::kLanes> cap_t_{};
  int width_, height_;
  std::uint32_t spp_;
  RTCRayHit16 camera_rays_{};
  std::vector<Sample> samples_;
  OcclusionBatch shadow_, occlusion_;
  std::uint64_t camera_rays_outside_ = 0, shadow_rays_ = 0, occlusion_rays_ = 0;
};

// `bounds` grown by the shadow they cast on the bed (the plane of their bottom) towards the key light of
// `lights`, penumbra included; nothing when the light grazes the bed and the shadow runs off to the horizon.
std::optional<Eigen::AlignedBox3f> with_ground_shadow(const Eigen::AlignedBox3f& bounds,
                                                      const Lights& lights) {
  const Vec3& to_light = lights.to_key;
  if (to_light.z() < 0.05f) return std::nullopt;
  Eigen::AlignedBox3f grown = bounds;
  const float height = bounds.sizes().z();
  // Tilting the light by its radius moves the shadow of the top by about this much; doubled to be safe.
  const float penumbra = 2.0f * height * lights.spread / (to_light.z() * to_light.z());
  const Vec3 blur(penumbra, penumbra, 0.0f);
  for (const auto corner : {Eigen::AlignedBox3f::TopLeftCeil, Eigen::AlignedBox3f::TopRightCeil,
                            Eigen::AlignedBox3f::BottomLeftCeil, Eigen::AlignedBox3f::BottomRightCeil}) {
    const Vec3 shadow = bounds.corner(corner) - (height / to_light.z()) * to_light;
    grown.extend(Vec3(shadow - blur));
    grown.extend(Vec3(shadow + blur));
  }
  return grown;
}

Eigen::AlignedBox2f whole_image(int width, int height) {
  return {Eigen::Vector2f::Zero(), Eigen::Vector2f(static_cast<float>(width), static_cast<float>(height))};
}

// The pixels of an image from `camera` (x right, y down, from its top left corner) whose rays may meet
// `box`: its corners' outline, a pixel wider on every side, or the whole image when a corner is behind the
// eye.
Eigen::AlignedBox2f screen_reach(const Camera& camera, const Eigen::AlignedBox3f& box, int width,
                                 int height) {
  Eigen::AlignedBox2f reach;
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner = box.corner(static_cast<Eigen::AlignedBox3f::CornerType>(i));
    if (!camera.orthographic() && (corner - camera.eye()).dot(camera.forward()) <= 0.0f)
      return whole_image(width, height);
    const Eigen::Vector2d uv = camera.project(corner);
    reach.extend(Eigen::Vector2f(static_cast<float>(uv.x() * width), static_cast<float>(uv.y() * height)));
  }
  return Eigen::AlignedBox2f(reach.min() - Eigen::Vector2f::Ones(), reach.max() + Eigen::Vector2f::Ones());
}

// Shadow and occlusion rays start this far off the surface, so a surface does not shadow itself (acne): a
// small part of a voxel, but well above float resolution at the part's distance from the origin.
float shadow_offset_mm(const SurfaceMesh& mesh, double voxel_mm) {
  const float extent =
      std::max(mesh.bounds.min().cwiseAbs().maxCoeff(), mesh.bounds.max().cwiseAbs().maxCoeff());
  return std::max(0.05f * static_cast<float>(voxel_mm),
                  16.0f * std::numeric_limits<float>::epsilon() * extent);
}

// The box a picture frames: the caller's, or the part's surface.
Eigen::AlignedBox3f framed_box(const RenderOptions& options, const SurfaceMesh& mesh) {
  return options.frame.isEmpty() ? mesh.bounds : options.frame;
}

// The picture of `deposit`'s surface coloured by `albedo`, the material under each point found in `labels`;
// with `values`, also each pixel's value and depth.
FieldPicture render_surface(const PreparedDeposit& deposit, const openvdb::Int32Grid& labels,
                            const Albedo& albedo, const RenderOptions& options, bool values) {
  const SurfaceMesh& mesh = deposit.surface();
  const Eigen::AlignedBox3f box = framed_box(options, mesh);
  const auto frame = [&](const Eigen::AlignedBox3f& bounds) {
    return Camera::make(options.camera, bounds, options.width, options.height, options.margins);
  };
  Camera camera = frame(box);
  // Set by the view's orientation, which framing does not change.
  const Lights lights(camera, options.key_light_radius_deg);
  // Looking down at the bed, the part's shadow lies beside it and is framed too; in oblique views it falls
  // mostly behind the part, and framing it would only push the part off centre.
  const std::optional<Eigen::AlignedBox3f> shadow_box = with_ground_shadow(mesh.bounds, lights);
  if (options.ground_shadow && camera.forward().z() < -0.9f && options.camera.view != View::kUser)
    camera = frame(with_ground_shadow(box, lights).value_or(box));
  // Pixels outside the outline of the part's box and its shadow's are the background: no ray can change
  // them (a grazing light's shadow can reach anywhere).
  const Eigen::AlignedBox2f reach =
      !options.ground_shadow ? screen_reach(camera, mesh.bounds, options.width, options.height)
      : shadow_box           ? screen_reach(camera, *shadow_box, options.width, options.height)
                             : whole_image(options.width, options.height);
  const double voxel_mm = deposit.voxel_size_mm();
  const double occlusion_mm = options.ambient_occlusion_distance_mm > 0.0
                                  ? options.ambient_occlusion_distance_mm
                                  : kAutoOcclusionVoxels * voxel_mm;
  std::optional<CutPlane> cut;
  if (options.cut) cut.emplace(*options.cut, deposit.fill());
  const Shader shader(deposit.scene().scene, mesh, albedo, lights, options, shadow_offset_mm(mesh, voxel_mm),
                      static_cast<float>(occlusion_mm), cut ? &*cut : nullptr);

  const RayGenerator rays(camera);
  const Patterns patterns(static_cast<std::uint32_t>(options.samples_per_pixel),
                          static_cast<std::uint32_t>(options.ambient_occlusion_samples));
  const int width = options.width, height = options.height;
  const Vec3 top = to_linear(options.background), bottom = to_linear(options.background_bottom);
  FieldPicture picture;
  picture.image = Image(width, height);
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (values) {
    picture.values.resize(pixels);
    picture.depth.resize(pixels);
  }
  std::atomic<std::uint64_t> outside{0}, shadow_rays{0}, occlusion_rays{0};
  // Square tiles keep a task's rays close together (in the BVH's cache); every pixel is a pure function of
  // its position, so how TBB splits the image does not change it.
  tbb::parallel_for(tbb::blocked_range2d<int>(0, height, kTile, 0, width, kTile),
                    [&](const tbb::blocked_range2d<int>& tile) {
                      const FlushDenormals flush;
                      PixelSampler sampler(shader, rays, patterns, reach, labels, albedo.field_grid(),
                                           deposit.fill(), options);
                      // The last colour encoded: runs of pixels of the same radiance (the background's rows)
                      // are encoded once.
                      Vec3 last = Vec3::Constant(std::numeric_limits<float>::quiet_NaN());
                      Rgb encoded{};
                      for (int y = tile.rows().begin(); y < tile.rows().end(); ++y) {
                        const float t = (static_cast<float>(y) + 0.5f) / static_cast<float>(height);
                        const Vec3 background = top + t * (bottom - top);
                        for (int x = tile.cols().begin(); x < tile.cols().end(); ++x) {
                          float value = 0.0f, depth = 0.0f;
                          const Vec3 c = sampler.pixel(x, y, background, value, depth);
                          if (c != last) {
                            encoded = {linear_to_srgb(c.x()), linear_to_srgb(c.y()), linear_to_srgb(c.z())};
                            last = c;
                          }
                          picture.image.set(x, y, encoded);
                          if (values) {
                            const std::size_t i =
                                static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                                static_cast<std::size_t>(x);
                            picture.values[i] = value;
                            picture.depth[i] = depth;
                          }
                        }
                      }
                      outside += sampler.camera_rays_outside();
                      shadow_rays += sampler.shadow_rays();
                      occlusion_rays += sampler.occlusion_rays();
                    });
  picture.stats.primary_rays = static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) *
                               static_cast<std::uint64_t>(options.samples_per_pixel);
  picture.stats.primary_rays_outside = outside;
  picture.stats.shadow_rays = shadow_rays;
  picture.stats.occlusion_rays = occlusion_rays;
  const Vec3 centre = box.center();
  picture.mm_per_pixel = camera.orthographic() || (centre - camera.eye()).dot(camera.forward()) > 0.0f
                             ? camera.mm_per_pixel_at(centre, width)
                             : 0.0;
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
