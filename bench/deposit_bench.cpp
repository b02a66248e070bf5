// The deposition benchmark: one run of either route to a voxel model of a scenario's print, timed
// inside the process so the slicing before it is not counted. bench/bench_deposit.sh runs each route in a
// process of its own (peak memory from /usr/bin/time) and reports the ratio.
//
//   deposit_bench SCENARIO deposit   beadtwin's deposit (sim::deposit): beads swept with roller squash and
//                                    conserved volume, substrate following, defects
//   deposit_bench SCENARIO mesh      what a user would do instead: every bead as a closed tube of its
//                                    stadium section (12 sides) in one surface mesh, voxelised with
//                                    OpenVDB's mesh-to-volume at the same voxel size
//   deposit_bench SCENARIO compare   the deposit, then the comparison with the CAD as a run makes it
//                                    (sim::compare_with_cad), timed alone (its CAD distance grid included)
//   deposit_bench SCENARIO skin DIR  file sizes: the bead-by-bead model above written as binary STL, against
//                                    the deposit's as-printed skin (sim::extract_skin, the scenario's
//                                    adaptivity) written as STL and PLY at several simplification tolerances;
//                                    the files are written into DIR
//
// Prints one line (deposit, mesh: route, seconds, bead length (m), active voxels, triangles; compare: the
// deposit's seconds, the comparison's, CAD samples and stocks) or one line per file (skin: what, triangles,
// bytes).
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include "bench/bench_common.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/run.hpp"
#include "scenarios/variant_stages.hpp"
#include "sim/bead_section.hpp"
#include "sim/deposit.hpp"
#include "sim/skin.hpp"

using namespace beadtwin;

namespace {

using bench::seconds_since;

// Every depositing move as a closed tube: its stadium section (core half-width a, radius r) in 12 points,
// swept along the move, with flat end caps.
void append_tube(const Move& m, std::vector<openvdb::Vec3s>& points, std::vector<openvdb::Vec3I>& triangles) {
  const Eigen::Vector3d axis = m.end - m.start;
  const Eigen::Vector2d plan = axis.head<2>();
  if (plan.norm() < 1e-6) return;
  const sim::BeadProfile p = sim::moving_bead_profile(m.volume_mm3 / m.length_mm(), m.layer_height_mm);
  const Eigen::Vector3d side(-plan.y() / plan.norm(), plan.x() / plan.norm(), 0.0);
  constexpr int kSides = 12;
  std::vector<Eigen::Vector2d> section;  // (across, up from the bead's centre)
  for (int k = 0; k < kSides; ++k) {
    const double t = (k + 0.5) * 2.0 * kPi / kSides;
    const double across =
        std::cos(t) * p.radius_mm + (std::cos(t) >= 0 ? p.core_half_width_mm : -p.core_half_width_mm);
    section.emplace_back(across, std::sin(t) * p.radius_mm);
  }
  const auto base = static_cast<unsigned>(points.size());
  for (const Eigen::Vector3d& end : {m.start, m.end})
    for (const Eigen::Vector2d& s : section) {
      const Eigen::Vector3d q = end + side * s.x() + Eigen::Vector3d(0, 0, s.y() - p.radius_mm);
      points.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()));
    }
  for (unsigned k = 0; k < kSides; ++k) {
    const unsigned j = (k + 1) % kSides;
    triangles.emplace_back(base + k, base + j, base + kSides + j);
    triangles.emplace_back(base + k, base + kSides + j, base + kSides + k);
  }
  for (unsigned k = 1; k + 1 < kSides; ++k) {
    triangles.emplace_back(base, base + k + 1, base + k);
    triangles.emplace_back(base + kSides, base + kSides + k, base + kSides + k + 1);
  }
}

