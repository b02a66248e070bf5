#include "slicer/mesh_repair.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "core/error.hpp"

namespace beadtwin::slicer {
namespace {

using Tri = std::array<int, 3>;

// One body's triangles over vertices of its own.
struct Soup {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Tri> triangles;
};

std::size_t at(int i) {
  return static_cast<std::size_t>(i);
}

bool has_repeated_corner(const Tri& t) {
  return t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
}

// Merges points closer than `tol` into the first one seen; points at exactly the same position share a
// vertex without counting as welded. A uniform grid of cells 2 tol wide finds the candidates: any point
// within tol lies in one of the 8 cells nearest to the point (2 per axis).
class Welder {
 public:
  Welder(const Eigen::Vector3d& origin, double tol) : origin_(origin), cell_(2 * tol), tol_(tol) {}

  // The index (into the welded vertices) of `p`'s vertex.
  int add(const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = cell_ > 0 ? Eigen::Vector3d((p - origin_) / cell_) : Eigen::Vector3d::Zero();
    std::array<std::uint64_t, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
      const double fl = std::floor(q[a]);
      // +1 so the cell before the first is 0. Coordinates span at most 1 / (2 kWeldToleranceOfDiagonal)
      // cells, so 21 bits per axis suffice.
      const auto c = static_cast<std::uint64_t>(fl) + 1;
      const auto ia = static_cast<std::size_t>(a);
      lo[ia] = cell_ > 0 && q[a] - fl < 0.5 ? c - 1 : c;
      hi[ia] = cell_ > 0 ? lo[ia] + 1 : lo[ia];
    }
    int near = -1;
    for (std::uint64_t x = lo[0]; x <= hi[0]; ++x)
      for (std::uint64_t y = lo[1]; y <= hi[1]; ++y)
        for (std::uint64_t z = lo[2]; z <= hi[2]; ++z) {
          const auto it = first_.find(x << 42 | y << 21 | z);
          if (it == first_.end()) continue;
          for (int e = it->second; e >= 0; e = entries_[at(e)].next) {
            const Entry& entry = entries_[at(e)];
            if (entry.position == p) return entry.vertex;
            if (near < 0 && (entry.position - p).norm() <= tol_) near = entry.vertex;
          }
        }
    if (near < 0) {
      near = static_cast<int>(vertices_.size());
      vertices_.push_back(p);
    } else {
      ++welded_;
    }
    const auto key = cell_key(q);
    auto [it, inserted] = first_.try_emplace(key, -1);
    entries_.push_back({p, near, it->second});
    it->second = static_cast<int>(entries_.size()) - 1;
    return near;
  }

  // Distinct positions merged into a vertex at another position.
  int welded() const { return welded_; }
  std::vector<Eigen::Vector3d> take_vertices() { return std::move(vertices_); }

 private:
  struct Entry {
    Eigen::Vector3d position;
    int vertex;  // the welded vertex it belongs to
    int next;    // the next entry in the same cell, or -1
  };

  static std::uint64_t cell_key(const Eigen::Vector3d& q) {
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) key = key << 21 | (static_cast<std::uint64_t>(std::floor(q[a])) + 1);
    return key;
  }

  Eigen::Vector3d origin_;
  double cell_, tol_;
  std::vector<Eigen::Vector3d> vertices_;
  std::vector<Entry> entries_;                    // one per distinct position
  std::unordered_map<std::uint64_t, int> first_;  // cell -> its first entry
  int welded_ = 0;
};

// The body's triangles over welded vertices. `vertex_of` (one per raw vertex, all -1) is scratch space,
// returned all -1.
Soup weld_body(const TriangleMesh& raw, const std::vector<std::size_t>& faces, double tol,
               std::vector<int>& vertex_of, MeshReport& report) {
  Welder welder(raw.min_corner(), tol);
  Soup soup;
  soup.triangles.reserve(faces.size());
  for (std::size_t f : faces) {
    Tri t{};
    for (std::size_t c = 0; c < 3; ++c) {
      int& v = vertex_of[at(raw.triangles[f][c])];
      if (v < 0) v = welder.add(raw.vertices[at(raw.triangles[f][c])]);
      t[c] = v;
    }
    soup.triangles.push_back(t);
  }
  for (std::size_t f : faces)
    for (int v : raw.triangles[f]) vertex_of[at(v)] = -1;
  report.welded_vertices += welder.welded();
  soup.vertices = welder.take_vertices();
  return soup;
}

