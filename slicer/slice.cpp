#include "slicer/slice.hpp"

#include <cmath>
#include <map>
#include <unordered_map>

namespace beadtwin::slicer {
namespace {

struct Segment {
  Eigen::Vector2d a, b;
  std::pair<int, int> key_a, key_b;  // the mesh edges the end points lie on (shared by neighbours)
};

std::pair<int, int> edge_key(int i, int j) {
  return i < j ? std::pair{i, j} : std::pair{j, i};
}

// Intersection of edge (i,j) with the plane, computed in a fixed vertex order so both triangles that share
// the edge get bit-identical points.
Eigen::Vector2d cut(const TriangleMesh& mesh, int i, int j, double z) {
  if (i > j) std::swap(i, j);
  const Eigen::Vector3d& p = mesh.vertices[static_cast<std::size_t>(i)];
  const Eigen::Vector3d& q = mesh.vertices[static_cast<std::size_t>(j)];
  const double t = (z - p.z()) / (q.z() - p.z());
  return {p.x() + t * (q.x() - p.x()), p.y() + t * (q.y() - p.y())};
}

}  // namespace

Polygons slice_mesh(const TriangleMesh& mesh, double z, SliceStats* stats) {
  std::vector<Segment> segments;
  for (const auto& t : mesh.triangles) {
    bool above[3];
    for (int c = 0; c < 3; ++c)
      above[c] = mesh.vertices[static_cast<std::size_t>(t[static_cast<std::size_t>(c)])].z() >= z;
    const int n_above = above[0] + above[1] + above[2];
    if (n_above == 0 || n_above == 3) continue;
    // The lone vertex (the one on its own side of the plane) and the other two, in triangle order.
    int lone = 0;
    for (int c = 0; c < 3; ++c)
      if ((n_above == 1) == above[c]) lone = c;
    const int v0 = t[static_cast<std::size_t>(lone)];
    const int v1 = t[static_cast<std::size_t>((lone + 1) % 3)];
    const int v2 = t[static_cast<std::size_t>((lone + 2) % 3)];
    Segment s{cut(mesh, v0, v1, z), cut(mesh, v0, v2, z), edge_key(v0, v1), edge_key(v0, v2)};
    // Orient so the solid lies to the left (outer contours CCW): with the lone vertex above, walking from
    // edge (v0,v1) to edge (v0,v2) has the solid on the right, so swap.
    if (above[lone]) {
      std::swap(s.a, s.b);
      std::swap(s.key_a, s.key_b);
    }
    segments.push_back(s);
  }
  // Chain segments into loops by the mesh edge their ends lie on.
  std::map<std::pair<int, int>, std::size_t> by_start;
  for (std::size_t i = 0; i < segments.size(); ++i) by_start.emplace(segments[i].key_a, i);
  std::vector<bool> used(segments.size(), false);
  Polygons loops;
  int open_chains = 0;
  for (std::size_t first = 0; first < segments.size(); ++first) {
    if (used[first]) continue;
    Polygon loop;
    std::size_t cur = first;
    while (true) {
      used[cur] = true;
      loop.push_back(segments[cur].a);
      const auto it = by_start.find(segments[cur].key_b);
      if (it == by_start.end()) {
        loop.push_back(segments[cur].b);
        ++open_chains;
        break;
      }
      if (it->second == first) break;
      if (used[it->second]) {
        ++open_chains;
        break;
      }
      cur = it->second;
    }
    if (loop.size() >= 3) loops.push_back(std::move(loop));
  }
  if (stats) stats->open_chains = open_chains;
  return union_nonzero(loops);
}

}  // namespace beadtwin::slicer
