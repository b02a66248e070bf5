#include "render/render.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#if defined(__x86_64__) || defined(__SSE2__)
#include <xmmintrin.h>
#define BEADTWIN_HAVE_MXCSR 1
#endif

#include "core/error.hpp"
#include "render/embree.hpp"
#include "render/sampling.hpp"
#include "render/surface.hpp"

namespace beadtwin::render {

namespace {

constexpr int kMaxImageSide = 16384;
constexpr int kMaxSamples = 1024;
constexpr double kSurfaceFill = 0.5;  // the part's surface: voxels at least half full are inside
constexpr long kMaxLayers = 1L << 24;

using Vec3 = Eigen::Vector3f;

Vec3 to_linear(Rgb c) {
  return {srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b)};
}

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
  if (o.field_of_view_deg != 0.0)
    in_range("field_of_view_deg (0: orthographic)", o.field_of_view_deg, 1.0, 120.0);
  if (!problems.empty()) throw InputError({}, "render options", problems);
}

// Colours of the layers present in the deposit, in linear light, looked up by index while rendering.
class Palette {
 public:
  Palette(const openvdb::Int32Grid& layers, const LayerColour& colour, Rgb unknown)
      : unknown_(to_linear(unknown)) {
    int lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
    for (auto it = layers.cbeginValueOn(); it; ++it) {
      if (*it < 0) continue;
      lo = std::min(lo, *it);
      hi = std::max(hi, *it);
    }
    if (lo > hi) return;  // no layer known anywhere: everything is drawn in the unknown colour
    if (static_cast<long>(hi) - lo + 1 > kMaxLayers)
      throw InputError({}, "deposit.layer",
                       "layer indices span " + std::to_string(lo) + ".." + std::to_string(hi) +
                           ", more than " + std::to_string(kMaxLayers) + " layers");
    first_ = lo;
    std::vector<char> present(static_cast<std::size_t>(hi - lo + 1), 0);
    for (auto it = layers.cbeginValueOn(); it; ++it)
      if (*it >= 0) present[static_cast<std::size_t>(*it - lo)] = 1;
    colours_.assign(present.size(), unknown_);
    for (std::size_t i = 0; i < present.size(); ++i)
      if (present[i] != 0) colours_[i] = to_linear(colour(first_ + static_cast<int>(i)));
  }

  const Vec3& operator()(int layer) const {
    const long i = static_cast<long>(layer) - first_;
    return layer >= 0 && i >= 0 && i < static_cast<long>(colours_.size())
               ? colours_[static_cast<std::size_t>(i)]
               : unknown_;
  }

 private:
  int first_ = 0;
  std::vector<Vec3> colours_;
  Vec3 unknown_;
};

// The colour of a surface point, in linear light: its layer's from the palette made up front, or the
// caller's colour of the point itself.
class Albedo {
 public:
  explicit Albedo(const Palette& palette) : palette_(&palette) {}
  explicit Albedo(const SurfaceColour& colour) : colour_(&colour) {}

  Vec3 operator()(const Vec3& point, int layer) const {
    return colour_ ? to_linear((*colour_)(point.cast<double>(), layer)) : (*palette_)(layer);
  }

 private:
  const Palette* palette_ = nullptr;
  const SurfaceColour* colour_ = nullptr;
};

embree::Scene build_scene(const embree::Device& device, const SurfaceMesh& mesh) {
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
  // Robust: no cracks along shared edges, where a sparkle of background would show through the part.
  scene.set_flags(RTC_SCENE_FLAG_ROBUST);
  scene.set_build_quality(RTC_BUILD_QUALITY_MEDIUM);
  scene.attach(geometry);
  scene.commit();
  return scene;
}

// --- Shading ---

// Light rig, in linear light. Set relative to the camera, so every view is lit alike: the key comes from
// the upper left, from in front of the part (behind the viewer), so the three faces of a box seen in the
// isometric view get three distinct tones (top brightest, left, right darkest) and no face is left black.
struct Lights {
  Vec3 to_key;                       // unit direction towards the key light
  Vec3 key{0.80f, 0.78f, 0.74f};     // slightly warm
  Vec3 sky{0.34f, 0.36f, 0.40f};     // ambient from above, slightly cool...
  Vec3 ground{0.16f, 0.15f, 0.14f};  // ...and from below
  float rim = 0.30f;                 // strength of the grazing-angle rim light
  float specular = 0.08f;            // strength of a soft highlight from the key
  float shininess = 24.0f;
  float ground_shadow = 0.30f;  // fraction of the background's light the part's shadow takes

  explicit Lights(const Camera& camera)
      : to_key((-0.34f * camera.right() + 0.35f * camera.up() - 0.87f * camera.forward()).normalized()) {}
};

