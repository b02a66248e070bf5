#include "thermal/interface_index.hpp"

#include <cmath>
#include <numeric>

namespace beadtwin::thermal {

std::vector<InterfaceResult> list_interfaces(const ThermalMesh& mesh) {
  std::vector<InterfaceResult> interfaces;
  for (const ThermalLink& link : mesh.links) {
    if (!link.interface) continue;
    InterfaceResult r;
    r.older = link.a;
    r.younger = link.b;
    r.area_mm2 = link.area_mm2();
    const double length = link.area_vector_mm2.norm();
    r.on_top = length > 0.0 && std::abs(link.area_vector_mm2.z()) >= 0.5 * length;
    interfaces.push_back(r);
  }
  return interfaces;
}

InterfaceIndex::InterfaceIndex(std::span<const InterfaceResult> interfaces, std::size_t mesh_cells)
    : mesh_cells_of_(interfaces.size()), cells_of_(interfaces.size()) {
  younger_first_.assign(mesh_cells + 1, 0);
  for (std::size_t k = 0; k < interfaces.size(); ++k) {
    mesh_cells_of_[k] = {interfaces[k].older, interfaces[k].younger};
    ++younger_first_[interfaces[k].younger + 1];
  }
  for (std::size_t i = 0; i < mesh_cells; ++i) younger_first_[i + 1] += younger_first_[i];
  by_younger_.resize(interfaces.size());
  std::vector<std::size_t> next(younger_first_.begin(), younger_first_.end() - 1);
  for (std::size_t k = 0; k < interfaces.size(); ++k)
    by_younger_[next[interfaces[k].younger]++] = static_cast<std::uint32_t>(k);
  std::vector<std::uint32_t> model_of(mesh_cells + 1);
  std::iota(model_of.begin(), model_of.end(), 0u);
  index(model_of);
}

void InterfaceIndex::index(std::span<const std::uint32_t> model_of) {
  const std::size_t m = model_of.back();
  cell_first_.assign(m + 1, 0);
  inner_first_.assign(m + 1, 0);
  for (std::size_t k = 0; k < cells_of_.size(); ++k) {
    const std::uint32_t a = model_of[mesh_cells_of_[k][0]], b = model_of[mesh_cells_of_[k][1]];
    cells_of_[k] = {a, b};
    if (a == b) {
      ++inner_first_[a + 1];
    } else {
      ++cell_first_[a + 1];
      ++cell_first_[b + 1];
    }
  }
  for (std::size_t g = 0; g < m; ++g)
    cell_first_[g + 1] += cell_first_[g], inner_first_[g + 1] += inner_first_[g];
  cell_interfaces_.resize(cell_first_[m]);
  inner_.resize(inner_first_[m]);
  std::vector<std::size_t> next(cell_first_.begin(), cell_first_.end() - 1);
  std::vector<std::size_t> next_inner(inner_first_.begin(), inner_first_.end() - 1);
  for (std::uint32_t k = 0; k < cells_of_.size(); ++k) {
    const auto [a, b] = cells_of_[k];
    if (a == b) {
      inner_[next_inner[a]++] = k;
      continue;
    }
    cell_interfaces_[next[a]++] = {k, b, b};
    cell_interfaces_[next[b]++] = {k, a, b};
  }
}

}  // namespace beadtwin::thermal
