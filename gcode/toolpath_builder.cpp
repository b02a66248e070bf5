#include "gcode/toolpath_builder.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/bead.hpp"
#include "core/units.hpp"

namespace beadtwin::gcode {
namespace {

constexpr double kSameZMm = 1e-4;  // material laid this close in Z lies in one layer

}  // namespace

GcodeToolpathBuilder::GcodeToolpathBuilder(std::string section, double default_layer_height_mm,
                                           std::function<void(const std::string&, const std::string&)> warn)
    : default_layer_height_mm_(default_layer_height_mm), warn_(std::move(warn)) {
  tp_.sections.push_back(std::move(section));
}

void GcodeToolpathBuilder::add(Move m) {
  m.section = 0;
  if (m.kind == MoveKind::kPrint) {
    // Layers come from material laid along a path; material fed with the head standing (a purge or a
    // prime, often in the air before the first layer) belongs to the layer it is fed in, or to the first
    // layer when it comes before any.
    const double z = m.end.z();
    if (layer_ < 0 || std::abs(z - layer_z_) > kSameZMm) start_layer(z);
    m.layer_height_mm = height_mm_ ? *height_mm_ : layer_height_mm_;
    shape_bead(m);
    last_print_ = tp_.moves.size();
  } else if (m.deposits()) {
    m.layer_height_mm = height_mm_ ? *height_mm_ : layer_height_mm_;
  }
  m.layer = layer_;
  tp_.moves.push_back(std::move(m));
  if (rotary_used_) tp_.rotary_deg.push_back(rotary_);
}

Toolpath GcodeToolpathBuilder::finish() {
  // A program that feeds material but never moves while feeding: its one layer is where it fed.
  if (layer_ < 0) {
    for (const Move& m : tp_.moves) {
      if (!m.deposits()) continue;
      start_layer(m.end.z());
      break;
    }
  }
  tp_.index_layers();
  return std::move(tp_);
}

void GcodeToolpathBuilder::start_layer(double z) {
  const double below = layer_ < 0 ? 0.0 : layer_z_;
  double h = height_mm_ ? *height_mm_ : z - below;
  if (!(h > 0.0)) {
    h = layer_height_mm_ > 0.0 ? layer_height_mm_ : default_layer_height_mm_;
    warn_("layer below",
          fmt::format("material laid at Z {:.4g} mm, not above the layer before (Z {:.4g} mm): "
                      "its height is taken as {:.4g} mm",
                      z, below, h));
  }
  ToolpathLayer l;
  l.z_mm = z;
  l.height_mm = h;
  l.section = 0;
  tp_.layers.push_back(l);
  layer_ = static_cast<int>(tp_.layers.size()) - 1;
  layer_z_ = z;
  layer_height_mm_ = h;
  if (layer_ == 0) {  // the first layer takes what was fed before it, at its height
    for (Move& m : tp_.moves)
      if (m.layer < 0 && m.deposits()) {
        m.layer = 0;
        if (!(m.layer_height_mm > 0.0)) m.layer_height_mm = h;
      }
  }
  for (std::size_t k = tp_.moves.size(); k-- > 0;) {
    Move& m = tp_.moves[k];
    if ((last_print_ && k <= *last_print_) || m.kind == MoveKind::kPrint ||
        std::abs(m.end.z() - z) > kSameZMm)
      break;
    m.layer = layer_;
  }
}

void GcodeToolpathBuilder::shape_bead(Move& m) const {
  if (width_mm_) {
    m.bead_width_mm = *width_mm_;
    return;
  }
  const double length = m.length_mm();
  if (!(length > 0.0) || !(m.volume_mm3 > 0.0)) return;
  const double area = m.volume_mm3 / length;
  const double h = m.layer_height_mm;
  if (h > 0.0 && area >= kPi * h * h / 4.0) {
    m.bead_width_mm = bead_width_mm(area, h);
  } else {
    const double d = std::sqrt(4.0 * area / kPi);  // a round bead: too little material to flatten to h
    m.bead_width_mm = m.layer_height_mm = d;
  }
}

}  // namespace beadtwin::gcode