class Shader {
 public:
  Shader(const embree::Scene& scene, const SurfaceMesh& mesh, const Albedo& albedo, const Lights& lights,
         const RenderOptions& options, float shadow_offset_mm)
      : scene_(scene),
        mesh_(mesh),
        albedo_(albedo),
        lights_(lights),
        shadows_(options.shadows),
        ground_shadow_(options.ground_shadow),
        ground_z_(mesh.bounds.min().z()),
        offset_(shadow_offset_mm) {}

  // Radiance (linear) along `ray`; `background` where it misses the part.
  Vec3 shade(const Ray& ray, const Vec3& background, LayerProbe& probe) const {
    RTCRayHit rh = make_ray(ray.origin, ray.direction);
    scene_.intersect(rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return ground(ray, background);

    const Vec3 point = ray.origin + rh.ray.tfar * ray.direction;
    Vec3 geometric = Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
    if (geometric.dot(ray.direction) > 0.0f) geometric = -geometric;  // face the viewer
    const Vec3 normal = shading_normal(rh.hit, geometric);
    const Vec3 albedo = albedo_(point, probe.layer_at(point, -geometric));
    const Vec3 to_eye = -ray.direction;

    const float hemisphere = 0.5f + 0.5f * normal.z();  // machine frame: z up
    Vec3 light = lights_.ground + hemisphere * (lights_.sky - lights_.ground);
    const float lambert = normal.dot(lights_.to_key);
    float highlight = 0.0f;
    if (lambert > 0.0f && geometric.dot(lights_.to_key) > 0.0f && lit(point + offset_ * geometric)) {
      light += lambert * lights_.key;
      const Vec3 half = (lights_.to_key + to_eye).normalized();
      highlight = lights_.specular * std::pow(std::max(0.0f, normal.dot(half)), lights_.shininess);
    }
    const float rim = lights_.rim * std::pow(1.0f - std::clamp(normal.dot(to_eye), 0.0f, 1.0f), 4.0f);
    return albedo.cwiseProduct(light) + Vec3::Constant(highlight) +
           rim * (0.6f * albedo + Vec3::Constant(0.4f));
  }

 private:
  static RTCRayHit make_ray(const Vec3& origin, const Vec3& direction) {
    RTCRayHit rh{};
    rh.ray.org_x = origin.x();
    rh.ray.org_y = origin.y();
    rh.ray.org_z = origin.z();
    rh.ray.dir_x = direction.x();
    rh.ray.dir_y = direction.y();
    rh.ray.dir_z = direction.z();
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
  }

  // Interpolated vertex normal, on the viewer's side like the face: smooth light across the facets of the
  // voxel isosurface, which are an artefact of the grid, not the part.
  Vec3 shading_normal(const RTCHit& hit, const Vec3& geometric) const {
    const auto& t = mesh_.triangles[hit.primID];
    Vec3 n = (1.0f - hit.u - hit.v) * mesh_.normals[t[0]] + hit.u * mesh_.normals[t[1]] +
             hit.v * mesh_.normals[t[2]];
    if (n.dot(geometric) < 0.0f) n = -n;
    const float length = n.norm();
    return length > 1e-6f ? Vec3(n / length) : geometric;
  }

  bool lit(const Vec3& origin) const {
    if (!shadows_) return true;
    RTCRayHit rh = make_ray(origin, lights_.to_key);
    return !scene_.occluded(rh.ray);
  }

  // The background, with the part's shadow on the bed it stands on (the plane through its lowest point)
  // where the ray meets the bed: it grounds the part, and in the top view it shows the walls' height.
  Vec3 ground(const Ray& ray, const Vec3& background) const {
    if (!ground_shadow_ || ray.direction.z() > -1e-4f) return background;
    const float t = (ground_z_ - ray.origin.z()) / ray.direction.z();
    if (t <= 0.0f) return background;
    RTCRayHit rh = make_ray(ray.origin + t * ray.direction + offset_ * Vec3::UnitZ(), lights_.to_key);
    return scene_.occluded(rh.ray) ? Vec3((1.0f - lights_.ground_shadow) * background) : background;
  }

  const embree::Scene& scene_;
  const SurfaceMesh& mesh_;
  const Albedo& albedo_;
  const Lights& lights_;
  bool shadows_;
  bool ground_shadow_;
  float ground_z_;
  float offset_;
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

// `bounds` grown by the shadow they cast on the bed (the plane of their bottom) along `to_light`.
Eigen::AlignedBox3f with_ground_shadow(const Eigen::AlignedBox3f& bounds, const Vec3& to_light) {
  Eigen::AlignedBox3f grown = bounds;
  if (to_light.z() < 0.05f) return grown;  // grazing light: the shadow runs off to the horizon
  const float height = bounds.sizes().z();
  for (const auto corner : {Eigen::AlignedBox3f::TopLeftCeil, Eigen::AlignedBox3f::TopRightCeil,
                            Eigen::AlignedBox3f::BottomLeftCeil, Eigen::AlignedBox3f::BottomRightCeil})
    grown.extend(Vec3(bounds.corner(corner) - (height / to_light.z()) * to_light));
  return grown;
}

// Shadow rays start this far off the surface, so a surface does not shadow itself (acne): a small part of
// a voxel, but well above float resolution at the part's distance from the origin.
float shadow_offset_mm(const SurfaceMesh& mesh, double voxel_mm) {
  const float extent =
      std::max(mesh.bounds.min().cwiseAbs().maxCoeff(), mesh.bounds.max().cwiseAbs().maxCoeff());
  return std::max(0.05f * static_cast<float>(voxel_mm),
                  16.0f * std::numeric_limits<float>::epsilon() * extent);
}

// The image of `mesh` (the deposit's surface) coloured by `albedo`.
Image render_surface(const sim::Deposit& deposit, const openvdb::Int32Grid& labels, const SurfaceMesh& mesh,
                     const Albedo& albedo, const RenderOptions& options) {
  const embree::Device device;
  const embree::Scene scene = build_scene(device, mesh);
  const auto frame = [&](const Eigen::AlignedBox3f& bounds) {
    return Camera::framed(options.view, bounds, options.width, options.height, options.field_of_view_deg);
  };
  Camera camera = frame(mesh.bounds);
  const Lights lights(camera);  // set by the view's orientation, which framing does not change
  // Looking down at the bed, the part's shadow lies beside it and is framed too; in oblique views it falls
  // mostly behind the part, and framing it would only push the part off centre.
  if (options.ground_shadow && camera.forward().z() < -0.9f)
    camera = frame(with_ground_shadow(mesh.bounds, lights.to_key));
  const Shader shader(scene, mesh, albedo, lights, options,
                      shadow_offset_mm(mesh, deposit.fill->voxelSize()[0]));

  const int width = options.width, height = options.height;
  const auto spp = static_cast<std::uint32_t>(options.samples_per_pixel);
  const Vec3 top = to_linear(options.background), bottom = to_linear(options.background_bottom);
  Image image(width, height);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    const FlushDenormals flush;
    LayerProbe probe(labels);
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const float t = (static_cast<float>(y) + 0.5f) / static_cast<float>(height);
      const Vec3 background = top + t * (bottom - top);
      for (int x = 0; x < width; ++x) {
        Vec3 sum = Vec3::Zero();
        const std::uint32_t seed = pixel_seed(x, y);
        for (std::uint32_t s = 0; s < spp; ++s) {
          const Eigen::Vector2f jitter = spp == 1 ? Eigen::Vector2f(0.5f, 0.5f) : cmj_sample(s, spp, seed);
          const Ray ray = camera.ray((x + static_cast<double>(jitter.x())) / width,
                                     (y + static_cast<double>(jitter.y())) / height);
          sum += shader.shade(ray, background, probe);
        }
        sum /= static_cast<float>(spp);
        image.set(x, y, {linear_to_srgb(sum.x()), linear_to_srgb(sum.y()), linear_to_srgb(sum.z())});
      }
    }
  });
  return image;
}

