// The exact distance from a point to the nearest of a set of triangles, and on which side of them it lies:
// Embree's point query finds the candidate triangles near the point, closest_on_triangle measures each.
// The comparison with the CAD measures both ways with it: from the CAD's surface to the print's, and from
// the print's skin to the CAD beyond the CAD's distance grid (sim/cad_compare.hpp).
#pragma once

#include <array>
#include <cstddef>
#include <span>

#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include "sim/embree.hpp"

namespace beadtwin::sim {

// The closest point of triangle (a, b, c) to p, and the feature it lies on: a corner, an edge or the face.
// By the Voronoi region of the triangle's corners, edges and face that p lies in (Ericson, Real-Time
// Collision Detection, 2005, section 5.1.5). Any triangle, also one without area; mm.
struct ClosestPoint {
  Eigen::Vector3d point;
  int corner = -1;  // the corner it is (0 for a, 1 for b, 2 for c), or -1 (an edge or the face)
};
ClosestPoint closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                 const Eigen::Vector3d& c);

// Triangles in an Embree scene (single-precision corners, mm), for nearest-distance queries. Safe to query
// from several threads at once.
class NearestTriangles {
 public:
  // `points`: the corners, mm; `triangles`: indices into them, each in range (not checked).
  NearestTriangles(std::span<const openvdb::Vec3s> points,
                   std::span<const std::array<unsigned, 3>> triangles);

  std::size_t triangles() const { return triangles_.size(); }
  // Triangle i's corners, mm.
  std::array<Eigen::Vector3d, 3> triangle(std::size_t i) const {
    const std::array<unsigned, 3>& t = triangles_[i];
    std::array<Eigen::Vector3d, 3> out;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::array<float, 3>& v = points_[t[k]];
      out[k] = Eigen::Vector3d(v[0], v[1], v[2]);
    }
    return out;
  }

  // The distance from p to the triangles, mm, if it is less than `radius_mm` (else `radius_mm`), and, for
  // triangles that face out from a closed surface, whether p lies outside it (when it is nearer than
  // `radius_mm`): by the side of the nearest point's pseudonormal — the face's normal, the sum of the two
  // faces' normals on an edge, their normals weighted by their angles at a corner — which tells inside from
  // outside for a closed surface wherever the nearest point lies (Bærentzen and Aanæs, Signed distance
  // computation using the angle weighted pseudonormal, IEEE TVCG 11(3), 2005). The faces that share the
  // nearest point are the ones nearest within a rounding. `radius_mm` > 0.
  struct Distance {
    double mm = 0.0;
    bool found = false, outside = false;
  };
  Distance distance(const Eigen::Vector3d& p, double radius_mm) const;

 private:
  struct Nearest;
  static bool visit(RTCPointQueryFunctionArguments* args);

  embree::Device device_;
  embree::Geometry geometry_;
  embree::Scene scene_;
  std::span<std::array<float, 3>> points_;
  std::span<std::array<unsigned, 3>> triangles_;
  double slack_mm_ = 0.0;
};

}  // namespace beadtwin::sim
