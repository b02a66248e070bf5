#include "sim/embree.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace beadtwin::embree {
namespace {

// One triangle in the plane z = 5 covering (0,0)-(10,0)-(0,10).
Scene triangle_scene(const Device& device) {
  Geometry geometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto v = geometry.new_buffer<std::array<float, 3>>(RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3);
  v[0] = {0, 0, 5};
  v[1] = {10, 0, 5};
  v[2] = {0, 10, 5};
  auto t = geometry.new_buffer<std::array<unsigned, 3>>(RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 1);
  t[0] = {0, 1, 2};
  geometry.commit();
  Scene scene(device);
  scene.attach(geometry);
  scene.commit();
  return scene;  // the scene holds its own reference to the geometry and the device
}

RTCRayHit down_from(float x, float y) {
  RTCRayHit rh{};
  rh.ray.org_x = x;
  rh.ray.org_y = y;
  rh.ray.org_z = 20;
  rh.ray.dir_z = -1;
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.mask = 0xffffffffu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

TEST(Embree, IntersectsAndOccludes) {
  const Device device;
  const Scene scene = triangle_scene(device);
  RTCRayHit hit = down_from(2, 2);
  scene.intersect(hit);
  ASSERT_NE(hit.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_NEAR(hit.ray.tfar, 15.0f, 1e-5f);
  RTCRayHit miss = down_from(8, 8);
  scene.intersect(miss);
  EXPECT_EQ(miss.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  RTCRayHit blocked = down_from(2, 2), open = down_from(8, 8);
  EXPECT_TRUE(scene.occluded(blocked.ray));
  EXPECT_FALSE(scene.occluded(open.ray));
}

// The primitives a point query visits.
bool record_visit(RTCPointQueryFunctionArguments* args) {
  static_cast<std::vector<unsigned>*>(args->userPtr)->push_back(args->primID);
  return false;
}

TEST(Embree, PointQueriesVisitWhatTheSphereReaches) {
  // 400 small triangles (1 mm) in the plane z = 0, 10 mm apart.
  const Device device;
  Geometry geometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  constexpr unsigned kSide = 20;
  auto v = geometry.new_buffer<std::array<float, 3>>(RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                     3 * kSide * kSide);
  auto t =
      geometry.new_buffer<std::array<unsigned, 3>>(RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, kSide * kSide);
  for (unsigned i = 0; i < kSide * kSide; ++i) {
    const auto x = static_cast<float>(10 * (i % kSide)), y = static_cast<float>(10 * (i / kSide));
    v[3 * i] = {x, y, 0};
    v[3 * i + 1] = {x + 1, y, 0};
    v[3 * i + 2] = {x, y + 1, 0};
    t[i] = {3 * i, 3 * i + 1, 3 * i + 2};
  }
  geometry.commit();
  Scene scene(device);
  scene.attach(geometry);
  scene.commit();
  const auto visits = [&](float z, float radius) {
    RTCPointQuery q{};
    q.x = 50.2f;  // over triangle 5 + 20 · 7
    q.y = 70.2f;
    q.z = z;
    q.radius = radius;
    std::vector<unsigned> primitives;
    scene.point_query(q, &record_visit, &primitives);
    std::sort(primitives.begin(), primitives.end());
    return primitives;
  };
  // 3 above its triangle: reached by a sphere of radius 4, with at most a few neighbours whose boxes share
  // a node with it (Embree prunes by bounding boxes); 25 above, or reached by no sphere, none.
  const std::vector<unsigned> near = visits(3, 4);
  EXPECT_TRUE(std::binary_search(near.begin(), near.end(), 5 + kSide * 7));
  EXPECT_LE(near.size(), 8u);
  EXPECT_TRUE(visits(25, 4).empty());
  EXPECT_EQ(visits(3, 1000).size(), kSide * kSide);
}

TEST(Embree, PacketsAgreeWithSingleRays) {
  const Device device;
  const Scene scene = triangle_scene(device);
  alignas(64) int valid[16];
  RTCRayHit16 hits{};
  RTCRay16 shadows{};
  for (int i = 0; i < 16; ++i) {
    valid[i] = i < 12 ? -1 : 0;  // the last four lanes are left alone; x >= 9 misses the triangle
    const RTCRayHit single = down_from(static_cast<float>(i), 1.5f);
    for (RTCRay16* rays : {&hits.ray, &shadows}) {
      rays->org_x[i] = single.ray.org_x;
      rays->org_y[i] = single.ray.org_y;
      rays->org_z[i] = single.ray.org_z;
      rays->dir_z[i] = single.ray.dir_z;
      rays->tfar[i] = single.ray.tfar;
      rays->mask[i] = single.ray.mask;
    }
    hits.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
  }
  scene.intersect16(valid, hits, /*coherent=*/true);
  scene.occluded16(valid, shadows, /*coherent=*/false);
  for (int i = 0; i < 16; ++i) {
    RTCRayHit single = down_from(static_cast<float>(i), 1.5f);
    scene.intersect(single);
    const bool hit = single.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    if (i >= 12) {
      EXPECT_EQ(hits.hit.geomID[i], RTC_INVALID_GEOMETRY_ID) << i;
      EXPECT_EQ(shadows.tfar[i], std::numeric_limits<float>::infinity()) << i;
      continue;
    }
    EXPECT_EQ(hits.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID, hit) << i;
    EXPECT_EQ(shadows.tfar[i] < 0.0f, hit) << i;
    if (hit) {
      EXPECT_NEAR(hits.ray.tfar[i], single.ray.tfar, 1e-5f) << i;
    }
  }
}

TEST(Embree, ErrorsBecomeExceptionsNamingTheCall) {
  const Device device;
  Geometry geometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  try {
    // Triangle meshes have one index buffer, slot 0.
    geometry.new_buffer<std::array<unsigned, 3>>(RTC_BUFFER_TYPE_INDEX, 7, RTC_FORMAT_UINT3, 1);
    FAIL() << "Embree accepted index buffer slot 7";
  } catch (const InternalError& e) {
    EXPECT_NE(std::string(e.what()).find("rtcSetNewGeometryBuffer"), std::string::npos) << e.what();
  }
  // The error was consumed: the next good call does not throw it again.
  EXPECT_NO_THROW(device.check("nothing"));
  EXPECT_NO_THROW(triangle_scene(device));
}

TEST(Embree, HandlesMoveAndOutliveEachOther) {
  Scene scene = [] {
    Device device;  // released before the scene: Embree keeps it alive, and so does the error slot
    Device moved = std::move(device);
    return triangle_scene(moved);
  }();
  Scene other = std::move(scene);
  RTCRayHit hit = down_from(1, 1);
  other.intersect(hit);
  EXPECT_NE(hit.hit.geomID, RTC_INVALID_GEOMETRY_ID);
}

}  // namespace
}  // namespace beadtwin::embree