// The deposit's surface, after the checks both colourings share.
SurfaceMesh checked_surface(const sim::Deposit& deposit) {
  if (!deposit.fill) throw InputError("nothing was deposited: the deposit has no fill grid");
  BT_CHECK(deposit.layer != nullptr);
  return extract_surface(*deposit.fill, kSurfaceFill);
}

}  // namespace

Image render_deposit(const sim::Deposit& deposit, const LayerColour& colour, const RenderOptions& options) {
  validate(options);
  BT_CHECK(static_cast<bool>(colour));
  const SurfaceMesh mesh = checked_surface(deposit);
  const Palette palette(*deposit.layer, colour, options.unknown_layer);
  return render_surface(deposit, *deposit.layer, mesh, Albedo(palette), options);
}

Image render_deposit(const sim::Deposit& deposit, const openvdb::Int32Grid& labels, const LayerColour& colour,
                     const RenderOptions& options) {
  validate(options);
  BT_CHECK(static_cast<bool>(colour));
  const SurfaceMesh mesh = checked_surface(deposit);
  const Palette palette(labels, colour, options.unknown_layer);
  return render_surface(deposit, labels, mesh, Albedo(palette), options);
}

Image render_deposit(const sim::Deposit& deposit, const SurfaceColour& colour, const RenderOptions& options) {
  validate(options);
  BT_CHECK(static_cast<bool>(colour));
  const SurfaceMesh mesh = checked_surface(deposit);
  return render_surface(deposit, *deposit.layer, mesh, Albedo(colour), options);
}

}  // namespace beadtwin::render