void drop_degenerate_faces(Soup& soup, MeshReport& report) {
  const auto removed = std::erase_if(soup.triangles, has_repeated_corner);
  report.degenerate_faces += static_cast<int>(removed);
}

// True when the corners' cyclic order is the ascending one (the face's winding relative to its sorted key).
bool ascending_winding(const Tri& t) {
  const auto m = static_cast<std::size_t>(std::min_element(t.begin(), t.end()) - t.begin());
  return t[(m + 1) % 3] < t[(m + 2) % 3];
}

void drop_duplicate_faces(Soup& soup, MeshReport& report) {
  std::vector<std::pair<Tri, std::size_t>> keyed;
  keyed.reserve(soup.triangles.size());
  for (std::size_t f = 0; f < soup.triangles.size(); ++f) {
    Tri key = soup.triangles[f];
    std::sort(key.begin(), key.end());
    keyed.emplace_back(key, f);
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<bool> keep(soup.triangles.size(), true);
  for (std::size_t i = 0; i < keyed.size();) {
    std::size_t j = i + 1;
    while (j < keyed.size() && keyed[j].first == keyed[i].first) ++j;
    if (j - i > 1) {
      bool ascending = false, descending = false;
      for (std::size_t k = i; k < j; ++k)
        (ascending_winding(soup.triangles[keyed[k].second]) ? ascending : descending) = true;
      // Same winding: keep the first copy. Opposite windings: a sheet inside the solid; keep none.
      for (std::size_t k = (ascending && descending) ? i : i + 1; k < j; ++k) keep[keyed[k].second] = false;
      report.duplicate_faces += static_cast<int>((ascending && descending) ? j - i : j - i - 1);
    }
    i = j;
  }
  std::vector<Tri> kept;
  kept.reserve(soup.triangles.size());
  for (std::size_t f = 0; f < soup.triangles.size(); ++f)
    if (keep[f]) kept.push_back(soup.triangles[f]);
  soup.triangles = std::move(kept);
}

// The faces using an undirected edge: how many, and the first two with the direction they run it in.
struct EdgeUse {
  int count = 0;
  std::array<int, 2> face{-1, -1};
  std::array<bool, 2> forward{false, false};  // the face runs the edge from its lower to its higher vertex
};

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
  return lo << 32 | hi;
}

std::unordered_map<std::uint64_t, EdgeUse> edge_uses(const std::vector<Tri>& triangles) {
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  edges.reserve(triangles.size() * 2);
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (std::size_t c = 0; c < 3; ++c) {
      const int a = triangles[f][c], b = triangles[f][(c + 1) % 3];
      EdgeUse& e = edges[edge_key(a, b)];
      if (e.count < 2) {
        e.face[at(e.count)] = static_cast<int>(f);
        e.forward[at(e.count)] = a < b;
      }
      ++e.count;
    }
  return edges;
}

// Shells: faces connected across edges used by exactly two faces, each with the flip that makes its
// winding agree with its shell's majority.
struct Shells {
  std::vector<std::vector<int>> faces;  // per shell
  std::vector<bool> flip;               // per face
  std::vector<bool> closed;             // per shell: no face has an edge used by it alone
};

Shells find_shells(const std::vector<Tri>& triangles,
                   const std::unordered_map<std::uint64_t, EdgeUse>& edges) {
  Shells s;
  s.flip.assign(triangles.size(), false);
  std::vector<int> shell_of(triangles.size(), -1);
  std::vector<int> queue;
  for (std::size_t seed = 0; seed < triangles.size(); ++seed) {
    if (shell_of[seed] >= 0) continue;
    const int shell = static_cast<int>(s.faces.size());
    s.faces.emplace_back();
    s.closed.push_back(true);
    shell_of[seed] = shell;
    queue.assign(1, static_cast<int>(seed));
    while (!queue.empty()) {
      const int f = queue.back();
      queue.pop_back();
      s.faces.back().push_back(f);
      const Tri& t = triangles[at(f)];
      for (std::size_t c = 0; c < 3; ++c) {
        const EdgeUse& e = edges.at(edge_key(t[c], t[(c + 1) % 3]));
        if (e.count == 1) s.closed.back() = false;
        if (e.count != 2) continue;
        const std::size_t k = e.face[0] == f ? 1 : 0;
        const int n = e.face[k];
        // Neighbours agree when they run the shared edge in opposite directions.
        const bool n_flip = s.flip[at(f)] != (e.forward[0] == e.forward[1]);
        if (shell_of[at(n)] >= 0) continue;  // a conflict here means a non-orientable shell; left as is
        shell_of[at(n)] = shell;
        s.flip[at(n)] = n_flip;
        queue.push_back(n);
      }
    }
    // The seed's winding may be the odd one out: keep the majority's.
    const auto& fs = s.faces.back();
    const auto flipped = std::count_if(fs.begin(), fs.end(), [&](int f) { return s.flip[at(f)]; });
    if (2 * static_cast<std::size_t>(flipped) > fs.size())
      for (int f : fs) s.flip[at(f)] = !s.flip[at(f)];
  }
  return s;
}

