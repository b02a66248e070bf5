#include "thermal/view_factor.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <queue>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.hpp"
#include "sim/embree.hpp"

namespace beadtwin::thermal {
namespace {

// The six voxel faces, as the mesh numbers them: +x, -x, +y, -y, +z, -z.
const std::array<openvdb::Coord, 6> kFaceSteps = {openvdb::Coord(1, 0, 0), openvdb::Coord(-1, 0, 0),
                                                  openvdb::Coord(0, 1, 0), openvdb::Coord(0, -1, 0),
                                                  openvdb::Coord(0, 0, 1), openvdb::Coord(0, 0, -1)};
constexpr int kDown = 5;
// How far off its face a sample's rays start, in voxels: clear of the face in float coordinates of a
// machine a few metres across, and far below any feature the voxels resolve.
constexpr float kLiftVoxels = 1e-3f;

// One voxel face of the part's surface for good: the voxel and which of its faces.
struct Face {
  std::uint32_t cell = 0;
  std::uint8_t dir = 0;
  openvdb::Coord ijk;
};

Eigen::Vector3f axis(int dir) {
  Eigen::Vector3f n = Eigen::Vector3f::Zero();
  n[dir / 2] = dir % 2 == 0 ? 1.0f : -1.0f;
  return n;
}

// The centre of face `f` of a voxel of side `vs`, mm.
Eigen::Vector3f face_centre(const Face& f, double vs) {
  const Eigen::Vector3f centre(static_cast<float>((f.ijk.x() + 0.5) * vs),
                               static_cast<float>((f.ijk.y() + 0.5) * vs),
                               static_cast<float>((f.ijk.z() + 0.5) * vs));
  return centre + static_cast<float>(0.5 * vs) * axis(f.dir);
}

// A hash of a cell's sample to a fraction in [0, 1) (SplitMix64's finaliser): the turn of its ray pattern.
double turn_of(std::uint32_t cell, int sample) {
  std::uint64_t z =
      (static_cast<std::uint64_t>(cell) << 8 | static_cast<std::uint64_t>(sample)) + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

}  // namespace

struct SkyView::Impl {
  struct Sample {
    Eigen::Vector3f origin;  // on the face, lifted off it, mm
    std::uint8_t dir = 0;
  };

  const ThermalMesh& mesh;
  ViewFactorOptions options;
  double vs;
  float table_z;
  // Per layer: its cells, how many of them are not yet born, its occluding faces until it joins the scene,
  // and the top of its voxels, mm.
  std::vector<std::vector<std::uint32_t>> layer_cells;
  std::vector<std::size_t> unborn;
  std::vector<std::vector<Face>> layer_faces;
  std::vector<double> layer_top_mm;
  // Per cell, its samples at [first_sample[c], first_sample[c + 1]).
  std::vector<std::size_t> first_sample;
  std::vector<Sample> samples;
  std::size_t born = 0;
  double top_mm = -std::numeric_limits<double>::infinity();  // of the layers in the scene
  // Cells due an update when the scene's top reaches a height: (height mm, cell), lowest first.
  std::priority_queue<std::pair<double, std::uint32_t>, std::vector<std::pair<double, std::uint32_t>>,
                      std::greater<>>
      due;
  // The layers in the scene, in blocks of consecutive completions, each its own Embree scene instanced into
  // the part's: a block is merged into the one before it (and its scene built anew) when it holds as many
  // layers, so there are about log2(layers) blocks for a ray to look into, and a face is built into a
  // scene about log2(layers) times.
  struct Block {
    std::size_t layers = 0;
    std::vector<Face> faces;
    std::optional<embree::Scene> scene;
  };
  std::optional<embree::Device> device;
  std::vector<Block> blocks;
  std::optional<embree::Scene> scene;
  std::size_t rays_total = 0, computed = 0;

