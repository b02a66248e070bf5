// One picture's pixels as the renderer traces them (render.cpp colours them at once, traced.cpp keeps them
// to colour later): what every pixel of a picture shares (the camera framed on the part, the light rig, the
// pixels that can meet the part or its shadow, the shader), the image's tiles, and a PixelSampler that traces
// one pixel's samples, their shadow and occlusion rays, as far as the light each sample receives.
//
// Internal to the render library, like shading.hpp.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#if defined(__x86_64__) || defined(__SSE2__)
#include <xmmintrin.h>
#define BEADTWIN_HAVE_MXCSR 1
#endif

#include "core/error.hpp"
#include "render/render.hpp"
#include "render/shading.hpp"
#include "render/surface.hpp"
#include "sim/embree.hpp"

namespace beadtwin::render {

// Embree's device and scene over a PreparedDeposit's surface.
struct PreparedScene {
  embree::Device device;
  embree::Scene scene;
};

namespace pixels {

using shading::Vec3;

// The automatic ambient occlusion distance, in voxels (RenderOptions::ambient_occlusion_distance_mm).
inline constexpr double kAutoOcclusionVoxels = 4.0;
inline constexpr int kTile = 16;  // pixels on a side of the image's tiles, the rendering's unit of work

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

// `bounds` grown by the shadow they cast on the bed (the plane of their bottom) towards the key light of
// `lights`, penumbra included; nothing when the light grazes the bed and the shadow runs off to the horizon.
inline std::optional<Eigen::AlignedBox3f> with_ground_shadow(const Eigen::AlignedBox3f& bounds,
                                                             const shading::Lights& lights) {
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

// Every pixel of a width x height image, as screen_reach gives a part of it.
inline Eigen::AlignedBox2f whole_image(int width, int height) {
  return {Eigen::Vector2f::Zero(), Eigen::Vector2f(static_cast<float>(width), static_cast<float>(height))};
}

// The pixels of an image from `camera` (x right, y down, from its top left corner) whose rays may meet
// `box`: its corners' outline, a pixel wider on every side, or the whole image when a corner is behind the
// eye.
inline Eigen::AlignedBox2f screen_reach(const Camera& camera, const Eigen::AlignedBox3f& box, int width,
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
inline float shadow_offset_mm(const SurfaceMesh& mesh, double voxel_mm) {
  const float extent =
      std::max(mesh.bounds.min().cwiseAbs().maxCoeff(), mesh.bounds.max().cwiseAbs().maxCoeff());
  return std::max(0.05f * static_cast<float>(voxel_mm),
                  16.0f * std::numeric_limits<float>::epsilon() * extent);
}

// The camera of a picture: framed on the caller's box or the part's surface, and looking down at the bed,
// on the part's shadow beside it too (in oblique views the shadow falls mostly behind the part, and framing
// it would only push the part off centre). The lights are set by the view's orientation, which framing does
// not change.
inline Camera framed_camera(const SurfaceMesh& mesh, const RenderOptions& options) {
  const Eigen::AlignedBox3f box = options.frame.isEmpty() ? mesh.bounds : options.frame;
  const auto frame = [&](const Eigen::AlignedBox3f& bounds) {
    return Camera::make(options.camera, bounds, options.width, options.height, options.margins);
  };
  const Camera camera = frame(box);
  if (!options.ground_shadow || camera.forward().z() >= -0.9f || options.camera.view == View::kUser)
    return camera;
  const shading::Lights lights(camera, options.key_light_radius_deg);
  return frame(with_ground_shadow(box, lights).value_or(box));
}

// The background's radiance on row y of `height`: a vertical gradient from `top` to `bottom` (linear).
inline Vec3 background_row(const Vec3& top, const Vec3& bottom, int y, int height) {
  const float t = (static_cast<float>(y) + 0.5f) / static_cast<float>(height);
  return top + t * (bottom - top);
}

// What every pixel of one picture of `deposit` shares. Holds references to both: they must outlive it.
class PictureSetup {
 public:
  // `options` already validated.
  PictureSetup(const PreparedDeposit& deposit, const RenderOptions& options)
      : deposit_(deposit),
        options_(options),
        camera_(framed_camera(deposit.surface(), options)),
        lights_(camera_, options.key_light_radius_deg),
        reach_(reach(deposit.surface(), camera_, lights_, options)),
        cut_(options.cut ? std::optional<shading::CutPlane>(std::in_place, *options.cut, deposit.fill())
                         : std::nullopt),
        shader_(deposit.scene().scene, deposit.surface(), lights_, options,
                shadow_offset_mm(deposit.surface(), deposit.voxel_size_mm()),
                static_cast<float>(options.ambient_occlusion_distance_mm > 0.0
                                       ? options.ambient_occlusion_distance_mm
                                       : kAutoOcclusionVoxels * deposit.voxel_size_mm()),
                cut_ ? &*cut_ : nullptr),
        rays_(camera_),
        patterns_(static_cast<std::uint32_t>(options.samples_per_pixel),
                  static_cast<std::uint32_t>(options.ambient_occlusion_samples)),
        top_(shading::to_linear(options.background)),
        bottom_(shading::to_linear(options.background_bottom)) {}
  PictureSetup(const PictureSetup&) = delete;
  PictureSetup& operator=(const PictureSetup&) = delete;

  const PreparedDeposit& deposit() const { return deposit_; }
  const RenderOptions& options() const { return options_; }
  const shading::Shader& shader() const { return shader_; }
  const RayGenerator& rays() const { return rays_; }
  const shading::Patterns& patterns() const { return patterns_; }
  const Eigen::AlignedBox2f& reach() const { return reach_; }

  // The background's radiance (linear) on row y.
  Vec3 background(int y) const { return background_row(top_, bottom_, y, options_.height); }

  // The image's scale at the centre of the framed box (0 when the box is behind a perspective camera).
  double mm_per_pixel() const {
    const Eigen::AlignedBox3f box = options_.frame.isEmpty() ? deposit_.surface().bounds : options_.frame;
    const Vec3 centre = box.center();
    return camera_.orthographic() || (centre - camera_.eye()).dot(camera_.forward()) > 0.0f
               ? camera_.mm_per_pixel_at(centre, options_.width)
               : 0.0;
  }

 private:
  // Pixels outside the outline of the part's box and its shadow's are the background: no ray can change
  // them (a grazing light's shadow can reach anywhere).
  static Eigen::AlignedBox2f reach(const SurfaceMesh& mesh, const Camera& camera,
                                   const shading::Lights& lights, const RenderOptions& options) {
    if (!options.ground_shadow) return screen_reach(camera, mesh.bounds, options.width, options.height);
    const std::optional<Eigen::AlignedBox3f> shadow_box = with_ground_shadow(mesh.bounds, lights);
    return shadow_box ? screen_reach(camera, *shadow_box, options.width, options.height)
                      : whole_image(options.width, options.height);
  }

  const PreparedDeposit& deposit_;
  const RenderOptions& options_;
  Camera camera_;
  shading::Lights lights_;
  Eigen::AlignedBox2f reach_;
  std::optional<shading::CutPlane> cut_;
  shading::Shader shader_;
  RayGenerator rays_;
  shading::Patterns patterns_;
  Vec3 top_, bottom_;
};

// The image's square tiles, a fixed grid of kTile pixels on a side (smaller along the right and bottom
// edges), numbered row by row. A tile keeps its rays close together (in the BVH's cache).
struct Tiles {
  int width, height, across, down;

  Tiles(int w, int h) : width(w), height(h), across((w + kTile - 1) / kTile), down((h + kTile - 1) / kTile) {}
  int count() const { return across * down; }
  int x0(int tile) const { return (tile % across) * kTile; }
  int y0(int tile) const { return (tile / across) * kTile; }
  int x1(int tile) const { return std::min(width, x0(tile) + kTile); }
  int y1(int tile) const { return std::min(height, y0(tile) + kTile); }

  // f(tile) for every tile, on TBB's threads, with denormals flushed. Every pixel is a pure function of its
  // position, so which thread takes which tile does not change the image.
  template <class F>
  void parallel(const F& f) const {
    tbb::parallel_for(tbb::blocked_range<int>(0, count(), 1), [&](const tbb::blocked_range<int>& r) {
      const FlushDenormals flush;
      for (int tile = r.begin(); tile != r.end(); ++tile) f(tile);
    });
  }
};

// The samples of one pixel at a time, on one thread: a pixel's camera rays are traced sixteen at a time
// (they start together and run alike, what packets are fastest for), then its samples' shadow rays
// together, then its occlusion rays.
class PixelSampler {
 public:
  explicit PixelSampler(const PictureSetup& setup)
      : setup_(setup),
        fill_(setup.deposit().fill().getConstUnsafeAccessor()),
        spp_(static_cast<std::uint32_t>(setup.options().samples_per_pixel)) {
    samples_.reserve(spp_);
  }

  std::uint32_t samples_per_pixel() const { return spp_; }

  // Traces pixel (x, y) (x right, y down, from the image's top left corner): its samples and the shadow and
  // occlusion rays they need. False, with nothing traced, for a pixel whose rays can meet neither the part
  // nor its shadow: it is the background.
  bool trace(int x, int y) {
    const auto fx = static_cast<float>(x), fy = static_cast<float>(y);
    if (!setup_.reach().intersects(
            Eigen::AlignedBox2f(Eigen::Vector2f(fx, fy), Eigen::Vector2f(fx + 1.0f, fy + 1.0f)))) {
      camera_rays_outside_ += spp_;
      return false;
    }
    samples_.clear();
    shadow_.clear();
    occlusion_.clear();
    const shading::Shader& shader = setup_.shader();
    const shading::PixelShifts shifts(x, y);
    const float inverse_width = 1.0f / static_cast<float>(setup_.options().width),
                inverse_height = 1.0f / static_cast<float>(setup_.options().height);
    for (std::uint32_t first = 0; first < spp_; first += shading::OcclusionBatch::kLanes) {
      const std::uint32_t n = std::min<std::uint32_t>(shading::OcclusionBatch::kLanes, spp_ - first);
      std::array<Ray, shading::OcclusionBatch::kLanes> rays;
      alignas(64) int valid[shading::OcclusionBatch::kLanes];
      for (std::uint32_t i = 0; i < shading::OcclusionBatch::kLanes; ++i) {
        valid[i] = i < n ? -1 : 0;
        if (i >= n) continue;
        const Eigen::Vector2f jitter =
            spp_ == 1 ? Eigen::Vector2f(0.5f, 0.5f) : setup_.patterns().pixel.at(first + i, shifts.pixel);
        rays[i] = setup_.rays()((fx + jitter.x()) * inverse_width, (fy + jitter.y()) * inverse_height);
        shading::set_lane(camera_rays_.ray, static_cast<int>(i), rays[i].origin, rays[i].direction,
                          std::numeric_limits<float>::infinity());
        camera_rays_.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        camera_rays_.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
        caps_[i] = false;
        if (const shading::CutPlane* cut = shader.cut()) clip(*cut, rays[i], static_cast<int>(i), valid[i]);
      }
      shader.scene().intersect16(valid, camera_rays_, /*coherent=*/true);
      for (std::uint32_t i = 0; i < n; ++i)
        samples_.push_back(shader.begin(rays[i], hit(static_cast<int>(i)),
                                        {setup_.patterns(), shifts, first + i}, shadow_, occlusion_));
    }
    shadow_.trace(shader.scene(), /*coherent=*/true);
    occlusion_.trace(shader.scene(), /*coherent=*/false);
    shadow_rays_ += shadow_.size();
    occlusion_rays_ += occlusion_.size();
    return true;
  }

  // The last pixel traced: its samples, in order.
  const std::vector<shading::Sample>& samples() const { return samples_; }
  // The light of one of them on the part.
  shading::SampleLight light(const shading::Sample& s) const {
    return setup_.shader().finish(s, shadow_, occlusion_);
  }
  // The share of the background's radiance one of them off the part sees.
  float background_share(const shading::Sample& s) const {
    return setup_.shader().background_share(s, shadow_);
  }

  std::uint64_t camera_rays_outside() const { return camera_rays_outside_; }
  std::uint64_t shadow_rays() const { return shadow_rays_; }
  std::uint64_t occlusion_rays() const { return occlusion_rays_; }

 private:
  // A cutaway: the ray traced only through the kept half; a ray that enters it through the cut face where
  // the face is material meets the face there (a cap, not traced).
  void clip(const shading::CutPlane& cut, const Ray& ray, int lane, int& valid) {
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

  shading::CameraHit hit(int lane) const {
    shading::CameraHit h;
    if (caps_[lane]) {
      h.hit = true;
      h.cap = true;
      h.t = cap_t_[lane];
      h.face_normal = setup_.shader().cut()->normal();
      return h;
    }
    h.hit = camera_rays_.hit.geomID[lane] != RTC_INVALID_GEOMETRY_ID;
    if (!h.hit) return h;
    h.t = camera_rays_.ray.tfar[lane];
    h.face_normal =
        Vec3(camera_rays_.hit.Ng_x[lane], camera_rays_.hit.Ng_y[lane], camera_rays_.hit.Ng_z[lane]);
    const TriangleHit on = primitive_hit(setup_.deposit().surface(), camera_rays_.hit.primID[lane],
                                         camera_rays_.hit.u[lane], camera_rays_.hit.v[lane]);
    h.triangle = on.triangle;
    h.u = on.u;
    h.v = on.v;
    return h;
  }

  const PictureSetup& setup_;
  openvdb::FloatGrid::ConstUnsafeAccessor fill_;
  std::array<bool, shading::OcclusionBatch::kLanes> caps_{};
  std::array<float, shading::OcclusionBatch::kLanes> cap_t_{};
  std::uint32_t spp_;
  RTCRayHit16 camera_rays_{};
  std::vector<shading::Sample> samples_;
  shading::OcclusionBatch shadow_, occlusion_;
  std::uint64_t camera_rays_outside_ = 0, shadow_rays_ = 0, occlusion_rays_ = 0;
};

// A pixel's radiance (linear) as display sRGB, the last one kept: runs of pixels of the same radiance (the
// background's rows) are encoded once. One per thread.
class SrgbEncoder {
 public:
  Rgb operator()(const Vec3& c) {
    if (c != last_) {
      encoded_ = {linear_to_srgb(c.x()), linear_to_srgb(c.y()), linear_to_srgb(c.z())};
      last_ = c;
    }
    return encoded_;
  }

 private:
  Vec3 last_ = Vec3::Constant(std::numeric_limits<float>::quiet_NaN());
  Rgb encoded_{};
};

// The rays of a picture's tiles, counted from their samplers on any thread.
class RayCounter {
 public:
  void add(const PixelSampler& sampler) {
    outside_ += sampler.camera_rays_outside();
    shadow_ += sampler.shadow_rays();
    occlusion_ += sampler.occlusion_rays();
  }
  RenderStats stats(const RenderOptions& options) const {
    RenderStats s;
    s.primary_rays = static_cast<std::uint64_t>(options.width) * static_cast<std::uint64_t>(options.height) *
                     static_cast<std::uint64_t>(options.samples_per_pixel);
    s.primary_rays_outside = outside_;
    s.shadow_rays = shadow_;
    s.occlusion_rays = occlusion_;
    return s;
  }

 private:
  std::atomic<std::uint64_t> outside_{0}, shadow_{0}, occlusion_{0};
};

}  // namespace pixels
}  // namespace beadtwin::render
