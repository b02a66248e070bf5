#include "sim/nearest_triangles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

namespace beadtwin::sim {

using Vec3 = Eigen::Vector3d;

ClosestPoint closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {a, 0};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {b, 1};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return {a + d1 / (d1 - d3) * ab};
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {c, 2};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return {a + d2 / (d2 - d6) * ac};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return {b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b)};
  const double scale = 1.0 / (va + vb + vc);
  return {a + ab * (vb * scale) + ac * (vc * scale)};
}

NearestTriangles::NearestTriangles(std::span<const openvdb::Vec3s> points,
                                   std::span<const std::array<unsigned, 3>> triangles)
    : geometry_(device_, RTC_GEOMETRY_TYPE_TRIANGLE), scene_(device_) {
  points_ =
      geometry_.new_buffer<std::array<float, 3>>(RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, points.size());
  double reach = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const openvdb::Vec3s& p = points[i];
    points_[i] = {p.x(), p.y(), p.z()};
    reach = std::max({reach, std::abs(double{p.x()}), std::abs(double{p.y()}), std::abs(double{p.z()})});
  }
  triangles_ = geometry_.new_buffer<std::array<unsigned, 3>>(RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             triangles.size());
  std::copy(triangles.begin(), triangles.end(), triangles_.begin());
  geometry_.commit();
  scene_.attach(geometry_);
  scene_.commit();
  // The query's point goes to Embree in single precision: its search sphere is this much wider, so that
  // no triangle within the radius of the point itself is passed over.
  slack_mm_ = 4.0 * std::numeric_limits<float>::epsilon() * (1.0 + reach);
}

struct NearestTriangles::Nearest {
  const NearestTriangles* surface;
  Vec3 p;
  double best_sq;
  Vec3 point = Vec3::Zero(), normal = Vec3::Zero();  // the nearest point, its pseudonormal so far
};

NearestTriangles::Distance NearestTriangles::distance(const Vec3& p, double radius_mm) const {
  Nearest nearest{this, p, radius_mm * radius_mm};
  RTCPointQuery query{};
  query.x = static_cast<float>(p.x());
  query.y = static_cast<float>(p.y());
  query.z = static_cast<float>(p.z());
  query.radius = static_cast<float>(radius_mm + slack_mm_);
  scene_.point_query(query, &visit, &nearest);
  Distance out;
  out.mm = std::sqrt(nearest.best_sq);
  out.found = nearest.best_sq < radius_mm * radius_mm;
  out.outside = (p - nearest.point).dot(nearest.normal) > 0;
  return out;
}

bool NearestTriangles::visit(RTCPointQueryFunctionArguments* args) {
  auto& n = *static_cast<Nearest*>(args->userPtr);
  const std::array<Vec3, 3> t = n.surface->triangle(args->primID);
  const ClosestPoint c = closest_on_triangle(n.p, t[0], t[1], t[2]);
  const double d_sq = (c.point - n.p).squaredNorm();
  // A face that shares the nearest point measures it to within a rounding of the corners' floats.
  const double tie = 1e-9 * (n.best_sq + n.surface->slack_mm_ * n.surface->slack_mm_);
  if (d_sq > n.best_sq + tie) return false;
  Vec3 normal = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
  if (c.corner >= 0) {
    const auto k = static_cast<std::size_t>(c.corner);
    const Vec3 u = t[(k + 1) % 3] - t[k], v = t[(k + 2) % 3] - t[k];
    normal *= std::atan2(u.cross(v).norm(), u.dot(v));
  }
  const bool shrinks = d_sq < n.best_sq - tie;
  if (shrinks)
    n.normal = normal;
  else
    n.normal += normal;
  if (d_sq >= n.best_sq) return false;
  n.best_sq = d_sq;
  n.point = c.point;
  if (!shrinks) return false;
  args->query->radius = static_cast<float>(std::sqrt(d_sq) + n.surface->slack_mm_);
  return true;
}

}  // namespace beadtwin::sim