  Impl(const ThermalMesh& m, const ViewFactorOptions& o);
  std::size_t layer_of(std::uint32_t cell) const {
    return static_cast<std::size_t>(std::max(mesh.cells[cell].layer, 0));
  }
  std::vector<Face> surface_faces() const;
  void choose_samples(std::vector<Face>& faces);
  void add_layer(std::size_t layer);
  embree::Scene faces_scene(const std::vector<Face>& faces) const;
  void instance_blocks();
  CellView view_of(std::uint32_t cell) const;
  std::vector<ViewChange> update(std::size_t now_born);
};

SkyView::Impl::Impl(const ThermalMesh& m, const ViewFactorOptions& o)
    : mesh(m), options(o), vs(m.voxel_size_mm), table_z(static_cast<float>(m.table_z_mm)) {
  BT_CHECK(o.faces_per_cell >= 1 && o.rays_per_cell >= o.faces_per_cell && o.regrow > 0.0);
  std::size_t layers = 0;
  for (const ThermalCell& c : mesh.cells) layers = std::max(layers, static_cast<std::size_t>(c.layer + 1));
  layer_cells.resize(std::max<std::size_t>(layers, 1));
  for (std::uint32_t c = 0; c < mesh.cells.size(); ++c) layer_cells[layer_of(c)].push_back(c);
  unborn.resize(layer_cells.size());
  for (std::size_t l = 0; l < layer_cells.size(); ++l) unborn[l] = layer_cells[l].size();
  layer_faces.resize(layer_cells.size());
  layer_top_mm.assign(layer_cells.size(), -std::numeric_limits<double>::infinity());
  first_sample.assign(mesh.cells.size() + 1, 0);
  if (!mesh.cell_grid) return;
  std::vector<Face> faces = surface_faces();
  choose_samples(faces);
  for (const Face& f : faces) {
    const std::size_t l = layer_of(f.cell);
    layer_faces[l].push_back(f);
    layer_top_mm[l] = std::max(layer_top_mm[l], (f.ijk.z() + 1.0) * vs);
  }
  device.emplace();
}

std::vector<Face> SkyView::Impl::surface_faces() const {
  // The faces towards the outside air: not towards material (another cell's or its own), an enclosed gap or
  // the table under the lowest row.
  const openvdb::Int32Tree& cells = mesh.cell_grid->tree();
  const int table_k = static_cast<int>(std::lround(mesh.table_z_mm / vs));
  openvdb::tree::ValueAccessor<const openvdb::Int32Tree> cell_at(cells);
  std::optional<openvdb::tree::ValueAccessor<const openvdb::MaskTree>> gap_at;
  if (mesh.gaps) gap_at.emplace(mesh.gaps->tree());
  std::vector<Face> faces;
  for (auto it = cells.cbeginValueOn(); it; ++it) {
    const openvdb::Coord ijk = it.getCoord();
    for (int d = 0; d < 6; ++d) {
      const openvdb::Coord q = ijk + kFaceSteps[static_cast<std::size_t>(d)];
      if (cell_at.isValueOn(q) || (gap_at && gap_at->isValueOn(q))) continue;
      if (d == kDown && ijk.z() == table_k) continue;
      faces.push_back({static_cast<std::uint32_t>(*it), static_cast<std::uint8_t>(d), ijk});
    }
  }
  return faces;
}

void SkyView::Impl::choose_samples(std::vector<Face>& faces) {
  // By cell, then direction, then the grid's voxel order (a stable sort keeps it): even picks in that order
  // share a cell's samples among its directions by their areas.
  std::stable_sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) {
    return a.cell != b.cell ? a.cell < b.cell : a.dir < b.dir;
  });
  const auto per_cell = static_cast<std::size_t>(options.faces_per_cell);
  for (std::size_t begin = 0; begin < faces.size();) {
    const std::uint32_t c = faces[begin].cell;
    std::size_t end = begin;
    while (end < faces.size() && faces[end].cell == c) ++end;
    const std::size_t n = end - begin, picks = std::min(n, per_cell);
    for (std::size_t j = 0; j < picks; ++j) {
      const Face& f = faces[begin + (2 * j + 1) * n / (2 * picks)];
      samples.push_back({face_centre(f, vs) + static_cast<float>(kLiftVoxels * vs) * axis(f.dir), f.dir});
    }
    first_sample[c + 1] = picks;
    begin = end;
  }
  for (std::size_t c = 0; c < mesh.cells.size(); ++c) first_sample[c + 1] += first_sample[c];
}