// Writes `mesh` into `dir` as `name` and prints its size.
void write_and_measure(const sim::SkinMesh& mesh, const std::filesystem::path& dir, const std::string& name,
                       sim::MeshFormat format) {
  const std::filesystem::path path = dir / (name + "." + std::string(sim::to_string(format)));
  sim::write_mesh(mesh, path, format);
  std::printf("%s %zu triangles, %ju bytes\n", path.filename().c_str(), mesh.triangles.size(),
              static_cast<std::uintmax_t>(std::filesystem::file_size(path)));
}

}  // namespace

int main(int argc, char** argv) {
  const std::string route = argc >= 3 ? argv[2] : "";
  if (!(argc == 3 && (route == "deposit" || route == "mesh" || route == "compare")) &&
      !(argc == 4 && route == "skin")) {
    std::fprintf(stderr, "usage: deposit_bench SCENARIO deposit|mesh|compare|skin DIR\n");
    return 2;
  }
  try {
    openvdb::initialize();
    const scenarios::Scenario sc = scenarios::load_scenario(argv[1]);
    const scenarios::Variant& v = sc.variants.front();
    const Toolpath tp = scenarios::variant_toolpath(v);
    const double length_m = tp.print_length_mm() / 1000.0;
    const auto t0 = std::chrono::steady_clock::now();
    if (route == "skin") {
      const std::filesystem::path dir = argv[3];
      sim::SkinMesh beads;
      for (const Move& m : tp.moves)
        if (m.kind == MoveKind::kPrint && m.deposits()) append_tube(m, beads.points_mm, beads.triangles);
      write_and_measure(beads, dir, "bead-by-bead", sim::MeshFormat::kStl);
      beads = {};
      const sim::Deposit d = sim::deposit(tp, scenarios::deposit_options(v));
      for (const double tolerance_mm : {0.0, 0.3, 0.5, 1.0}) {
        const sim::SkinMesh skin = sim::extract_skin(d, v.output.skin_adaptivity, true, tolerance_mm);
        const std::string name = fmt::format("skin-{}mm", tolerance_mm);
        for (const sim::MeshFormat f : sim::kMeshFormats) write_and_measure(skin, dir, name, f);
      }
    } else if (route == "compare") {
      const sim::Deposit d = sim::deposit(tp, scenarios::deposit_options(v));
      const double deposit_s = seconds_since(t0);
      const auto t1 = std::chrono::steady_clock::now();
      const std::optional<sim::CadComparison> c = scenarios::compare_variant_with_cad(v, d);
      if (!c) throw InputError("the scenario's first variant has no CAD to compare with");
      std::printf(
          "compare %.3f s (deposit %.3f s), %zu CAD samples, stock min %.4f p05 %.4f p50 %.4f p95 %.4f "
          "max %.4f mm, undercut %.5f\n",
          seconds_since(t1), deposit_s, c->cad_samples, c->min_stock_mm, c->p05_stock_mm, c->median_stock_mm,
          c->p95_stock_mm, c->max_stock_mm, c->undercut_fraction);
    } else if (route == "deposit") {
      const sim::Deposit d = sim::deposit(tp, scenarios::deposit_options(v));
      std::printf("deposit %.3f s, %.1f m of bead, %zu voxels, porosity %.4f, %zu defects\n",
                  seconds_since(t0), length_m, d.active_voxels, d.porosity, d.defects.size());
    } else {
      std::vector<openvdb::Vec3s> points;
      std::vector<openvdb::Vec3I> triangles;
      for (const Move& m : tp.moves)
        if (m.kind == MoveKind::kPrint && m.deposits()) append_tube(m, points, triangles);
      const auto transform = sim::deposit_transform(v.output.voxel_size_mm);
      // Points in index space, as mesh-to-volume takes them.
      for (openvdb::Vec3s& p : points) p = transform->worldToIndex(p);
      openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> mesh(points, triangles);
      const auto level_set = openvdb::tools::meshToVolume<openvdb::FloatGrid>(mesh, *transform, 3.0f, 3.0f);
      std::printf("mesh %.3f s, %.1f m of bead, %llu voxels, %zu triangles\n", seconds_since(t0), length_m,
                  static_cast<unsigned long long>(level_set->activeVoxelCount()), triangles.size());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
