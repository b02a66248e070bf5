// The render stage's shading, sample by sample (render.cpp drives it pixel by pixel): the colour of the
// material under a surface point, the light rig, and a Shader that turns one camera sample into the shadow
// and ambient occlusion rays it needs and, once they are traced, into radiance.
//
// Every sample pattern is a pure function of the pixel and the sample's index, so a picture does not depend
// on the order in which threads take its pixels. Internal to the render library: inline, because the
// renderer calls these once or more per sample.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <openvdb/tools/Interpolation.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/error.hpp"
#include "core/units.hpp"
#include "render/camera.hpp"
#include "render/render.hpp"
#include "render/sampling.hpp"
#include "render/surface.hpp"
#include "sim/embree.hpp"

namespace beadtwin::render::shading {

using Vec3 = Eigen::Vector3f;

inline constexpr long kMaxLayers = 1L << 24;  // a palette's span of layer indices

// A display sRGB colour in linear light.
inline Vec3 to_linear(Rgb c) {
  return {srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b)};
}

// Colours of the layers present in the deposit, in linear light, looked up by index while rendering.
class Palette {
 public:
  Palette(const openvdb::Int32Grid& layers, const LayerColour& colour, Rgb unknown)
      : unknown_(to_linear(unknown)) {
    int lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
    for_each_active(layers, [&](int value) {
      if (value < 0) return;
      lo = std::min(lo, value);
      hi = std::max(hi, value);
    });
    if (lo > hi) return;  // no layer known anywhere: everything is drawn in the unknown colour
    if (static_cast<long>(hi) - lo + 1 > kMaxLayers)
      throw InputError({}, "deposit.layer",
                       "layer indices span " + std::to_string(lo) + ".." + std::to_string(hi) +
                           ", more than " + std::to_string(kMaxLayers) + " layers");
    first_ = lo;
    std::vector<char> present(static_cast<std::size_t>(hi - lo + 1), 0);
    for_each_active(layers, [&](int value) {
      if (value >= 0) present[static_cast<std::size_t>(value - lo)] = 1;
    });
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
  // Calls `f` with every active value of `grid`: leaf by leaf, then the active tiles above the leaves.
  // The tree's value iterator visits the same values several times slower, and a deposit holds millions.
  template <class F>
  static void for_each_active(const openvdb::Int32Grid& grid, F&& f) {
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf)
      for (auto it = leaf->cbeginValueOn(); it; ++it) f(*it);
    auto tiles = grid.cbeginValueOn();
    tiles.setMaxDepth(openvdb::Int32Tree::DEPTH - 2);  // stop above the leaves' voxels
    for (; tiles; ++tiles) f(*tiles);
  }

  int first_ = 0;
  std::vector<Vec3> colours_;
  Vec3 unknown_;
};

// A field's values in linear light, through its colour function (display sRGB), the last value's colour kept
// (by its bits, so that NaN is a value too): the samples of a pixel, and the pixels along a bead, mostly show
// the same voxel's value, and the colour function and the sRGB decoding are a large part of a sample's
// cost. One per thread.
class ValueColours {
 public:
  explicit ValueColours(const std::function<Rgb(double)>& colour) : colour_(colour) {}

  const Vec3& operator()(double value) {
    const auto bits = std::bit_cast<std::uint64_t>(value);
    if (!has_last_ || last_bits_ != bits) {
      last_ = to_linear(colour_(value));
      last_bits_ = bits;
      has_last_ = true;
    }
    return last_;
  }

 private:
  const std::function<Rgb(double)>& colour_;
  bool has_last_ = false;
  std::uint64_t last_bits_ = 0;
  Vec3 last_ = Vec3::Zero();
};

// What lies under surface points, for one thread: the label (layer or cell) and the field's value.
struct Probes {
  LayerProbe labels;
  std::optional<FieldProbe> field;
  std::optional<ValueColours> colours;  // the field's

