// The interfaces of the heat solve as its step loop reads them, internal to the thermal library: by the mesh
// cell that opens each one (its younger cell, born with it) and by model cell (after lumping several mesh
// cells are one model cell: thermal/part_model.hpp).
//
// The index by model cell is flat, each entry with the interface's other cell beside it: the scan for the
// interfaces that heal, after every step, reads memory in order rather than chasing per-cell lists and
// interface records. An interface inside one lumped cell is listed apart (inner): both its sides are at the
// lumped cell's temperature, so it heals at the lumped cell's rate.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "thermal/heat.hpp"
#include "thermal/mesh.hpp"

namespace beadtwin::thermal {

// The interfaces of `mesh`, as results still to fill: one per interface link, in link order, with its cells
// (older: the link's a, younger: its b), its area and whether the younger lands on top (its contact within
// 60° of horizontal).
std::vector<InterfaceResult> list_interfaces(const ThermalMesh& mesh);

// The interfaces by younger mesh cell and by model cell, re-indexed when cells are lumped.
class InterfaceIndex {
 public:
  // One of a model cell's interfaces with another model cell.
  struct CellInterface {
    std::uint32_t interface, other, younger;  // the younger of the two model cells
  };

  // The interfaces of a mesh of `mesh_cells` cells (each cell below mesh_cells), indexed by younger mesh
  // cell, and by model cell with every mesh cell its own model cell.
  InterfaceIndex(std::span<const InterfaceResult> interfaces, std::size_t mesh_cells);

  // Indexes the interfaces by model cell anew: model_of[i] is mesh cell i's model cell (non-decreasing),
  // model_of.back() the model's cell count.
  void index(std::span<const std::uint32_t> model_of);

  std::size_t size() const { return cells_of_.size(); }               // interfaces
  std::size_t model_cells() const { return cell_first_.size() - 1; }  // model cells indexed
  // The interfaces whose younger cell is mesh cell i, in interface order.
  std::span<const std::uint32_t> of_younger(std::size_t i) const {
    return {by_younger_.data() + younger_first_[i], by_younger_.data() + younger_first_[i + 1]};
  }
  // Interface k's two model cells: the older's, the younger's.
  const std::array<std::uint32_t, 2>& cells(std::size_t k) const { return cells_of_[k]; }
  // Model cell g's interfaces with other model cells.
  std::span<const CellInterface> of_cell(std::size_t g) const {
    return {cell_interfaces_.data() + cell_first_[g], cell_interfaces_.data() + cell_first_[g + 1]};
  }
  // The interfaces inside model cell g (between mesh cells lumped into it).
  std::span<const std::uint32_t> inner(std::size_t g) const {
    return {inner_.data() + inner_first_[g], inner_.data() + inner_first_[g + 1]};
  }
  bool has_inner(std::size_t g) const { return inner_first_[g] != inner_first_[g + 1]; }

 private:
  std::vector<std::array<std::uint32_t, 2>> mesh_cells_of_;  // per interface: older, younger mesh cell
  std::vector<std::size_t> younger_first_;
  std::vector<std::uint32_t> by_younger_;
  // Each interface's two model cells, packed: the healing rate reads them for every healing interface twice
  // a step.
  std::vector<std::array<std::uint32_t, 2>> cells_of_;
  std::vector<std::size_t> cell_first_;  // model cell g's entries: [cell_first_[g], cell_first_[g + 1])
  std::vector<CellInterface> cell_interfaces_;
  std::vector<std::size_t> inner_first_;  // model cell g's inner interfaces: [inner_first_[g], [g + 1])
  std::vector<std::uint32_t> inner_;
};

}  // namespace beadtwin::thermal
