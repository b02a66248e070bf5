// The G-code reader's toolpath (gcode/block_reader.hpp): moves in program order, gathered into layers,
// with the bead each print move lays.
//
// A layer starts when material is laid at a new Z; its height is that Z less the layer before's, or what a
// HEIGHT annotation said. The moves without material just before the layer's first deposit that end at
// its Z (the travel there, a melt on, an unretract) are moved into it. A print move's width follows from
// its section A = volume / length and its height through core/bead.hpp's stadium, unless a WIDTH
// annotation gives it; below π h²/4 the bead is round.
#pragma once

#include <cstddef>
#include <functional>
#include <new>
#include <optional>
#include <string>

#include "core/memory.hpp"
#include "core/toolpath.hpp"

namespace beadtwin::gcode {

class GcodeToolpathBuilder {
 public:
  // `warn(kind, message)` reports a layer whose height cannot be found; `default_layer_height_mm` (0: none)
  // stands in for it when no layer before has one.
  GcodeToolpathBuilder(std::string section, double default_layer_height_mm,
                       std::function<void(const std::string&, const std::string&)> warn);

  // Annotations: a layer change (forgets the height annotation), a layer height, an extrusion width (mm).
  void layer_marker() { height_mm_.reset(); }
  void set_height(double mm) { height_mm_ = mm; }
  void set_width(double mm) { width_mm_ = mm; }
  // The rotary axes A, B, C (degrees) from now on; from the first call every move keeps them
  // (Toolpath::rotary_deg), the moves before it at zero.
  void set_rotary(const Eigen::Vector3d& abc_deg) {
    if (tp_.rotary_deg.empty()) tp_.rotary_deg.assign(tp_.moves.size(), Eigen::Vector3f::Zero());
    rotary_ = abc_deg.cast<float>();
    rotary_used_ = true;
  }

  // Appends `m`, setting its section and layer, and for a print move or a dwell laying material its layer
  // height and (print moves) width.
  void add(Move m);
  // Room for `moves` moves, so that the move list is not copied as it grows (in huge pages where the system
  // has them: core/memory.hpp). A hint: without room for them, the list grows as it would have.
  void reserve(std::size_t moves) {
    try {
      reserve_huge(tp_.moves, moves);
    } catch (const std::bad_alloc&) {
    }
  }
  std::size_t size() const { return tp_.moves.size(); }
  std::size_t layers() const { return tp_.layers.size(); }
  // The toolpath, layers indexed.
  Toolpath finish();

 private:
  void start_layer(double z);
  void shape_bead(Move& m) const;

  Toolpath tp_;
  double default_layer_height_mm_;
  std::function<void(const std::string&, const std::string&)> warn_;
  std::optional<double> height_mm_;
  std::optional<double> width_mm_;
  int layer_ = -1;
  Eigen::Vector3f rotary_ = Eigen::Vector3f::Zero();
  bool rotary_used_ = false;
  double layer_z_ = 0.0;
  double layer_height_mm_ = 0.0;
  std::optional<std::size_t> last_print_;  // the last move laid along a path
};

}  // namespace beadtwin::gcode