  Probes(const openvdb::Int32Grid& label_grid, const SurfaceField* surface_field) : labels(label_grid) {
    if (surface_field == nullptr) return;
    if (surface_field->voxels != nullptr) field.emplace(*surface_field->voxels);
    colours.emplace(surface_field->colour);
  }
};

// The colour of a surface point, in linear light, and the value it shows: its label's colour from the
// palette made up front (the value is the label), the caller's colour of the point (no value), or a field's
// value and its colour.
class Albedo {
 public:
  explicit Albedo(const Palette& palette) : palette_(&palette) {}
  explicit Albedo(const SurfaceColour& colour) : colour_(&colour) {}
  explicit Albedo(const SurfaceField& field) : field_(&field) {}

  const SurfaceField* field() const { return field_; }

  // `inward`: the unit direction into the material at `point`.
  Vec3 operator()(const Vec3& point, const Vec3& inward, Probes& probes, float& value) const {
    if (field_) {
      const double v = field_->voxels ? static_cast<double>(probes.field->value_at(point, inward))
                                      : field_->at_point(point.cast<double>());
      value = static_cast<float>(v);
      return (*probes.colours)(v);
    }
    const int label = probes.labels.layer_at(point, inward);
    if (colour_) {
      value = std::numeric_limits<float>::quiet_NaN();
      return to_linear((*colour_)(point.cast<double>(), label));
    }
    value = label >= 0 ? static_cast<float>(label) : std::numeric_limits<float>::quiet_NaN();
    return (*palette_)(label);
  }

 private:
  const Palette* palette_ = nullptr;
  const SurfaceColour* colour_ = nullptr;
  const SurfaceField* field_ = nullptr;
};

// The kept half of a cutaway (RenderOptions::cut): where a ray runs in it, and whether the cut face is
// material at a point (the fill there at least half).
class CutPlane {
 public:
  CutPlane(const Cutaway& cut, const openvdb::FloatGrid& fill)
      : point_(cut.point), normal_(cut.normal.normalized()), fill_(fill) {}

  const Vec3& normal() const { return normal_; }  // into the half taken away

  // The part of the ray from `origin` along unit `direction` (t in [0, length]) in the kept half, as
  // [near, far]; near > far when none of it is.
  std::pair<float, float> kept(const Vec3& origin, const Vec3& direction, float length) const {
    const float s0 = normal_.dot(origin - point_), rate = normal_.dot(direction);
    if (rate == 0.0f) return s0 <= 0.0f ? std::pair{0.0f, length} : std::pair{1.0f, 0.0f};
    const float t = -s0 / rate;
    if (rate > 0.0f) return {0.0f, std::min(length, t)};  // leaving the kept half at t
    return {std::max(0.0f, t), length};                   // entering it at t
  }

  // The fill at `point` (world, mm), trilinear between voxel centres.
  float fill_at(const Vec3& point, openvdb::FloatGrid::ConstUnsafeAccessor& accessor) const {
    const openvdb::Vec3d index =
        fill_.transform().worldToIndex(openvdb::Vec3d(point.x(), point.y(), point.z()));
    return openvdb::tools::BoxSampler::sample(accessor, index);
  }

 private:
  Vec3 point_, normal_;
  const openvdb::FloatGrid& fill_;
};

// --- Sample patterns ---

// A stratified pattern of `count` points in the unit square (correlated multi-jittered, sampling.hpp),
// made once per picture and shared by every pixel, each shifting it by an offset of its own, wrapping round
// (a Cranley-Patterson rotation): the points stay one to a stratum, and a sample costs an addition instead of
// the permutations of a pattern of its own.
class SharedPattern {
 public:
  SharedPattern(std::uint32_t count, std::uint32_t seed) {
    points_.reserve(count);
    for (std::uint32_t i = 0; i < count; ++i) points_.push_back(cmj_sample(i, count, seed));
  }
  Eigen::Vector2f at(std::uint32_t i, const Eigen::Vector2f& shift) const {
    Eigen::Vector2f p = points_[i] + shift;
    if (p.x() >= 1.0f) p.x() -= 1.0f;
    if (p.y() >= 1.0f) p.y() -= 1.0f;
    return p;
  }