void SkyView::Impl::add_layer(std::size_t layer) {
  top_mm = std::max(top_mm, layer_top_mm[layer]);
  blocks.push_back({.layers = 1, .faces = std::move(layer_faces[layer]), .scene = std::nullopt});
  while (blocks.size() >= 2 && blocks[blocks.size() - 2].layers <= blocks.back().layers) {
    Block& into = blocks[blocks.size() - 2];
    into.layers += blocks.back().layers;
    into.faces.insert(into.faces.end(), blocks.back().faces.begin(), blocks.back().faces.end());
    into.scene.reset();
    blocks.pop_back();
  }
}

void SkyView::Impl::instance_blocks() {
  scene.emplace(*device);
  const std::array<float, 12> identity = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  for (Block& b : blocks) {
    if (b.faces.empty()) continue;
    if (!b.scene) b.scene.emplace(faces_scene(b.faces));
    embree::Geometry instance(*device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(instance.get(), b.scene->get());
    rtcSetGeometryTransform(instance.get(), 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity.data());
    instance.commit();
    scene->attach(instance);
  }
  scene->commit();
}

embree::Scene SkyView::Impl::faces_scene(const std::vector<Face>& faces) const {
  embree::Geometry quads(*device, RTC_GEOMETRY_TYPE_QUAD);
  auto points =
      quads.new_buffer<std::array<float, 3>>(RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 4 * faces.size());
  auto index = quads.new_buffer<std::array<std::uint32_t, 4>>(RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4,
                                                              faces.size());
  const auto half = static_cast<float>(0.5 * vs);
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const int a = faces[k].dir / 2;
    const Eigen::Vector3f centre = face_centre(faces[k], vs);
    const Eigen::Vector3f t1 = half * axis(2 * ((a + 1) % 3)), t2 = half * axis(2 * ((a + 2) % 3));
    const std::array<Eigen::Vector3f, 4> corner = {centre - t1 - t2, centre + t1 - t2, centre + t1 + t2,
                                                   centre - t1 + t2};
    for (std::size_t j = 0; j < 4; ++j) points[4 * k + j] = {corner[j].x(), corner[j].y(), corner[j].z()};
    const auto v = static_cast<std::uint32_t>(4 * k);
    index[k] = {v, v + 1, v + 2, v + 3};
  }
  quads.commit();
  embree::Scene part(*device);
  // Robust: no ray slips between two faces along their shared edge.
  part.set_flags(RTC_SCENE_FLAG_ROBUST);
  part.attach(quads);
  part.commit();
  return part;
}