void flip_face(Tri& t) {
  std::swap(t[1], t[2]);
}

// Signed volume of some faces, about `centre` (for precision far from the origin).
double signed_volume(const Soup& soup, const std::vector<int>& faces, const Eigen::Vector3d& centre) {
  double v6 = 0;
  for (int f : faces) {
    const Tri& t = soup.triangles[at(f)];
    v6 += (soup.vertices[at(t[0])] - centre)
              .dot((soup.vertices[at(t[1])] - centre).cross(soup.vertices[at(t[2])] - centre));
  }
  return v6 / 6.0;
}

// Möller-Trumbore: does the ray o + s d (s > 0) cross triangle abc?
bool ray_crosses(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                 const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, p = d.cross(e2);
  const double det = e1.dot(p);
  if (det == 0) return false;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) / det;
  if (u < 0 || u > 1) return false;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (v < 0 || u + v > 1) return false;
  return e2.dot(q) / det > 0;
}

struct ClosedShell {
  std::vector<int> faces;
  Eigen::AlignedBox3d box;
  Eigen::Vector3d probe;  // a point on the shell: the centroid of its largest face
};

ClosedShell describe_shell(const Soup& soup, const std::vector<int>& faces) {
  ClosedShell c{faces, {}, {}};
  double largest = -1;
  for (int f : faces) {
    const Tri& t = soup.triangles[at(f)];
    const Eigen::Vector3d &a = soup.vertices[at(t[0])], &b = soup.vertices[at(t[1])],
                          &d = soup.vertices[at(t[2])];
    c.box.extend(a).extend(b).extend(d);
    const double area = (b - a).cross(d - a).norm();
    if (area > largest) {
      largest = area;
      c.probe = (a + b + d) / 3.0;
    }
  }
  return c;
}

// How many of the other closed shells contain shell `i`'s probe point (ray parity against each).
int nesting_depth(const Soup& soup, const std::vector<ClosedShell>& shells, std::size_t i) {
  // An arbitrary, irrational-looking direction, unlikely to graze an edge of axis-aligned geometry.
  const Eigen::Vector3d dir = Eigen::Vector3d(0.3141592653589793, 0.2718281828459045, 0.9092974268256817);
  const Eigen::Vector3d& p = shells[i].probe;
  int depth = 0;
  for (std::size_t j = 0; j < shells.size(); ++j) {
    if (j == i || !shells[j].box.contains(p)) continue;
    int crossings = 0;
    for (int f : shells[j].faces) {
      const Tri& t = soup.triangles[at(f)];
      crossings +=
          ray_crosses(p, dir, soup.vertices[at(t[0])], soup.vertices[at(t[1])], soup.vertices[at(t[2])]);
    }
    depth += crossings % 2;
  }
  return depth;
}

// Makes windings consistent per shell, then turns closed shells to face out (or in, for cavities).
void orient(Soup& soup, MeshReport& report) {
  const auto edges = edge_uses(soup.triangles);
  for (const auto& [key, e] : edges) {
    report.open_edges += e.count == 1;
    report.non_manifold_edges += e.count > 2;
  }
  const Shells shells = find_shells(soup.triangles, edges);
  report.shells += static_cast<int>(shells.faces.size());
  for (std::size_t f = 0; f < soup.triangles.size(); ++f)
    if (shells.flip[f]) {
      flip_face(soup.triangles[f]);
      ++report.flipped_faces;
    }
  std::vector<ClosedShell> closed;
  for (std::size_t s = 0; s < shells.faces.size(); ++s)
    if (shells.closed[s]) closed.push_back(describe_shell(soup, shells.faces[s]));
  for (std::size_t i = 0; i < closed.size(); ++i) {
    const bool cavity = nesting_depth(soup, closed, i) % 2 == 1;  // parity does not depend on winding
    report.cavities += cavity;
    const double volume = signed_volume(soup, closed[i].faces, closed[i].box.center());
    if (cavity ? volume > 0 : volume < 0) {
      ++report.reversed_shells;
      for (int f : closed[i].faces) flip_face(soup.triangles[at(f)]);
    }
  }
}