 private:
  std::vector<Eigen::Vector2f> points_;
};

// The sample patterns of a picture: where in the pixel, where on the key light's disc, and which
// directions of the hemisphere for occlusion. Each has its own pattern, so the dimensions are not
// correlated (every sample jittered left seeing the same side of the light), and each is stratified across a
// pixel's samples, so the penumbra and the occlusion converge as fast as the edges do.
struct Patterns {
  SharedPattern pixel, light, occlusion;

  Patterns(std::uint32_t samples, std::uint32_t occlusion_rays)
      : pixel(samples, 0x3c6ef372u),
        light(samples, 0xa54ff53au),
        occlusion(samples * occlusion_rays, 0x510e527fu) {}
};

// One pixel's offsets of the shared patterns, a pure function of its position.
struct PixelShifts {
  Eigen::Vector2f pixel, light, occlusion;

  PixelShifts(int x, int y) {
    const std::uint32_t seed = pixel_seed(x, y);
    pixel = {hash_float(0u, seed), hash_float(1u, seed)};
    light = {hash_float(2u, seed), hash_float(3u, seed)};
    occlusion = {hash_float(4u, seed), hash_float(5u, seed)};
  }
};

// Sample `index` of a pixel: its point on the key light and its occlusion rays' points.
struct SampleIndex {
  const Patterns& patterns;
  const PixelShifts& shifts;
  std::uint32_t index;

  Eigen::Vector2f light() const { return patterns.light.at(index, shifts.light); }
  // Occlusion ray k of n for this sample: the pixel's samples * n rays are stratified together.
  Eigen::Vector2f occlusion(std::uint32_t k, std::uint32_t n) const {
    return patterns.occlusion.at(index * n + k, shifts.occlusion);
  }
};

