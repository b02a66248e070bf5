#include "thermal/mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"

namespace beadtwin::thermal {
namespace {

constexpr double kJoinMm = 1e-3;  // a move continues a chain when it starts this close to the last end

// Which chain (continuous bead) each depositing move belongs to and where along it the move starts.
struct Chains {
  std::vector<std::uint32_t> of_move;  // chain index per move (unused for moves that do not deposit)
  std::vector<double> offset_mm;       // plan length of the chain before the move
  std::vector<double> piece_mm;        // per chain: the length of one piece
  std::vector<std::uint32_t> pieces;   // per chain: how many pieces
  double length_factor = 1.0;          // automatic pieces made this many times longer (MeshOptions)
};

double plan_length(const Move& m) {
  return (m.end - m.start).head<2>().norm();
}

Chains find_chains(const Toolpath& tp, const MeshOptions& o) {
  const double cell_length_mm = o.cell_length_mm;
  Chains c;
  c.of_move.assign(tp.moves.size(), 0);
  c.offset_mm.assign(tp.moves.size(), 0.0);
  std::vector<double> length, widest;
  bool open = false;  // a chain is open and the next depositing move may continue it
  Eigen::Vector3d last_end = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < tp.moves.size(); ++i) {
    const Move& m = tp.moves[i];
    if (!m.deposits()) {
      if (plan_length(m) > 0.0 || std::abs(m.end.z() - m.start.z()) > 0.0) open = false;  // a travel
      continue;
    }
    if (!open || (m.start - last_end).norm() > kJoinMm) {
      length.push_back(0.0);
      widest.push_back(0.0);
    }
    const std::size_t chain = length.size() - 1;
    c.of_move[i] = static_cast<std::uint32_t>(chain);
    c.offset_mm[i] = length[chain];
    length[chain] += plan_length(m);
    widest[chain] =
        std::max(widest[chain], m.bead_width_mm > 0.0 ? m.bead_width_mm : 2.0 * m.layer_height_mm);
    last_end = m.end;
    open = true;
  }
  if (cell_length_mm <= 0.0) {  // two bead widths, unless that makes too many cells
    double pieces = 0.0;
    for (std::size_t k = 0; k < length.size(); ++k) pieces += std::max(1.0, length[k] / (2.0 * widest[k]));
    const double cells = pieces * o.cells_across * o.cells_through;
    if (cells > static_cast<double>(o.max_automatic_cells))
      c.length_factor = cells / static_cast<double>(o.max_automatic_cells);
  }
  for (std::size_t k = 0; k < length.size(); ++k) {
    const double target = cell_length_mm > 0.0 ? cell_length_mm : 2.0 * widest[k] * c.length_factor;
    const auto n = static_cast<std::uint32_t>(std::max(1.0, std::round(length[k] / target)));
    c.pieces.push_back(n);
    c.piece_mm.push_back(length[k] > 0.0 ? length[k] / n : 1.0);
  }
  return c;
}

// A cell's name before it has an index: chain, piece, strip, slice.
using CellKey = std::uint64_t;
CellKey make_key(std::uint32_t chain, std::uint32_t piece, int across, int through) {
  return (static_cast<std::uint64_t>(chain) << 32) | (static_cast<std::uint64_t>(piece & 0xFFFFFFu) << 8) |
         (static_cast<std::uint64_t>(across) << 4) | static_cast<std::uint64_t>(through);
}
std::uint32_t key_chain(CellKey k) {
  return static_cast<std::uint32_t>(k >> 32);
}
std::uint32_t key_piece(CellKey k) {
  return static_cast<std::uint32_t>((k >> 8) & 0xFFFFFFu);
}

struct Placement {
  CellKey key = 0;
  double cos2 = 1.0, sin2 = 0.0;  // the move's direction as a doubled angle (an axis)
};

// The cell of the material at `p` (a voxel centre) laid by move `m`.
Placement place(const Toolpath& tp, const Chains& chains, const MeshOptions& o, std::size_t m,
                const Eigen::Vector3d& p) {
  const Move& mv = tp.moves[m];
  const Eigen::Vector2d d = (mv.end - mv.start).head<2>();
  const double len = d.norm();
  double along = 0.0, lateral = 0.0, z_top = mv.end.z();
  Placement out;
  if (len > 1e-9) {
    const Eigen::Vector2d u = d / len;
    const Eigen::Vector2d r = p.head<2>() - mv.start.head<2>();
    along = std::clamp(r.dot(u), 0.0, len);
    lateral = r.dot(Eigen::Vector2d(-u.y(), u.x()));
    z_top = mv.start.z() + (mv.end.z() - mv.start.z()) * (along / len);
    out.cos2 = u.x() * u.x() - u.y() * u.y();
    out.sin2 = 2.0 * u.x() * u.y();
  }
  const std::uint32_t chain = chains.of_move[m];
  const double s = chains.offset_mm[m] + along;
  const auto piece = std::min(chains.pieces[chain] - 1,
                              static_cast<std::uint32_t>(std::max(0.0, s / chains.piece_mm[chain])));
  const double h = mv.layer_height_mm;
  const double w = mv.bead_width_mm > 0.0 ? mv.bead_width_mm : 2.0 * h;
  int across = o.cells_across / 2;
  if (len > 1e-9)
    across =
        std::clamp(static_cast<int>(std::floor((lateral / w + 0.5) * o.cells_across)), 0, o.cells_across - 1);
  const int through =
      std::clamp(static_cast<int>(std::floor((z_top - p.z()) / h * o.cells_through)), 0, o.cells_through - 1);
  out.key = make_key(chain, piece, across, through);
  return out;
}

struct CellSums {
  double fill = 0.0;  // voxel volumes
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  double time = 0.0;
  double cos2 = 0.0, sin2 = 0.0;
  std::size_t move = 0;
  bool any = false;
};

void check_options(const MeshOptions& o) {
  if (o.cells_across < 1 || o.cells_across > 15 || o.cells_across % 2 == 0)
    throw InputError({}, "thermal.cells_across",
                     fmt::format("must be an odd whole number from 1 to 15, got {}", o.cells_across));
  if (o.cells_through < 1 || o.cells_through > 15)
    throw InputError({}, "thermal.cells_through",
                     fmt::format("must be a whole number from 1 to 15, got {}", o.cells_through));
  if (!(o.cell_length_mm >= 0.0) || !std::isfinite(o.cell_length_mm))
    throw InputError({}, "thermal.cell_length", fmt::format("must be 0 or more, got {}", o.cell_length_mm));
}

const std::array<openvdb::Coord, 6> kFaces = {openvdb::Coord(1, 0, 0), openvdb::Coord(-1, 0, 0),
                                              openvdb::Coord(0, 1, 0), openvdb::Coord(0, -1, 0),
                                              openvdb::Coord(0, 0, 1), openvdb::Coord(0, 0, -1)};

// Step 1 of the mesh: every material voxel placed in its cell, and the cells' sums, in the order the cells
// are met (the fill's voxel order). Each voxel's cell is kept, by its number met, for the cell grid (step 3).
struct MetCells {
  std::vector<CellSums> sums;
  std::vector<CellKey> keys;
  std::vector<std::uint32_t> voxel_cell;  // per voxel of the fill, in its order
};

MetCells meet_cells(const Toolpath& toolpath, const sim::Deposit& deposit, const Chains& chains,
                    const MeshOptions& options) {
  const double vs = deposit.voxel_size_mm;
  const openvdb::FloatTree& fill = deposit.fill->tree();
  const openvdb::Int32Tree& moves = deposit.move->tree();
  const openvdb::FloatTree& times = deposit.time->tree();
  MetCells met;
  std::unordered_map<CellKey, std::uint32_t> number;
  met.voxel_cell.reserve(static_cast<std::size_t>(fill.activeVoxelCount()));
  openvdb::tree::ValueAccessor<const openvdb::Int32Tree> move_at(moves);
  openvdb::tree::ValueAccessor<const openvdb::FloatTree> time_at(times);
  CellKey last_key = 0;
  std::uint32_t last = std::numeric_limits<std::uint32_t>::max();
  // Leaf by leaf; the move and time of a voxel from its leaves' buffers where the grids have the leaf (they
  // share the fill's topology), else through the accessors.
  for (auto leaf = fill.cbeginLeaf(); leaf; ++leaf) {
    const auto* move_leaf = moves.probeConstLeaf(leaf->origin());
    const auto* time_leaf = times.probeConstLeaf(leaf->origin());
    for (auto it = leaf->cbeginValueOn(); it; ++it) {
      const openvdb::Coord ijk = it.getCoord();
      const openvdb::Index n = it.pos();
      const int move = move_leaf ? move_leaf->getValue(n) : move_at.getValue(ijk);
      BT_CHECK(move >= 0 && static_cast<std::size_t>(move) < toolpath.moves.size());
      const Eigen::Vector3d centre = sim::voxel_center_mm(ijk, vs);
      const Placement pl = place(toolpath, chains, options, static_cast<std::size_t>(move), centre);
      if (last == std::numeric_limits<std::uint32_t>::max() ||
          pl.key != last_key) {  // neighbours mostly share
        const auto [entry, added] = number.try_emplace(pl.key, static_cast<std::uint32_t>(met.sums.size()));
        if (added) {
          met.sums.emplace_back();
          met.keys.push_back(pl.key);
        }
        last = entry->second;
        last_key = pl.key;
      }
      met.voxel_cell.push_back(last);
      CellSums& c = met.sums[last];
      const double f = *it;
      c.fill += f;
      c.moment += f * centre;
      c.time += f * (time_leaf ? time_leaf->getValue(n) : time_at.getValue(ijk));
      c.cos2 += f * pl.cos2;
      c.sin2 += f * pl.sin2;
      if (!c.any || static_cast<std::size_t>(move) < c.move) c.move = static_cast<std::size_t>(move);
      c.any = true;
    }
  }
  return met;
}

// Step 2: the cells from their sums, by birth time (ties: by key) into mesh.cells. Returns each cell's key by
// index, and fills `index_of_met` with each cell's index by its number met.
std::vector<CellKey> order_cells(const Toolpath& toolpath, const MetCells& met, double voxel_volume_mm3,
                                 std::vector<ThermalCell>& cells, std::vector<std::int32_t>& index_of_met) {
  struct Met {
    CellKey key;
    ThermalCell cell;
    std::uint32_t number;  // in the order met
  };
  // The slices of one strip through the bead's height are born together, from its first move: their
  // material lands in one pass, and born together they come one after another in birth order (top slice
  // first), which the lumper needs to merge them into one cell once the bead is covered (thermal/lumper.hpp).
  struct Strip {
    double time = 0.0, fill = 0.0;
    std::size_t move = std::numeric_limits<std::size_t>::max();
  };
  std::unordered_map<CellKey, Strip> strips;
  for (std::size_t m = 0; m < met.sums.size(); ++m) {
    Strip& s = strips[met.keys[m] >> 4];
    s.time += met.sums[m].time, s.fill += met.sums[m].fill;
    s.move = std::min(s.move, met.sums[m].move);
  }
  std::vector<Met> by_birth;
  by_birth.reserve(met.sums.size());
  for (std::size_t m = 0; m < met.sums.size(); ++m) {
    const CellSums& c = met.sums[m];
    const Strip& strip = strips.at(met.keys[m] >> 4);
    ThermalCell cell;
    cell.volume_mm3 = c.fill * voxel_volume_mm3;
    cell.centroid_mm = c.fill > 0.0 ? Eigen::Vector3d(c.moment / c.fill) : Eigen::Vector3d::Zero();
    cell.birth_s = strip.fill > 0.0 ? strip.time / strip.fill : 0.0;
    const double angle = 0.5 * std::atan2(c.sin2, c.cos2);
    cell.along = Eigen::Vector2d(std::cos(angle), std::sin(angle));
    cell.move = strip.move;
    cell.layer = toolpath.moves[strip.move].layer;
    by_birth.push_back({met.keys[m], cell, static_cast<std::uint32_t>(m)});
  }
  std::sort(by_birth.begin(), by_birth.end(), [](const Met& x, const Met& y) {
    return x.cell.birth_s != y.cell.birth_s ? x.cell.birth_s < y.cell.birth_s : x.key < y.key;
  });
  std::vector<CellKey> keys;  // by index (birth order)
  index_of_met.assign(by_birth.size(), 0);
  keys.reserve(by_birth.size());
  cells.reserve(by_birth.size());
  for (std::size_t i = 0; i < by_birth.size(); ++i) {
    index_of_met[by_birth[i].number] = static_cast<std::int32_t>(i);
    keys.push_back(by_birth[i].key);
    cells.push_back(by_birth[i].cell);
  }
  return keys;
}

// Step 3: the cell of every material voxel, as a grid with the fill's topology.
openvdb::Int32Grid::Ptr make_cell_grid(const sim::Deposit& deposit, std::span<const std::uint32_t> voxel_cell,
                                       std::span<const std::int32_t> index_of_met) {
  openvdb::Int32Grid::Ptr grid = openvdb::Int32Grid::create(
      std::make_shared<openvdb::Int32Tree>(deposit.fill->tree(), -1, openvdb::TopologyCopy()));
  grid->setTransform(deposit.fill->transform().copy());
  grid->setName("cell");
  std::size_t j = 0;
  for (auto it = grid->tree().beginValueOn(); it; ++it) {
    BT_CHECK(j < voxel_cell.size());
    it.setValue(index_of_met[voxel_cell[j++]]);
  }
  BT_CHECK_OP(j, ==, voxel_cell.size());
  return grid;
}

struct Contact {
  Eigen::Vector3d vector = Eigen::Vector3d::Zero();
  double faces = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();  // Σ face area × face centre
};

// A voxel's open surface (the vector sum of its open faces, `open`, mm²) as the cell's half cell sees it
// (ThermalCell::open_depth_mm3): the surface lies at the voxel's centre `centre` moved along the normal by
// the voxel's fill less a half (material fills a voxel from its inner side), at least a quarter voxel from
// the cell's centroid.
Eigen::Vector3d open_depth(const ThermalCell& cell, const Eigen::Vector3d& centre,
                           const Eigen::Vector3d& open, double fill, double vs) {
  const double area = open.norm();
  if (!(area > 0.0)) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d n = open / area;
  const double depth = std::max((centre - cell.centroid_mm).dot(n) + (fill - 0.5) * vs, 0.25 * vs);
  const Eigen::Vector3d along(cell.along.x(), cell.along.y(), 0.0);
  const Eigen::Vector3d across(-cell.along.y(), cell.along.x(), 0.0);
  const double a = n.dot(along), c = n.dot(across);
  return area * depth * Eigen::Vector3d(a * a, c * c, n.z() * n.z());
}
// By the lower-numbered cell of each pair: the higher one and their contact. A cell touches a dozen others or
// so, so a short list searched in order beats a hash map over all the pairs.
using ContactLists = std::vector<std::vector<std::pair<std::uint32_t, Contact>>>;

// Step 4: the voxels' faces. Adds each cell's open and table area to mesh.cells, sets mesh.table_z_mm, and
// returns the contacts between cells.
ContactLists sum_faces(const sim::Deposit& deposit, ThermalMesh& mesh) {
  const double vs = deposit.voxel_size_mm;
  const double face_area = vs * vs;
  const openvdb::FloatTree& fill = deposit.fill->tree();
  const int table_k = deposit.fill->evalActiveVoxelBoundingBox().min().z();
  mesh.table_z_mm = table_k * vs;
  ContactLists contacts(mesh.cells.size());
  openvdb::tree::ValueAccessor<const openvdb::FloatTree> fill_at(fill);
  openvdb::tree::ValueAccessor<const openvdb::Int32Tree> cell_at(mesh.cell_grid->tree());
  std::optional<openvdb::tree::ValueAccessor<const openvdb::MaskTree>> gap_at;
  if (deposit.gaps) gap_at.emplace(deposit.gaps->tree());
  // Leaf by leaf, in the order of the fill's voxels: a neighbour in the same leaf is read from the leaves'
  // buffers, one across its border through the accessors.
  static_assert(openvdb::FloatTree::LeafNodeType::LOG2DIM == 3 &&
                openvdb::Int32Tree::LeafNodeType::LOG2DIM == 3);
  // The step of a voxel's offset in its leaf towards each face (kFaces' order: offset = 64 x + 8 y + z).
  constexpr std::array<int, 6> kStep = {64, -64, 8, -8, 1, -1};
  for (auto leaf = fill.cbeginLeaf(); leaf; ++leaf) {
    const auto* cell_leaf = mesh.cell_grid->tree().probeConstLeaf(leaf->origin());
    BT_CHECK(cell_leaf != nullptr);  // the cell grid has the fill's topology
    const float* leaf_fill = leaf->buffer().data();
    const std::int32_t* leaf_cell = cell_leaf->buffer().data();
    const auto& on = leaf->getValueMask();
    for (auto it = leaf->cbeginValueOn(); it; ++it) {
      const auto n = static_cast<int>(it.pos());
      const openvdb::Coord ijk = it.getCoord();
      const double f = *it;
      const std::int32_t cell = leaf_cell[n];
      const std::array<int, 3> local = {n >> 6, (n >> 3) & 7, n & 7};
      Eigen::Vector3d open = Eigen::Vector3d::Zero();
      for (std::size_t d = 0; d < kFaces.size(); ++d) {
        const openvdb::Coord q = ijk + kFaces[d];
        const Eigen::Vector3d normal(kFaces[d].x(), kFaces[d].y(), kFaces[d].z());
        const int along = local[d / 2];
        const bool inside = d % 2 == 0 ? along < 7 : along > 0;  // the neighbour is in this leaf
        const int m = n + kStep[d];
        const double fq =
            inside ? (on.isOn(static_cast<openvdb::Index>(m)) ? static_cast<double>(leaf_fill[m]) : 0.0)
            : fill_at.isValueOn(q) ? static_cast<double>(fill_at.getValue(q))
                                   : 0.0;
        if (fq > 0.0) {
          const std::int32_t other = inside ? leaf_cell[m] : cell_at.getValue(q);
          if (other == cell) {
            if (f > fq) open += normal * (face_area * (f - fq));
          } else if (d % 2 == 0) {  // each shared face once, from its lower side
            const auto a = static_cast<std::uint32_t>(std::min(cell, other));
            const auto b = static_cast<std::uint32_t>(std::max(cell, other));
            const double sign = cell < other ? 1.0 : -1.0;
            auto& list = contacts[a];
            auto entry = std::find_if(list.begin(), list.end(), [b](const auto& e) { return e.first == b; });
            if (entry == list.end()) entry = list.insert(list.end(), {b, Contact{}});
            Contact& c = entry->second;
            const double shared = face_area * std::min(f, fq);
            c.vector += sign * normal * shared;
            c.faces += shared;
            c.moment += shared * (sim::voxel_center_mm(ijk, vs) + 0.5 * vs * normal);
          }
          continue;
        }
        if (gap_at && gap_at->isValueOn(q)) continue;  // an enclosed gap: no air
        if (d == 5 && ijk.z() == table_k) {
          mesh.cells[static_cast<std::size_t>(cell)].table_area_mm2 += face_area * f;
          continue;
        }
        open += normal * (face_area * f);
      }
      ThermalCell& owner = mesh.cells[static_cast<std::size_t>(cell)];
      owner.open_area_mm2 += open.norm();
      owner.open_depth_mm3 += open_depth(owner, sim::voxel_center_mm(ijk, vs), open, f, vs);
    }
  }
  return contacts;
}

// Step 5: the links in the order of their pairs (by the lower cell, then the higher); interfaces between
// chains, or between pieces of one chain that are not neighbours. `keys`: each cell's key by index.
std::vector<ThermalLink> make_links(ContactLists& contacts, std::span<const CellKey> keys) {
  std::size_t link_count = 0;
  for (auto& list : contacts) {
    std::sort(list.begin(), list.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    link_count += list.size();
  }
  std::vector<ThermalLink> links;
  links.reserve(link_count);
  for (std::size_t a = 0; a < contacts.size(); ++a)
    for (const auto& [b, c] : contacts[a]) {
      ThermalLink link;
      link.a = static_cast<std::uint32_t>(a);
      link.b = b;
      link.area_vector_mm2 = c.vector;
      link.faces_mm2 = c.faces;
      if (c.faces > 0.0) link.face_centroid_mm = c.moment / c.faces;
      const CellKey ka = keys[link.a], kb = keys[link.b];
      const bool same_chain = key_chain(ka) == key_chain(kb);
      const std::uint32_t pa = key_piece(ka), pb = key_piece(kb);
      link.interface = !same_chain || (pa > pb ? pa - pb : pb - pa) > 1;
      links.push_back(link);
    }
  return links;
}

// What the user is told when the automatic cells were made longer.
std::string longer_cells_note(const ThermalMesh& mesh) {
  const double at_two_widths = mesh.cell_length_factor * static_cast<double>(mesh.cells.size());
  return fmt::format(
      "thermal cells made {:.3g} times two bead widths long, {} cells: at two bead widths there would be "
      "about {}, too many to solve in reasonable time; set thermal.cell_length to choose",
      mesh.cell_length_factor, mesh.cells.size(),
      at_two_widths >= 1e6 ? fmt::format("{:.3g} million", at_two_widths / 1e6)
                           : fmt::format("{:.0f}", at_two_widths));
}

}  // namespace

double ThermalLink::area_mm2() const {
  return std::max(area_vector_mm2.norm(), faces_mm2 / std::sqrt(3.0));
}

ThermalMesh build_thermal_mesh(const Toolpath& toolpath, const sim::Deposit& deposit,
                               const MeshOptions& options) {
  check_options(options);
  ThermalMesh mesh;
  const double vs = deposit.voxel_size_mm;
  mesh.voxel_size_mm = vs;
  mesh.gaps = deposit.gaps;
  if (!deposit.fill || deposit.fill->activeVoxelCount() == 0) return mesh;
  BT_CHECK(deposit.move && deposit.time);
  // The steps go over the fill leaf by leaf: a deposit's grids hold voxels, never active tiles.
  BT_CHECK(!deposit.fill->tree().hasActiveTiles());
  const Chains chains = find_chains(toolpath, options);
  mesh.chains = chains.pieces.size();
  mesh.cell_length_factor = chains.length_factor;
  std::vector<std::int32_t> index_of_met;
  std::vector<CellKey> keys;
  {
    const MetCells met = meet_cells(toolpath, deposit, chains, options);
    keys = order_cells(toolpath, met, vs * vs * vs, mesh.cells, index_of_met);
    mesh.cell_grid = make_cell_grid(deposit, met.voxel_cell, index_of_met);
  }
  ContactLists contacts = sum_faces(deposit, mesh);
  mesh.links = make_links(contacts, keys);
  mesh.support = support_cells(mesh, &toolpath);
  if (mesh.cell_length_factor > 1.0) mesh.notes.push_back(longer_cells_note(mesh));
  return mesh;
}

std::size_t planned_cell_count(const Toolpath& toolpath, const MeshOptions& options) {
  const Chains chains = find_chains(toolpath, options);
  std::size_t pieces = 0;
  for (const std::uint32_t n : chains.pieces) pieces += n;
  return pieces * static_cast<std::size_t>(options.cells_across) *
         static_cast<std::size_t>(options.cells_through);
}

// Bytes a thermal cell takes while the heat is solved: its links, the integrator's vectors, its history.
// Measured on whole runs (docs/RELIABILITY.md).
constexpr double kThermalBytesPerCell = 3000.0;

MemoryCost thermal_cost(const Toolpath& toolpath, const sim::Deposit& deposit, const MeshOptions& options) {
  return {.fixed_bytes = kThermalBytesPerCell * static_cast<double>(planned_cell_count(toolpath, options)),
          .volume_bytes = deposit.layer ? static_cast<double>(deposit.layer->memUsage()) : 0.0};
}

}  // namespace beadtwin::thermal