// Appends the soup as body `body` of `out`, keeping only the vertices its triangles use.
void append_body(TriangleMesh& out, const Soup& soup, int body) {
  std::vector<int> index(soup.vertices.size(), -1);
  for (const Tri& t : soup.triangles) {
    Tri nt{};
    for (std::size_t c = 0; c < 3; ++c) {
      int& v = index[at(t[c])];
      if (v < 0) {
        v = static_cast<int>(out.vertices.size());
        out.vertices.push_back(soup.vertices[at(t[c])]);
      }
      nt[c] = v;
    }
    out.triangles.push_back(nt);
    out.body.push_back(body);
  }
}

}  // namespace

TriangleMesh repair_mesh(const TriangleMesh& raw, MeshReport& report) {
  BT_CHECK(raw.body.empty() || raw.body.size() == raw.triangles.size());
  const std::size_t n_bodies = raw.body.empty() ? 1 : std::max<std::size_t>(raw.body_names.size(), 1);
  std::vector<std::vector<std::size_t>> faces_of(n_bodies);
  for (std::size_t f = 0; f < raw.triangles.size(); ++f) {
    const int b = raw.body.empty() ? 0 : raw.body[f];
    BT_CHECK(b >= 0 && static_cast<std::size_t>(b) < n_bodies);
    for (int v : raw.triangles[f]) BT_CHECK(v >= 0 && static_cast<std::size_t>(v) < raw.vertices.size());
    faces_of[static_cast<std::size_t>(b)].push_back(f);
  }
  report.weld_tolerance_mm =
      raw.triangles.empty() ? 0.0 : kWeldToleranceOfDiagonal * (raw.max_corner() - raw.min_corner()).norm();
  TriangleMesh out;
  std::vector<int> vertex_of(raw.vertices.size(), -1);
  for (std::size_t b = 0; b < n_bodies; ++b) {
    Soup soup = weld_body(raw, faces_of[b], report.weld_tolerance_mm, vertex_of, report);
    drop_degenerate_faces(soup, report);
    drop_duplicate_faces(soup, report);
    if (soup.triangles.empty()) continue;
    orient(soup, report);
    append_body(out, soup, static_cast<int>(out.body_names.size()));
    out.body_names.push_back(b < raw.body_names.size() ? raw.body_names[b] : "part");
  }
  report.bodies = static_cast<int>(out.body_names.size());
  return out;
}

void add_repair_warnings(MeshReport& report, const std::string& source) {
  auto warn = [&](int n, std::string_view one, std::string_view many) {
    if (n > 0) report.warnings.push_back(fmt::format("{}: {} {}", source, n, n == 1 ? one : many));
  };
  warn(report.ignored_primitives, "point or line was ignored (only triangles bound a solid)",
       "points and lines were ignored (only triangles bound a solid)");
  warn(report.welded_vertices,
       fmt::format("vertex closer than {:.3g} mm to another was welded to it", report.weld_tolerance_mm),
       fmt::format("vertices closer than {:.3g} mm to another were welded to it", report.weld_tolerance_mm));
  warn(report.degenerate_faces, "degenerate face (two corners at one point) was dropped",
       "degenerate faces (two corners at one point) were dropped");
  warn(report.duplicate_faces, "duplicate face was dropped (both copies when wound oppositely)",
       "duplicate faces were dropped (both copies when wound oppositely)");
  warn(report.flipped_faces, "face was flipped to match its neighbours",
       "faces were flipped to match their neighbours");
  warn(report.reversed_shells, "closed shell was inside out and was turned around",
       "closed shells were inside out and were turned around");
  warn(report.cavities, "closed shell lies inside another shell of its body and is taken as a cavity",
       "closed shells lie inside another shell of their body and are taken as cavities");
  warn(report.open_edges, "open edge (used by one face only): the mesh has holes; slices close them straight",
       "open edges (used by one face only): the mesh has holes; slices close them straight");
  warn(report.non_manifold_edges, "edge is shared by more than two faces",
       "edges are shared by more than two faces");
}

}  // namespace beadtwin::slicer