CellView SkyView::Impl::view_of(std::uint32_t cell) const {
  const std::size_t first = first_sample[cell], count = first_sample[cell + 1] - first;
  if (count == 0) return {};
  const int per_sample = options.rays_per_cell / static_cast<int>(count);
  double sky = 0.0, table = 0.0;
  for (std::size_t s = first; s < first + count; ++s) {
    const Sample& sample = samples[s];
    const int a = sample.dir / 2;
    const Eigen::Vector3f n = axis(sample.dir), t1 = axis(2 * ((a + 1) % 3)), t2 = axis(2 * ((a + 2) % 3));
    const double turn = turn_of(cell, static_cast<int>(s - first));
    int up = 0, down = 0;
    // In packets of 16 rays from the sample's point.
    for (int k0 = 0; k0 < per_sample; k0 += 16) {
      RTCRay16 rays{};
      std::array<int, 16> valid{};
      std::array<bool, 16> towards_table{};
      for (int j = 0; j < 16 && k0 + j < per_sample; ++j) {
        // Equal areas of the unit disk along a spiral, lifted onto the hemisphere: cosine-weighted.
        const int k = k0 + j;
        const double u = (k + 0.5) / per_sample;
        const double phi = 2.0 * std::numbers::pi * (k * (std::numbers::phi - 1.0) + turn);
        const auto r = static_cast<float>(std::sqrt(u));
        const Eigen::Vector3f d = r * static_cast<float>(std::cos(phi)) * t1 +
                                  r * static_cast<float>(std::sin(phi)) * t2 +
                                  static_cast<float>(std::sqrt(1.0 - u)) * n;
        rays.org_x[j] = sample.origin.x(), rays.org_y[j] = sample.origin.y(),
        rays.org_z[j] = sample.origin.z();
        rays.dir_x[j] = d.x(), rays.dir_y[j] = d.y(), rays.dir_z[j] = d.z();
        // Down, a ray ends on the table unless the part is in the way.
        towards_table[static_cast<std::size_t>(j)] = d.z() < 0.0f;
        rays.tfar[j] =
            d.z() < 0.0f ? (table_z - sample.origin.z()) / d.z() : std::numeric_limits<float>::infinity();
        rays.mask[j] = 0xFFFFFFFFu;
        valid[static_cast<std::size_t>(j)] = rays.tfar[j] > 0.0f ? -1 : 0;
      }
      scene->occluded16(valid.data(), rays, false);
      for (std::size_t j = 0; j < 16; ++j)
        if (valid[j] != 0 && rays.tfar[j] >= 0.0f) ++(towards_table[j] ? down : up);
    }
    sky += static_cast<double>(up) / per_sample;
    table += static_cast<double>(down) / per_sample;
  }
  return {.sky = static_cast<float>(sky / static_cast<double>(count)),
          .table = static_cast<float>(table / static_cast<double>(count))};
}

std::vector<ViewChange> SkyView::Impl::update(std::size_t now_born) {
  BT_CHECK(now_born >= born && now_born <= mesh.cells.size());
  std::vector<std::size_t> complete;
  for (; born < now_born; ++born) {
    const std::size_t l = layer_of(static_cast<std::uint32_t>(born));
    if (--unborn[l] == 0) complete.push_back(l);
  }
  if (complete.empty() || !device) return {};
  for (const std::size_t l : complete) add_layer(l);
  instance_blocks();
  std::vector<std::uint32_t> cells;
  for (const std::size_t l : complete)
    for (const std::uint32_t c : layer_cells[l])
      if (first_sample[c + 1] > first_sample[c]) cells.push_back(c);
  while (!due.empty() && due.top().first <= top_mm) {
    cells.push_back(due.top().second);
    due.pop();
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  std::vector<ViewChange> out(cells.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t k = r.begin(); k != r.end(); ++k)
                        out[k] = {cells[k], view_of(cells[k])};
                    });
  for (const std::uint32_t c : cells) {
    const std::size_t count = first_sample[c + 1] - first_sample[c];
    rays_total += count * static_cast<std::size_t>(options.rays_per_cell / static_cast<int>(count));
    // Due again when the height of the top above it has grown by 1 + regrow (at least half a voxel now).
    const double z = mesh.cells[c].centroid_mm.z();
    due.emplace(z + (1.0 + options.regrow) * std::max(top_mm - z, 0.5 * vs), c);
  }
  computed += cells.size();
  return out;
}

SkyView::SkyView(const ThermalMesh& mesh, const ViewFactorOptions& options)
    : impl_(std::make_unique<Impl>(mesh, options)) {}
SkyView::~SkyView() = default;

std::vector<ViewChange> SkyView::update(std::size_t born) {
  return impl_->update(born);
}
std::size_t SkyView::rays_cast() const {
  return impl_->rays_total;
}
std::size_t SkyView::updates() const {
  return impl_->computed;
}

}  // namespace beadtwin::thermal