// The unit square onto the unit disc, keeping strata compact (P. Shirley and K. Chiu, "A low distortion map
// between disk and square", Journal of Graphics Tools 2(3), 1997).
inline Eigen::Vector2f concentric_disc(const Eigen::Vector2f& u) {
  const float a = 2.0f * u.x() - 1.0f, b = 2.0f * u.y() - 1.0f;
  if (a == 0.0f && b == 0.0f) return Eigen::Vector2f::Zero();
  constexpr float kQuarterPi = 0.785398163f;
  float r = 0.0f, phi = 0.0f;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = kQuarterPi * (b / a);
  } else {
    r = b;
    phi = 2.0f * kQuarterPi - kQuarterPi * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

// x^n for a whole n >= 0, by repeated squaring: a few multiplications where std::pow, once a sample, is a
// measurable part of a run's CPU time.
inline float whole_power(float x, int n) {
  float result = 1.0f;
  for (; n > 0; n >>= 1, x *= x)
    if (n & 1) result *= x;
  return result;
}

// Two unit vectors completing unit `n` to an orthonormal basis, without a branch on its direction (T. Duff
// et al., "Building an orthonormal basis, revisited", JCGT 6(1), 2017).
inline void complete_basis(const Vec3& n, Vec3& t, Vec3& b) {
  const float sign = std::copysign(1.0f, n.z());
  const float a = -1.0f / (sign + n.z());
  const float c = n.x() * n.y() * a;
  t = Vec3(1.0f + sign * n.x() * n.x() * a, sign * c, -sign * n.x());
  b = Vec3(c, sign + n.y() * n.y() * a, -n.y());
}

// --- Rays ---

// Ray `lane` of a packet: from `origin` along `direction`, up to `tfar` lengths of it.
inline void set_lane(RTCRay16& rays, int lane, const Vec3& origin, const Vec3& direction, float tfar) {
  rays.org_x[lane] = origin.x();
  rays.org_y[lane] = origin.y();
  rays.org_z[lane] = origin.z();
  rays.dir_x[lane] = direction.x();
  rays.dir_y[lane] = direction.y();
  rays.dir_z[lane] = direction.z();
  rays.tnear[lane] = 0.0f;
  rays.tfar[lane] = tfar;
  rays.time[lane] = 0.0f;
  rays.mask[lane] = 0xffffffffu;
  rays.id[lane] = 0;
  rays.flags[lane] = 0;
}

// Occlusion rays gathered from one pixel's samples and traced together, sixteen at a time.
class OcclusionBatch {
 public:
  static constexpr int kLanes = 16;

  // Queues a ray from `origin` along unit `direction`, up to `length` mm; returns its index.
  int add(const Vec3& origin, const Vec3& direction, float length) {
    const std::size_t packet = size_ / kLanes;
    const int lane = static_cast<int>(size_ % kLanes);
    if (packet == packets_.size()) packets_.emplace_back();
    set_lane(packets_[packet], lane, origin, direction, length);
    return static_cast<int>(size_++);
  }
  void trace(const embree::Scene& scene, bool coherent) {
    for (std::size_t p = 0; p * kLanes < size_; ++p) {
      alignas(64) int valid[kLanes];
      for (int lane = 0; lane < kLanes; ++lane) valid[lane] = p * kLanes + lane < size_ ? -1 : 0;
      scene.occluded16(valid, packets_[p], coherent);
    }
  }
  bool occluded(int ray) const {
    return packets_[static_cast<std::size_t>(ray) / kLanes].tfar[ray % kLanes] < 0.0f;
  }
  std::size_t size() const { return size_; }
  void clear() { size_ = 0; }

 private:
  std::vector<RTCRay16> packets_;  // kept between pixels: no allocation once warm
  std::size_t size_ = 0;
};

// Where a camera ray met the surface, as Embree reports it.
struct CameraHit {
  bool hit = false;
  float t = 0.0f;    // along the ray, mm
  Vec3 face_normal;  // geometric, not normalised
  std::uint32_t triangle = 0;
  float u = 0.0f, v = 0.0f;  // barycentric
  bool cap = false;          // the cut face of a cutaway (face_normal is the plane's), not a triangle
};

// --- Shading ---

// Light rig, in linear light. Set relative to the camera, so every view is lit alike: the key comes from
// the upper left, from in front of the part (behind the viewer), so the three faces of a box seen in the
// isometric view get three distinct tones (top brightest, left, right darkest) and no face is left black.
// The sky and ground carry about 40 % of a lit face's light, so that ambient occlusion, which takes only
// from them, visibly darkens grooves and inside corners.
struct Lights {
  Vec3 to_key;                       // unit direction towards the key light's centre
  Vec3 key_u, key_v;                 // across the key light's disc, scaled by `spread`
  float spread = 0.0f;               // the tangent of the key light's angular radius
  Vec3 key{0.68f, 0.66f, 0.63f};     // slightly warm
  Vec3 sky{0.46f, 0.48f, 0.53f};     // ambient from above, slightly cool...
  Vec3 ground{0.20f, 0.19f, 0.18f};  // ...and from below
  float rim = 0.30f;                 // strength of the grazing-angle rim light
  float specular = 0.08f;            // strength of a soft highlight from the key
  int shininess = 24;  // the highlight's exponent: a whole number, taken by repeated squaring (no powf)
  float ground_shadow = 0.30f;  // fraction of the background's light the part's shadow takes

  Lights(const Camera& camera, double key_radius_deg)
      : to_key((-0.34f * camera.right() + 0.35f * camera.up() - 0.87f * camera.forward()).normalized()) {
    complete_basis(to_key, key_u, key_v);
    spread = static_cast<float>(std::tan(key_radius_deg * kPi / 180.0));
    key_u *= spread;
    key_v *= spread;
  }

  // A direction towards a point of the key light's disc, for a sample `u` of the unit square.
  Vec3 towards_key(const Eigen::Vector2f& u) const {
    const Eigen::Vector2f d = concentric_disc(u);
    return (to_key + d.x() * key_u + d.y() * key_v).normalized();
  }
};

// One camera sample: what its ray found, and the indices of the occlusion rays it asked for.
struct Sample {
  bool on_part = false;
  // On the part:
  Vec3 point, geometric, normal;  // the normals face the viewer; geometric is the facet's
  Vec3 to_eye;
  float t = 0.0f;                                   // along the camera ray, mm
  float key_lit = 0.0f;                             // the key's visibility when no shadow ray decides it
  int shadow_ray = -1;                              // in the shadow batch (on the part or on the bed), or -1
  int first_occlusion_ray = 0, occlusion_rays = 0;  // in the occlusion batch
};

// The light a sample on the part sends towards the eye, in two shares: radiance = albedo ⊙ tinted +
// untinted, where albedo is the colour of the material there (linear). Apart, the light of a picture's
// samples can be kept and the picture coloured by another field later (TracedPicture).
struct SampleLight {
  Vec3 tinted = Vec3::Zero();  // what the surface's colour filters: the key, sky and ground, most of the rim
  float untinted = 0.0f;       // what it does not: the highlight and the rim's white share

  Vec3 radiance(const Vec3& albedo) const { return albedo.cwiseProduct(tinted) + Vec3::Constant(untinted); }
};

// Shades camera samples in two steps, so that the rays of many samples can be traced together: begin()
// finds what a camera ray met and queues the shadow and occlusion rays the sample needs; once the caller
// has traced those, finish() (on the part) or background_share() (off it) gives its light.
class Shader {
 public:
  // `offset_mm`: shadow and occlusion rays start this far off the surface, against self-intersection;
  // `occlusion_distance_mm`: how far an occluder darkens (RenderOptions::ambient_occlusion_distance_mm).
  Shader(const embree::Scene& scene, const SurfaceMesh& mesh, const Lights& lights,
         const RenderOptions& options, float offset_mm, float occlusion_distance_mm,
         const CutPlane* cut = nullptr)
      : cut_(cut),
        scene_(scene),
        mesh_(mesh),
        lights_(lights),
        shadows_(options.shadows),
        ground_shadow_(options.ground_shadow),
        occlusion_rays_(
            options.ambient_occlusion ? static_cast<std::uint32_t>(options.ambient_occlusion_samples) : 0u),
        ground_z_(mesh.bounds.min().z()),
        offset_(offset_mm),
        occlusion_distance_(occlusion_distance_mm),
        caster_(mesh.bounds.min() - Vec3::Constant(offset_mm), mesh.bounds.max() + Vec3::Constant(offset_mm)),
        caster_radius_(0.5f * caster_.diagonal().norm()) {}

  const embree::Scene& scene() const { return scene_; }
  const CutPlane* cut() const { return cut_; }

  // The sample of a camera `ray` and its `hit`: the surface point, or the background, with the shadow and
  // occlusion rays it needs queued in `shadow` and `occlusion`.
  Sample begin(const Ray& ray, const CameraHit& hit, const SampleIndex& index, OcclusionBatch& shadow,
               OcclusionBatch& occlusion) const {
    Sample s;
    if (!hit.hit) {
      queue_ground_shadow(ray, index, s, shadow);
      return s;
    }
    s.on_part = true;
    s.point = ray.origin + hit.t * ray.direction;
    s.geometric = hit.face_normal.normalized();
    if (s.geometric.dot(ray.direction) > 0.0f) s.geometric = -s.geometric;  // face the viewer
    s.normal = hit.cap ? s.geometric : shading_normal(hit, s.geometric);
    s.t = hit.t;
    s.to_eye = -ray.direction;
    const Vec3 origin = s.point + offset_ * s.geometric;

    if (s.normal.dot(lights_.to_key) > 0.0f) {
      // A point of the light behind the facet is hidden by the surface itself: no ray needed. The same
      // point is sampled with shadows off, so shadows can only take light away.
      const Vec3 to_light = lights_.towards_key(index.light());
      if (s.geometric.dot(to_light) > 0.0f) {
        const float length = clip_length(origin, to_light, std::numeric_limits<float>::infinity());
        if (shadows_ && length > 0.0f)
          s.shadow_ray = shadow.add(origin, to_light, length);
        else
          s.key_lit = 1.0f;
      }
    }
    s.first_occlusion_ray = static_cast<int>(occlusion.size());
    s.occlusion_rays = static_cast<int>(occlusion_rays_);
    if (occlusion_rays_ > 0) {
      Vec3 t, b;
      complete_basis(s.normal, t, b);
      for (std::uint32_t k = 0; k < occlusion_rays_; ++k) {
        // Cosine-weighted about the shading normal; a direction below the facet (the shading normal leans
        // off it) is mirrored above it, so the facets of the voxel surface do not show as occlusion.
        const Eigen::Vector2f d = concentric_disc(index.occlusion(k, occlusion_rays_));
        const float z = std::sqrt(std::max(0.0f, 1.0f - d.squaredNorm()));
        Vec3 direction = d.x() * t + d.y() * b + z * s.normal;
        const float below = direction.dot(s.geometric);
        if (below < 0.0f) direction -= 2.0f * below * s.geometric;
        occlusion.add(origin, direction, std::max(0.0f, clip_length(origin, direction, occlusion_distance_)));
      }
    }
    return s;
  }

  // The share of the background's radiance a sample off the part sees (1 unless the part's shadow falls
  // on it), once its shadow ray is traced.
  float background_share(const Sample& s, const OcclusionBatch& shadow) const {
    return s.shadow_ray >= 0 && shadow.occluded(s.shadow_ray) ? 1.0f - lights_.ground_shadow : 1.0f;
  }

  // The light of a sample on the part, once its shadow and occlusion rays are traced.
  SampleLight finish(const Sample& s, const OcclusionBatch& shadow, const OcclusionBatch& occlusion) const {
    const bool shadowed = s.shadow_ray >= 0 && shadow.occluded(s.shadow_ray);
    const float key = s.shadow_ray >= 0 ? (shadowed ? 0.0f : 1.0f) : s.key_lit;
    float open = 1.0f;
    if (s.occlusion_rays > 0) {
      int blocked = 0;
      for (int k = 0; k < s.occlusion_rays; ++k)
        blocked += occlusion.occluded(s.first_occlusion_ray + k) ? 1 : 0;
      open = 1.0f - static_cast<float>(blocked) / static_cast<float>(s.occlusion_rays);
    }
    return light(s, key, open);
  }

  // The light leaving a surface point towards the eye, given how much of the key light reaches it (0..1)
  // and what fraction of the sky and ground (0..1) its surroundings leave open.
  SampleLight light(const Sample& s, float key, float open) const {
    const float hemisphere = 0.5f + 0.5f * s.normal.z();  // machine frame: z up
    Vec3 diffuse = open * (lights_.ground + hemisphere * (lights_.sky - lights_.ground));
    const float lambert = s.normal.dot(lights_.to_key);
    float highlight = 0.0f;
    if (lambert > 0.0f && key > 0.0f) {
      diffuse += key * lambert * lights_.key;
      const Vec3 half = (lights_.to_key + s.to_eye).normalized();
      highlight = key * lights_.specular * whole_power(std::max(0.0f, s.normal.dot(half)), lights_.shininess);
    }
    const float facing = 1.0f - std::clamp(s.normal.dot(s.to_eye), 0.0f, 1.0f);
    const float rim = lights_.rim * (facing * facing) * (facing * facing);
    return {diffuse + Vec3::Constant(0.6f * rim), highlight + 0.4f * rim};  // the rim: 0.6 tinted, 0.4 white
  }

 private:
  // Interpolated vertex normal, on the viewer's side like the face: smooth light across the facets of the
  // voxel isosurface, which are an artefact of the grid, not the part.
  Vec3 shading_normal(const CameraHit& hit, const Vec3& geometric) const {
    const auto& t = mesh_.triangles[hit.triangle];
    Vec3 n = (1.0f - hit.u - hit.v) * mesh_.normals[t[0]] + hit.u * mesh_.normals[t[1]] +
             hit.v * mesh_.normals[t[2]];
    if (n.dot(geometric) < 0.0f) n = -n;
    const float length = n.norm();
    return length > 1e-6f ? Vec3(n / length) : geometric;
  }

  // The part's shadow on the bed it stands on (the plane through its lowest point), where the ray meets
  // the bed: it grounds the part, and in the top view it shows the walls' height. Only points whose ray
  // towards the light passes the part's box can be in its shadow; the others need no ray.
  void queue_ground_shadow(const Ray& ray, const SampleIndex& index, Sample& s,
                           OcclusionBatch& shadow) const {
    if (!ground_shadow_ || ray.direction.z() > -1e-4f) return;
    const float t = (ground_z_ - ray.origin.z()) / ray.direction.z();
    if (t <= 0.0f) return;
    const Vec3 bed = ray.origin + t * ray.direction + offset_ * Vec3::UnitZ();
    // Most of the bed is far from the part's shadow: a ray towards any point of the light meets the part's
    // box only if the ray towards the light's centre meets the box grown by the light's spread at the
    // box's far side. Tested first, it saves sampling the light for most of the background.
    const float reach = (bed - caster_.center()).norm() + caster_radius_;
    if (!meets_box(bed, lights_.to_key, reach * lights_.spread)) return;
    const Vec3 to_light = lights_.towards_key(index.light());
    const float length = clip_length(bed, to_light, std::numeric_limits<float>::infinity());
    if (length > 0.0f && meets_box(bed, to_light, 0.0f)) s.shadow_ray = shadow.add(bed, to_light, length);
  }

  // How far a ray from `origin` along `direction` may look for what hides it, at most `length`: with a
  // cutaway, only as far as the cutting plane (what lies beyond is taken away); <= 0 when it starts there.
  float clip_length(const Vec3& origin, const Vec3& direction, float length) const {
    if (!cut_) return length;
    const auto [near, far] = cut_->kept(origin, direction, length);
    return near > 0.0f || near > far ? 0.0f : far;
  }

  // Whether the ray from `origin` along `direction` meets the part's bounding box grown by `margin` mm
  // (slab test).
  bool meets_box(const Vec3& origin, const Vec3& direction, float margin) const {
    float near = 0.0f, far = std::numeric_limits<float>::infinity();
    for (int i = 0; i < 3; ++i) {
      const float inverse = 1.0f / direction[i];  // +-inf along an axis-parallel direction: still correct
      float a = (caster_.min()[i] - margin - origin[i]) * inverse;
      float b = (caster_.max()[i] + margin - origin[i]) * inverse;
      if (a > b) std::swap(a, b);
      near = std::max(near, a);
      far = std::min(far, b);
    }
    return near <= far;
  }

  const CutPlane* cut_;
  const embree::Scene& scene_;
  const SurfaceMesh& mesh_;
  const Lights& lights_;
  bool shadows_;
  bool ground_shadow_;
  std::uint32_t occlusion_rays_;
  float ground_z_;
  float offset_;
  float occlusion_distance_;
  Eigen::AlignedBox3f caster_;  // the part's box, grown by the offset
  float caster_radius_;         // half its diagonal
};

}  // namespace beadtwin::render::shading
