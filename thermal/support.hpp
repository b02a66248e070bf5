// Whether the material under a new bead carries it (docs/physics.md, too hot): the structural side of the
// fusion window.
//
// Where a bead lands on top of earlier ones, the material under it that is still above the softening
// temperature T_s (the glass transition unless the material says otherwise) is a viscous layer of height H
// resting on the glassy wall below and carrying the new bead's weight, its own, and the compression roller
// (or tamper) while it passes. Such a layer squeezes out sideways: in a wall of width W much wider than H the
// flow is lubrication squeeze flow against the rigid wall below, shear-free at the top, whose strain rate is
// 4 p H² / (η W²) (the planar Stefan problem, Engmann, Servais & Burbidge 2005, J. Non-Newtonian Fluid Mech.
// 132:1-27, with one no-slip boundary); a column much taller than it is wide flows as a free column in
// uniaxial compression, p / (3 η) (Trouton 1906). The two are joined as
//     ε̇ = p / (η (3 + W² / (4 H²))),
// which is each of them in its limit (the join between is an interpolation). η follows the material's
// temperature shift: η(T) = η_ref · t_w(T) / t_w(T_ref) (thermal/fusion.hpp, Reptation), as chain mobility
// sets both viscosity and welding; through the layer it is taken at each height's temperature, the layer's
// compliance the sum of its slices'. The slump the soft layer has made by the time the bead lands is
//     δ = (ρ g (H + h) t_soft + p_roller t_roller max(1, H / h)) ∫₀^H dz / η(T(z)) / (3 + W² / (4 H²)),
// h the new bead's layer height, t_soft the time since the deepest soft material landed (as long as the soft
// layer has been carrying weight), t_roller the roller's contact length over the speed, once for every layer
// laid on the soft material. The bead is too hot when δ exceeds the material's allowed slump, a fraction of
// h.
//
// Limits: the rubbery (elastic) strain of the soft layer under the roller recovers and is not counted; the
// nozzle's own push and drag on a desktop printer's tiny features are not modelled; the temperatures are
// those at landing, held through t_soft (the layer was hotter before: the slump is underestimated there, and
// the weight grew over t_soft: overestimated there).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "core/material.hpp"
#include "core/toolpath.hpp"
#include "thermal/fusion.hpp"

namespace beadtwin::thermal {

struct ThermalMesh;

// What the support criterion needs of each cell, from the mesh and its toolpath (support_cells).
struct SupportCell {
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  // The cell this one rests on: of its older contacts within 60° of horizontal, the largest; kNone on the
  // table or where nothing lies under it.
  std::uint32_t below = kNone;
  // The top cell of its bead's column through the layer height (thermal.cells_through): itself where the
  // bead is one cell through.
  std::uint32_t bead_top = 0;
  double birth_s = 0.0;  // when it landed
  float centre_z_mm = 0.0f;
  float top_z_mm = 0.0f;         // the top of its material (its centre and half its height)
  float wall_width_mm = 0.0f;    // the part's material across the bead, through its centre, mm
  float layer_height_mm = 0.0f;  // of the move that laid it
  float speed_mm_s = 0.0f;       // of that move
};

// Measures every cell of `mesh` (built from `toolpath`): what lies under it, its heights, the wall's width
// across its bead in the cell grid (material voxels in a straight line through its centre, across the bead
// in plan, gaps of up to two voxels bridged) and its move's layer height and speed. Without a toolpath
// (null: a mesh built by hand) the layer height is the cell's own height and the speed unknown (0: no
// roller time); without a cell grid the wall's width is the cell's own, √(volume / height).
std::vector<SupportCell> support_cells(const ThermalMesh& mesh, const Toolpath* toolpath);

// The roller or tamper on the new bead; zero pressure: none.
struct SupportLoad {
  double roller_pressure_Pa = 0.0;  // mean pressure under it
  double roller_contact_mm = 0.0;   // its contact length along the bead
};

// What support_of found for one landing.
struct SupportResult {
  double soft_height_mm = 0.0;  // H: the material under the bead above the softening temperature
  double wall_width_mm = 0.0;   // W
  double slump_mm = 0.0;        // δ
  double allowed_mm = 0.0;      // the material's allowed slump × the bead's layer height
  // The substrate temperature at which δ would equal the allowed slump, the whole column under the bead
  // warmer or cooler by as much, °C: the temperature to wait for (the layer-time window's hot edge);
  // +infinity where no column up to the deposition temperature would slump that far.
  double limit_c = 0.0;
  bool too_hot() const { return slump_mm > allowed_mm; }
};

// Judges landings on top of older cells for one material and load.
class Support {
 public:
  // Throws InputError where the material's viscosity or allowed slump is not positive.
  Support(const Material& material, const SupportLoad& load);

  // The landing of `younger` on `older` (indices into `cells`), with every cell's temperature, °C, given by
  // `temp_c(cell)`. The soft material has carried weight for at least `min_load_s` (the solver's birth
  // interval: cells born together landed within it). The hot edge is stated as a value of `reference_c`
  // (the substrate temperature as the caller measures it; NaN: the older cell's own) shifted as the column.
  SupportResult judge(std::span<const SupportCell> cells, std::uint32_t older, std::uint32_t younger,
                      double min_load_s, const std::function<double(std::uint32_t)>& temp_c,
                      double reference_c = std::numeric_limits<double>::quiet_NaN()) const;

  // The same for a column given directly: points from the top of the material under the bead down to a
  // rigid bottom (the table, or far enough down to be below the softening temperature), their heights `z_mm`
  // (falling) and temperatures `temp_c` (linear between the points), the wall's width, and the new bead's
  // layer height and speed. For the 1-D wall model and the tests. `reference_c` as for judge (NaN: the
  // top point's temperature).
  SupportResult judge_column(std::span<const double> z_mm, std::span<const double> temp_c,
                             double wall_width_mm, double layer_height_mm, double speed_mm_s,
                             double layer_time_s,
                             double reference_c = std::numeric_limits<double>::quiet_NaN()) const;

  // 1 / η at `temp_c`, 1/(Pa·s); 0 at or below the softening temperature.
  double fluidity(double temp_c) const;
  // ∫ 1/η dT from `low_c` up to `high_c` (low_c ≤ high_c), K/(Pa·s); only the part above the softening
  // temperature counts.
  double fluidity_integral(double low_c, double high_c) const;
  double softening_c() const { return softening_c_; }

 private:
  struct Slump {
    double soft_height_mm = 0.0, slump_mm = 0.0;
  };
  // The soft height and the slump of the column with every temperature raised by `offset_k`.
  Slump slump(std::span<const double> z_mm, std::span<const double> temp_c, double offset_k,
              double wall_width_mm, double layer_height_mm, double speed_mm_s, double soft_for_s) const;

  // The fluidity integral from the softening temperature up to `temp_c`, from the table (exact for a
  // fluidity exponential between its points) within it, by Simpson's rule above it.
  double cumulative(double temp_c) const;
  // The table's k-th temperature, °C.
  double node_c(std::size_t k) const;
  // 1 / η at `temp_c` without the softening cut-off (0 where the reptation law gives no finite time).
  double raw_fluidity(double temp_c) const;

  Reptation reptation_;
  double deposition_c_;
  double softening_c_;
  double viscosity_ref_Pa_s_;
  double weight_Pa_per_mm_;  // ρ g, Pa per mm of height
  double allowed_;           // allowed slump, a fraction of the layer height
  SupportLoad load_;
  // The fluidity and its integral from the softening temperature at node_c(k).
  std::vector<double> table_fluidity_, table_cumulative_;
};

}  // namespace beadtwin::thermal
