// Embree 3, wrapped once: RAII handles for a device, a scene and a geometry. The renderer
// traces rays with it; the comparison with the CAD asks it for nearest points (sim/nearest_triangles.hpp).
//
// The Device installs an error callback when it is created. Embree calls it on the thread whose call
// failed; the callback records the error and the wrapper function that made the call throws it, as an
// InternalError naming the call (an Embree error here is a bug of ours, an unsupported CPU or a lack of
// memory, never the user's input). Throwing from inside the callback itself would unwind through Embree's
// frames, which its C API does not promise to survive, hence record-then-throw.
//
// Ray and point queries (intersect, occluded, point_query) are not checked: Embree validates their arguments
// only in its debug builds, so they stay inline and cheap. They are thread-safe once the scene is committed.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string_view>

#include <embree3/rtcore.h>

namespace beadtwin::embree {

// Errors reported by the callback, shared by the device and everything made from it, so the callback's
// target lives as long as any handle that can trigger it.
struct ErrorSlot;

// An Embree device, with the error callback installed.
class Device {
 public:
  // `config` is Embree's device configuration string ("" for the defaults; "verbose=1" etc.).
  explicit Device(const char* config = "");
  ~Device();
  Device(Device&& other) noexcept;
  Device& operator=(Device&& other) noexcept;
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  RTCDevice get() const { return device_; }
  // Throws the error recorded since the last check, naming `call`; does nothing if there is none.
  void check(std::string_view call) const;
  const std::shared_ptr<ErrorSlot>& errors() const { return errors_; }

 private:
  RTCDevice device_ = nullptr;
  std::shared_ptr<ErrorSlot> errors_;
};

// A geometry of `type` (triangles, quads, user primitives) on a device: fill its buffers, commit it, attach
// it to a scene.
class Geometry {
 public:
  Geometry(const Device& device, RTCGeometryType type);
  ~Geometry();
  Geometry(Geometry&& other) noexcept;
  Geometry& operator=(Geometry&& other) noexcept;
  Geometry(const Geometry&) = delete;
  Geometry& operator=(const Geometry&) = delete;

  // A buffer of `count` items of type T, owned by Embree (and padded as Embree needs), bound to `type`
  // slot `slot` in `format`. Fill it before commit().
  template <class T>
  std::span<T> new_buffer(RTCBufferType type, unsigned slot, RTCFormat format, std::size_t count) {
    return {static_cast<T*>(new_buffer_bytes(type, slot, format, sizeof(T), count)), count};
  }
  void commit();

  RTCGeometry get() const { return geometry_; }

 private:
  void* new_buffer_bytes(RTCBufferType type, unsigned slot, RTCFormat format, std::size_t stride,
                         std::size_t count);

  RTCGeometry geometry_ = nullptr;
  std::shared_ptr<ErrorSlot> errors_;
};

// A scene: committed geometries and the acceleration structure built over them for rays and point queries.
class Scene {
 public:
  explicit Scene(const Device& device);
  ~Scene();
  Scene(Scene&& other) noexcept;
  Scene& operator=(Scene&& other) noexcept;
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  void set_flags(RTCSceneFlags flags);
  void set_build_quality(RTCBuildQuality quality);
  // Attaches a committed geometry (the scene keeps its own reference) and returns its id.
  unsigned attach(const Geometry& geometry);
  // Builds the acceleration structure (in parallel, on the caller's TBB arena).
  void commit();

  RTCScene get() const { return scene_; }

  // Closest hit along `rayhit.ray`; rayhit.hit.geomID stays RTC_INVALID_GEOMETRY_ID on a miss.
  void intersect(RTCRayHit& rayhit) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(scene_, &context, &rayhit);
  }
  // Whether anything lies along `ray` between tnear and tfar.
  bool occluded(RTCRay& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcOccluded1(scene_, &context, &ray);
    return ray.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
  }
  // Packets of 16 rays, traced together (fastest for rays that start close together and run alike, such
  // as one pixel's camera rays). `valid[i]` is -1 for a ray to trace, 0 to leave alone. `coherent` tells
  // Embree the rays run alike. intersect16 fills the hits as intersect does; occluded16 sets the tfar of
  // every occluded ray to -inf.
  void intersect16(const int* valid, RTCRayHit16& rayhits, bool coherent) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    if (coherent) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    rtcIntersect16(valid, scene_, &context, &rayhits);
  }
  void occluded16(const int* valid, RTCRay16& rays, bool coherent) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    if (coherent) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    rtcOccluded16(valid, scene_, &context, &rays);
  }
  // Calls `visit` for every primitive within query.radius of the query's point, and maybe a few more (Embree
  // prunes by bounding boxes: `visit` measures). `visit` returns true when it has shrunk the radius
  // (args->query->radius), so that the traversal prunes with it; the caller's `query` is left as it was.
  void point_query(RTCPointQuery& query, RTCPointQueryFunction visit, void* user) const {
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(scene_, &query, &context, visit, user);
  }

 private:
  RTCScene scene_ = nullptr;
  std::shared_ptr<ErrorSlot> errors_;
};

}  // namespace beadtwin::embree
