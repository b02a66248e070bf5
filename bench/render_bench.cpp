// The render benchmark: a scenario's first variant sliced and deposited as a run does, its surface
// extracted and its ray tracing structure built once, then full-HD isometric pictures rendered from it
// several times — with soft shadows and ambient occlusion (the defaults), and, in the same run, with both
// off as the reference — each timed inside the process. Prints the surface and structure times, the median
// time per frame and the rays traced per second (camera, shadow and occlusion rays together).
// bench/bench_render.sh runs it on the LSAM hull-mould shell and the default scenario.
//
//   render_bench SCENARIO [FRAMES [WIDTH HEIGHT [SAMPLES_PER_PIXEL [OUT_DIR]]]]
//
// FRAMES (default 5) frames per setting; WIDTH x HEIGHT default 1920 x 1080; SAMPLES_PER_PIXEL 0 (default)
// keeps RenderOptions' default; with OUT_DIR the first frame of each setting is written there as a PNG, and
// the deposit as deposit.vdb. SCENARIO may also be a deposit.vdb (as a run or this program writes it): the
// surface and the pictures of a deposit without depositing it again.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>

#include "bench/bench_common.hpp"
#include "render/render.hpp"
#include "render/surface.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/run.hpp"
#include "scenarios/variant_stages.hpp"
#include "sim/deposit.hpp"
#include "sim/deposit_files.hpp"

using namespace beadtwin;

namespace {

using bench::seconds_since;

// Layers in bands of three tones, so the layer lines and a band's edges both show.
render::Rgb layer_colour(int layer) {
  static constexpr render::Rgb kBands[] = {
      {0.35f, 0.70f, 0.40f}, {0.40f, 0.62f, 0.80f}, {0.85f, 0.65f, 0.30f}};
  return kBands[(layer / 10) % 3];
}

// The deposit of `path`: a scenario's first variant, sliced and deposited (then also written to
// OUT_DIR/deposit.vdb when `out` is not empty), or a deposit.vdb as a run writes it (grids fill and layer).
sim::Deposit load_deposit(const std::filesystem::path& path, const std::filesystem::path& out) {
  sim::Deposit d;
  if (path.extension() == ".vdb") {
    openvdb::io::File file(path.string());
    file.open();
    d.fill = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("fill"));
    d.layer = openvdb::gridPtrCast<openvdb::Int32Grid>(file.readGrid("layer"));
    if (!d.fill || !d.layer)
      throw std::runtime_error(path.string() + ": no float grid fill or int grid layer");
    d.voxel_size_mm = d.fill->voxelSize()[0];
    d.active_voxels = d.fill->activeVoxelCount();
    return d;
  }
  const scenarios::Scenario sc = scenarios::load_scenario(path);
  const scenarios::Variant& v = sc.variants.front();
  const Toolpath tp = scenarios::variant_toolpath(v);
  const auto t0 = std::chrono::steady_clock::now();
  d = sim::deposit(tp, scenarios::deposit_options(v));
  std::printf("deposit %.2f s\n", seconds_since(t0));
  if (!out.empty()) sim::write_deposit_vdb(d, out / "deposit.vdb");
  return d;
}

struct Setting {
  const char* name;
  bool soft_shadows_and_occlusion;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 7 || argc == 4) {
    std::fprintf(stderr,
                 "usage: render_bench SCENARIO [FRAMES [WIDTH HEIGHT [SAMPLES_PER_PIXEL [OUT_DIR]]]]\n");
    return 2;
  }
  try {
    openvdb::initialize();
    const int frames = argc >= 3 ? std::atoi(argv[2]) : 5;
    render::RenderOptions options;
    options.width = argc >= 5 ? std::atoi(argv[3]) : 1920;
    options.height = argc >= 5 ? std::atoi(argv[4]) : 1080;
    if (argc >= 6 && std::atoi(argv[5]) > 0) options.samples_per_pixel = std::atoi(argv[5]);
    const std::filesystem::path out = argc >= 7 ? argv[6] : "";

    const sim::Deposit d = load_deposit(argv[1], out);
    std::printf("%zu voxels of %.2f mm\n", d.active_voxels, d.voxel_size_mm);

    auto t0 = std::chrono::steady_clock::now();
    render::SurfaceMesh surface = render::extract_surface(*d.fill);
    const double surface_s = seconds_since(t0);
    const std::size_t triangles = surface.triangles.size();
    t0 = std::chrono::steady_clock::now();
    const render::PreparedDeposit prepared(d, std::move(surface));
    const double bvh_s = seconds_since(t0);
    std::printf("surface %.3f s, %zu triangles; bvh %.3f s\n", surface_s, triangles, bvh_s);

    for (const Setting setting : {Setting{"full", true}, Setting{"plain", false}}) {
      render::RenderOptions o = options;
      if (!setting.soft_shadows_and_occlusion) {
        o.ambient_occlusion = false;
        o.key_light_radius_deg = 0.0;
      }
      std::vector<double> times, cpu;
      render::RenderStats stats;
      for (int i = 0; i < frames; ++i) {
        t0 = std::chrono::steady_clock::now();
        const std::clock_t c0 = std::clock();
        const render::Image image = render::render_deposit(prepared, layer_colour, o, &stats);
        times.push_back(seconds_since(t0));
        cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
        if (i == 0 && !out.empty())
          render::write_png(image, out / (std::string("render-") + setting.name + ".png"));
      }
      const double frame_s = bench::median(times);
      const double rays_m = static_cast<double>(stats.rays()) * 1e-6;
      const double traced_m = static_cast<double>(stats.rays_traced()) * 1e-6;
      std::printf(
          "%s %dx%d spp %d ao %d x %d: frame %.3f s (median of %d, min %.3f; cpu %.3f s); rays %.1f M "
          "(primary "
          "%.1f of which %.1f outside, shadow %.1f, occlusion %.1f): %.2f Mrays/s, traced %.1f M: %.2f "
          "Mrays/s\n",
          setting.name, o.width, o.height, o.samples_per_pixel, o.ambient_occlusion ? 1 : 0,
          o.ambient_occlusion_samples, frame_s, frames, *std::min_element(times.begin(), times.end()),
          bench::median(cpu), rays_m, static_cast<double>(stats.primary_rays) * 1e-6,
          static_cast<double>(stats.primary_rays_outside) * 1e-6,
          static_cast<double>(stats.shadow_rays) * 1e-6, static_cast<double>(stats.occlusion_rays) * 1e-6,
          rays_m / frame_s, traced_m, traced_m / frame_s);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
