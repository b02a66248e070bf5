#include "scenarios/pictures.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include <fmt/format.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/parallel_for.h>

#include "render/colormap.hpp"
#include "render/image.hpp"
#include "render/render.hpp"
#include "render/sheet.hpp"
#include "scenarios/colours.hpp"
#include "sim/cad_compare.hpp"
#include "sim/porosity.hpp"
#include "thermal/summary.hpp"

namespace beadtwin::scenarios {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// What a picture colours the part by: a value per material voxel (or per surface point), the colours of those
// values, and the legend that explains them.
struct Field {
  std::string heading;  // the picture's title
  std::string title;    // what the value is, with its unit: the legend's title
  // The value of every material voxel, in display units; NaN (or no voxel) where there is none.
  openvdb::FloatGrid::Ptr voxels;
  // Or a function of the surface point (in display units), for quantities that live on a surface of their
  // own (the CAD's distance).
  std::function<double(const Eigen::Vector3d&)> at_point;
  // Categories (the value is the index) or a scale.
  std::vector<render::LegendEntry> categories;
  render::ScalarScale scale;
  std::string note;

  render::Rgb colour(double value) const {
    if (!categories.empty()) {
      if (!std::isfinite(value)) return render::kNoValueGrey;
      const long i = std::lround(value);
      return i >= 0 && i < static_cast<long>(categories.size())
                 ? categories[static_cast<std::size_t>(i)].colour
                 : render::kNoValueGrey;
    }
    return scale.colour(value);
  }
  render::Legend legend() const {
    render::Legend l;
    l.title = title;
    if (categories.empty())
      l.scale = scale;
    else
      l.entries = categories;
    l.note = note;
    return l;
  }
};

// A value on every material voxel of `fill` (active on exactly its voxels, NaN elsewhere), leaf by leaf on
// TBB's threads: read(voxel) of a reader each task makes with make_reader() (its accessors of the grids it
// reads, unregistered with their trees, as the renderer's: render/surface.hpp). Leaf by leaf, because voxel
// by voxel through one accessor the fields of the pictures drawn after the thermal stage were a large share
// of a run's time (docs/PERFORMANCE.md).
template <class MakeReader>
openvdb::FloatGrid::Ptr values_on(const openvdb::FloatGrid& fill, const MakeReader& make_reader) {
  constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
  const auto tree = std::make_shared<openvdb::FloatTree>(fill.tree(), kNaNf, kNaNf, openvdb::TopologyCopy());
  const openvdb::tree::LeafManager<openvdb::FloatTree> leaves(*tree);
  tbb::parallel_for(leaves.leafRange(),
                    [&](const openvdb::tree::LeafManager<openvdb::FloatTree>::LeafRange& r) {
                      auto read = make_reader();
                      for (auto leaf = r.begin(); leaf; ++leaf)
                        for (auto it = leaf->beginValueOn(); it; ++it)
                          it.setValue(static_cast<float>(read(it.getCoord())));
                    });
  openvdb::FloatGrid::Ptr out = openvdb::FloatGrid::create(tree);
  out->setTransform(fill.transform().copy());
  return out;
}

// The value per label of `labels` (cells, layers) on the material voxels (NaN: label outside the table).
openvdb::FloatGrid::Ptr values_by_label(const openvdb::FloatGrid& fill, const openvdb::Int32Grid& labels,
                                        const std::vector<double>& by_label) {
  return values_on(fill, [&] {
    return [label_at = labels.getConstUnsafeAccessor(), &by_label](const openvdb::Coord& ijk) {
      const int label = label_at.getValue(ijk);
      return label >= 0 && static_cast<std::size_t>(label) < by_label.size()
                 ? by_label[static_cast<std::size_t>(label)]
                 : kNaN;
    };
  });
}

// `grid`'s values on the material voxels, divided by `unit`.
openvdb::FloatGrid::Ptr values_of(const openvdb::FloatGrid& fill, const openvdb::FloatGrid& grid,
                                  double unit) {
  return values_on(fill, [&] {
    return [grid_at = grid.getConstUnsafeAccessor(), unit](const openvdb::Coord& ijk) {
      return grid_at.getValue(ijk) / unit;
    };
  });
}

// A duration in the unit that reads best for `longest_s`.
struct TimeUnit {
  double seconds;
  const char* name;
};
TimeUnit time_unit(double longest_s) {
  if (longest_s > 3 * 3600.0) return {3600.0, "h"};
  if (longest_s > 3 * 60.0) return {60.0, "min"};
  return {1.0, "s"};
}

std::string when(double t_s) {
  const auto total = static_cast<long>(std::lround(t_s));
  if (total < 60) return fmt::format("{} s", total);
  if (total < 3600) return fmt::format("{} min {:02} s", total / 60, total % 60);
  return fmt::format("{} h {:02} min", total / 3600, (total % 3600) / 60);
}

// The snapshot of the thermal run nearest `t_s` (the pictures asked for it, so it is there).
const thermal::TemperatureSnapshot* snapshot_at(const thermal::HeatResult& heat, double t_s) {
  const thermal::TemperatureSnapshot* best = nullptr;
  for (const thermal::TemperatureSnapshot& s : heat.snapshots)
    if (!best || std::abs(s.time_s - t_s) < std::abs(best->time_s - t_s)) best = &s;
  return best;
}

// The end of toolpath layer `layer` (or of the print for -1), s.
double layer_end_s(const Toolpath& tp, int layer) {
  if (layer < 0 || static_cast<std::size_t>(layer) >= tp.layers.size()) return tp.total_time_s();
  const ToolpathLayer& l = tp.layers[static_cast<std::size_t>(layer)];
  return l.start_s + l.duration_s();
}

// The moment a temperature picture shows: its own time, or the end of its layer, or of the print.
double picture_time_s(const Toolpath& tp, double time_s, int up_to_layer) {
  return std::isfinite(time_s) ? time_s : layer_end_s(tp, up_to_layer);
}

// Sets `f`'s scale from lo to hi (display units), or to the picture's own `range` (given in the colouring's
// internal unit, `unit` of them to a display unit).
void set_scale(Field& f, const std::optional<std::pair<double, double>>& range, double lo, double hi,
               render::ColourMap map, double unit = 1.0) {
  f.scale.lo = range ? range->first / unit : lo;
  f.scale.hi = range ? range->second / unit : hi;
  f.scale.map = std::move(map);
}

// Each piece of bead by its worst interface's fusion verdict: a category per verdict, in kVerdicts' order.
Field fusion_field(const thermal::ThermalResult& th, const openvdb::FloatGrid& fill) {
  using thermal::Verdict;
  Field f;
  f.heading = "Fusion";
  f.title = "each piece of bead by its worst interface";
  static constexpr std::pair<Verdict, const char*> kVerdicts[] = {
      {Verdict::kOk, "fuses"},
      {Verdict::kTooHot, "too hot: landed on soft material"},
      {Verdict::kTooCold, "too cold: does not heal"},
      {Verdict::kMarginal, "marginal: changes within the P10-P90 band"},
      {Verdict::kNoInterface, "no interface (on the table)"}};
  // Marginal only where the bands were estimated (thermal.uncertainty): without them no verdict can be. A
  // cell's value is its verdict's place among the categories listed.
  const bool bands = !th.uncertain_inputs.empty();
  std::vector<Verdict> listed;
  for (const auto& [v, label] : kVerdicts)
    if (bands || v != Verdict::kMarginal)
      listed.push_back(v), f.categories.push_back({verdict_colour(v), label});
  std::vector<double> by_cell;
  by_cell.reserve(th.cells.size());
  for (const Verdict v : th.cells)
    by_cell.push_back(static_cast<double>(std::find(listed.begin(), listed.end(), v) - listed.begin()));
  f.voxels = values_by_label(fill, *th.mesh.cell_grid, by_cell);
  return f;
}

// The local porosity (void fraction) within about half the first section's bead width of each voxel.
Field porosity_field(const PictureInputs& in, const openvdb::FloatGrid& fill,
                     const std::optional<std::pair<double, double>>& range) {
  Field f;
  f.heading = "Porosity";
  f.title = "local porosity (void fraction)";
  const openvdb::MaskGrid::Ptr none = openvdb::MaskGrid::create();
  const double bead = in.variant->sections.empty() ? 4.0 * in.deposit->voxel_size_mm
                                                   : in.variant->sections.front().bead_width_mm;
  const int radius = std::max(1, static_cast<int>(std::lround(0.5 * bead / in.deposit->voxel_size_mm)));
  const openvdb::FloatGrid::Ptr porosity =
      sim::local_porosity(*in.deposit->fill, in.deposit->gaps ? *in.deposit->gaps : *none, radius);
  f.voxels = values_of(fill, *porosity, 1.0);
  set_scale(f, range, 0.0, 0.3, render::ColourMap::viridis());
  f.note = fmt::format("void over envelope within {:.0f} mm", (2 * radius + 1) * in.deposit->voxel_size_mm);
  return f;
}

// The field of `colouring` for the variant of `in`, over the material voxels of `fill` (the part as the
// picture shows it). `time_s`: the moment of a temperature picture. `thermal`: the variant's thermal run,
// null while it runs (then only colourings that do not need it).
Field make_field(Colouring colouring, const PictureInputs& in, const thermal::ThermalResult* thermal,
                 const openvdb::FloatGrid& fill, double time_s,
                 const std::optional<std::pair<double, double>>& range) {
  const PictureFrame& frame = *in.frame;
  BT_CHECK(thermal != nullptr || !needs_thermal(colouring));
  const Material& material = in.variant->material;
  Field f;
  switch (colouring) {
    case Colouring::kFusion:
      f = fusion_field(*thermal, fill);
      break;
    case Colouring::kSection: {
      f.heading = "Sections";
      f.title = "section";
      const Toolpath& tp = *in.toolpath;
      for (std::size_t s = 0; s < tp.sections.size(); ++s)
        f.categories.push_back({section_colour(static_cast<int>(s)), tp.sections[s]});
      std::vector<double> by_layer;
      for (const ToolpathLayer& l : tp.layers) by_layer.push_back(l.section >= 0 ? l.section : kNaN);
      f.voxels = values_by_label(fill, *in.deposit->layer, by_layer);
      break;
    }
    case Colouring::kLayer: {
      f.heading = "Layers";
      f.title = "toolpath layer (from 0 at the table)";
      std::vector<double> by_layer(in.toolpath->layers.size());
      for (std::size_t i = 0; i < by_layer.size(); ++i) by_layer[i] = static_cast<double>(i);
      f.voxels = values_by_label(fill, *in.deposit->layer, by_layer);
      set_scale(f, range, 0.0, std::max(1, frame.layers - 1), render::ColourMap::viridis());
      break;
    }
    case Colouring::kTime: {
      const TimeUnit unit = time_unit(frame.print_time_s);
      f.heading = "Deposition time";
      f.title = fmt::format("deposition time ({})", unit.name);
      f.voxels = values_of(fill, *in.deposit->time, unit.seconds);
      set_scale(f, range, 0.0, frame.print_time_s / unit.seconds, render::ColourMap::viridis(), unit.seconds);
      break;
    }
    case Colouring::kSubstrate: {
      const thermal::ThermalResult& th = *thermal;
      f.heading = "Substrate temperature at deposition";
      f.title = "temperature of what the bead landed on (°C)";
      f.voxels = values_by_label(fill, *th.mesh.cell_grid, thermal::cell_substrate_c(th.mesh, th.heat));
      set_scale(f, range, frame.cold_c, frame.hot_c, render::ColourMap::inferno());
      f.note = fmt::format("soft above {:.0f} °C; grey: on the table", material.softening_temp_c);
      break;
    }
    case Colouring::kSurface: {
      const thermal::ThermalResult& th = *thermal;
      f.heading = "Surface temperature before each bead landed";
      f.title = "surface of what the bead landed on, as a thermal camera reads it (°C)";
      f.voxels = values_by_label(
          fill, *th.mesh.cell_grid,
          thermal::cell_substrate_c(th.mesh, th.heat, &thermal::InterfaceResult::substrate_surface_c));
      set_scale(f, range, frame.cold_c, frame.hot_c, render::ColourMap::inferno());
      f.note = fmt::format("glass transition {:.0f} °C; grey: on the table", material.glass_transition_c);
      break;
    }
    case Colouring::kHealing: {
      const thermal::ThermalResult& th = *thermal;
      f.heading = "Degree of healing";
      f.title = "least degree of healing of each piece of bead";
      f.voxels = values_by_label(fill, *th.mesh.cell_grid, thermal::cell_healing(th.mesh, th.heat));
      set_scale(f, range, 0.0, 1.0, render::ColourMap::viridis());
      f.note = fmt::format("needs {:.2f}; grey: no interface", material.required_healing);
      break;
    }
    case Colouring::kDeviation: {
      BT_CHECK(in.cad != nullptr);
      f.heading = "Stock over the CAD";
      f.title = "stock over the CAD (mm)";
      const std::shared_ptr<const sim::CadField> distance = in.cad->comparison.cad_distance;
      f.at_point = [distance](const Eigen::Vector3d& p) { return distance->at(p); };
      set_scale(f, range, frame.stock_centre_mm - frame.stock_half_range_mm,
                frame.stock_centre_mm + frame.stock_half_range_mm, render::ColourMap::diverging());
      f.note =
          fmt::format("white: the requested {:.1f} mm; blue: less (undercut below 0)", frame.stock_centre_mm);
      break;
    }
    case Colouring::kPorosity:
      f = porosity_field(in, fill, range);
      break;
    case Colouring::kTemperature: {
      const thermal::ThermalResult& th = *thermal;
      f.heading = fmt::format("Temperature at {}", when(time_s));
      f.title = "temperature (°C)";
      const thermal::TemperatureSnapshot* s = snapshot_at(th.heat, time_s);
      BT_CHECK(s != nullptr);
      const std::vector<double> by_cell(s->temp_c.begin(), s->temp_c.end());
      f.voxels = values_by_label(fill, *th.mesh.cell_grid, by_cell);
      set_scale(f, range, frame.cold_c, frame.hot_c, render::ColourMap::inferno());
      break;
    }
  }
  return f;
}

render::RenderOptions render_options(const RenderSpec& r) {
  render::RenderOptions o;
  o.width = r.width;
  o.height = r.height;
  o.samples_per_pixel = r.samples;
  o.ambient_occlusion = r.ambient_occlusion;
  return o;
}

std::string view_title(const render::CameraSpec& c) {
  return c.view == render::View::kUser ? "user camera" : std::string(render::to_string(c.view)) + " view";
}

// How a picture of the variant is rendered from `camera`: the same for every picture from that camera
// whatever it shows, as the room kept for the annotation does not depend on it (every picture has a title
// and subtitle, a legend and a scale bar).
render::RenderOptions picture_options(const PictureInputs& in, const render::CameraSpec& camera,
                                      const std::optional<CutSpec>& cut) {
  const RenderSpec& spec = in.variant->render;
  render::Annotation any;
  any.title = any.subtitle = "-";
  any.legend.emplace();
  any.mm_per_pixel = 1.0;  // a placeholder for the layout: the real scale is known once framed
  const render::AnnotationLayout layout =
      spec.legend ? render::layout_for(spec.width, spec.height, any) : render::AnnotationLayout{};
  render::RenderOptions o = render_options(spec);
  o.camera = camera;
  o.frame = in.frame->bounds;
  o.margins = {0.03 + static_cast<double>(layout.margin_px) / spec.width,
               0.03 + static_cast<double>(layout.legend_panel_px) / spec.width,
               0.03 + static_cast<double>(layout.title_band_px) / spec.height,
               0.03 + static_cast<double>(layout.scale_band_px) / spec.height};
  if (cut) o.cut = render::Cutaway{cut->point.cast<float>(), cut->normal.cast<float>()};
  return o;
}

render::SurfaceField surface_field(const Field& field) {
  render::SurfaceField sf;
  sf.voxels = field.voxels.get();
  sf.at_point = field.at_point;
  sf.colour = [&field](double v) { return field.colour(v); };
  return sf;
}

// One picture: the field drawn on the part from the camera (or coloured on the rays traced from it before),
// annotated, with its raw values.
render::FieldPicture draw(const render::PreparedDeposit& prepared, const render::TracedPicture* traced,
                          const Field& field, const render::CameraSpec& camera,
                          const std::optional<CutSpec>& cut, const PictureInputs& in,
                          const std::string& title, const std::string& subtitle) {
  const render::SurfaceField sf = surface_field(field);
  render::FieldPicture picture = traced != nullptr && traced->colours(sf)
                                     ? traced->colour(sf)
                                     : render::render_field(prepared, sf, picture_options(in, camera, cut));
  if (in.variant->render.legend) {
    render::Annotation note;
    note.title = title;
    note.subtitle = subtitle;
    note.legend = field.legend();
    note.length_unit = in.frame->length_unit;
    note.mm_per_pixel = picture.mm_per_pixel;
    render::annotate(picture.image, note);
  }
  return picture;
}

void write_picture(const render::FieldPicture& picture, const std::filesystem::path& dir,
                   const std::string& stem, bool exr, const std::string& rel_dir, PictureFiles& files) {
  render::write_png(picture.image, dir / (stem + ".png"));
  files.images.push_back(rel_dir + "/" + stem + ".png");
  if (!exr) return;
  render::write_exr(picture.image, dir / (stem + ".exr"), {{"value", picture.values}, {"Z", picture.depth}});
  files.exr.push_back(rel_dir + "/" + stem + ".exr");
}

}  // namespace

PictureFrame picture_frame(const std::vector<const Variant*>& variants,
                           const std::vector<const Toolpath*>& toolpaths, bool inches) {
  BT_CHECK(variants.size() == toolpaths.size());
  PictureFrame f;
  f.length_unit = inches ? render::LengthUnit::kInch : render::LengthUnit::kMetric;
  // The extremes over the variants, then the defaults where no variant had one.
  f.cold_c = f.stock_centre_mm = std::numeric_limits<double>::infinity();
  f.hot_c = -std::numeric_limits<double>::infinity();
  f.stock_half_range_mm = 0.0;
  for (std::size_t k = 0; k < variants.size(); ++k) {
    const Variant& v = *variants[k];
    const Toolpath& tp = *toolpaths[k];
    f.print_time_s = std::max(f.print_time_s, tp.total_time_s());
    f.layers = std::max(f.layers, static_cast<int>(tp.layers.size()));
    f.cold_c = std::min(f.cold_c, v.machine.environment.ambient_c);
    f.hot_c = std::max(f.hot_c, v.material.deposition_temp_c);
    const StockScale stock = stock_scale(v);
    f.stock_centre_mm = std::min(f.stock_centre_mm, stock.requested_mm);
    f.stock_half_range_mm = std::max(f.stock_half_range_mm, stock.half_range_mm);
    // The beads: every depositing move's ends, grown by half its bead across and by its height below; the
    // hottest the program sets the nozzle to.
    for (const Move& m : tp.moves) {
      if (!m.deposits()) continue;
      if (std::isfinite(m.nozzle_c)) f.hot_c = std::max(f.hot_c, static_cast<double>(m.nozzle_c));
      const float half = static_cast<float>(0.5 * std::max(m.bead_width_mm, m.layer_height_mm));
      for (const Eigen::Vector3d& p : {m.start, m.end}) {
        const Eigen::Vector3f q = p.cast<float>();
        f.bounds.extend(
            Eigen::Vector3f(q.x() - half, q.y() - half, q.z() - static_cast<float>(m.layer_height_mm)));
        f.bounds.extend(Eigen::Vector3f(q.x() + half, q.y() + half, q.z()));
      }
    }
  }
  const PictureFrame defaults;
  if (!std::isfinite(f.cold_c)) f.cold_c = defaults.cold_c;
  if (!std::isfinite(f.hot_c)) f.hot_c = defaults.hot_c;
  if (!(f.hot_c > f.cold_c)) f.hot_c = f.cold_c + 1.0;
  if (!std::isfinite(f.stock_centre_mm)) f.stock_centre_mm = defaults.stock_centre_mm;
  if (!(f.stock_half_range_mm > 0.0)) f.stock_half_range_mm = defaults.stock_half_range_mm;
  return f;
}

std::vector<double> picture_snapshot_times(const RenderSpec& spec, const Toolpath& tp) {
  std::vector<double> out;
  for (const ImageSpec& im : spec.images)
    if (im.colour == Colouring::kTemperature) out.push_back(picture_time_s(tp, im.time_s, im.up_to_layer));
  if (spec.progress && spec.progress->colour == Colouring::kTemperature)
    for (std::size_t i = 0; i < tp.layers.size(); ++i)
      if ((i + 1) % static_cast<std::size_t>(spec.progress->every) == 0 || i + 1 == tp.layers.size())
        out.push_back(layer_end_s(tp, static_cast<int>(i)));
  return out;
}

bool needs_thermal(Colouring colouring) {
  switch (colouring) {
    case Colouring::kFusion:
    case Colouring::kSubstrate:
    case Colouring::kSurface:
    case Colouring::kHealing:
    case Colouring::kTemperature:
      return true;
    case Colouring::kSection:
    case Colouring::kLayer:
    case Colouring::kTime:
    case Colouring::kDeviation:
    case Colouring::kPorosity:
      return false;
  }
  return true;
}

namespace {

bool same_camera(const render::CameraSpec& a, const render::CameraSpec& b) {
  const auto same_point = [](const std::optional<Eigen::Vector3f>& p,
                             const std::optional<Eigen::Vector3f>& q) {
    return p.has_value() == q.has_value() && (!p || *p == *q);
  };
  return a.view == b.view && same_point(a.position, b.position) && same_point(a.target, b.target) &&
         a.direction == b.direction && a.field_of_view_deg == b.field_of_view_deg;
}

bool same_cut(const std::optional<CutSpec>& a, const std::optional<CutSpec>& b) {
  return a.has_value() == b.has_value() && (!a || (a->point == b->point && a->normal == b->normal));
}

}  // namespace

// The part as a picture shows it, prepared once per shape: whole, as it stood when a layer was done, or as
// it stood at a moment (the material landed by then); by (last layer or -1, moment or infinity).
struct PictureWriter::State {
  PictureInputs in;
  std::filesystem::path dir;
  struct Shown {
    openvdb::FloatGrid::Ptr fill;
    render::PreparedDeposit prepared;
  };
  std::map<std::pair<int, double>, Shown> shapes;
  // The views traced once for several pictures (of one shape, from one camera, cut alike), and for the
  // pictures drawn after the thermal run, traced beside it: each picture then only colours the rays (which
  // is most of what is left for the pictures once the thermal stage is done). Dropped once their last picture
  // is drawn.
  struct View {
    std::size_t first;           // the first picture of the render block from it
    int pictures = 0;            // its pictures not yet drawn
    bool after_thermal = false;  // one of them is drawn after the thermal run
    std::optional<render::TracedPicture> traced;
  };
  std::vector<View> views;
  std::vector<int> view_of;  // per picture of the render block: its view, or -1 when drawn on its own
  // Per picture of the render block: its files once drawn (none for one left out).
  std::vector<PictureFiles> drawn;
  PictureFiles progress;  // the progress frames, once drawn
  std::vector<std::string> notes;
  bool early_done = false;

  const Variant& variant() const { return *in.variant; }
  const Toolpath& toolpath() const { return *in.toolpath; }

  const Shown& shape(int last_layer, double until_s) {
    const std::pair key{last_layer, until_s};
    if (auto it = shapes.find(key); it != shapes.end()) return it->second;
    const sim::Deposit& d = *in.deposit;
    sim::Deposit shown = d;
    if (last_layer >= 0)
      shown.fill = sim::fill_up_to_layer(d, last_layer);
    else if (std::isfinite(until_s))
      shown.fill = sim::fill_up_to_time(d, until_s);
    openvdb::FloatGrid::Ptr fill = shown.fill;
    if (last_layer < 0 && !std::isfinite(until_s) && in.whole_surface)
      if (std::optional<render::SurfaceMesh> surface = in.whole_surface())
        return shapes.emplace(key, Shown{fill, render::PreparedDeposit(shown, std::move(*surface))})
            .first->second;
    return shapes.emplace(key, Shown{fill, render::PreparedDeposit(shown)}).first->second;
  }

  // A picture of the render block: whether it is drawn at all, its moment, and the shape it shows.
  bool left_out(const ImageSpec& im) const { return im.colour == Colouring::kDeviation && !in.cad; }
  double moment_s(const ImageSpec& im) const { return picture_time_s(toolpath(), im.time_s, im.up_to_layer); }
  // A temperature picture at a moment inside the print shows the part as it stood then.
  bool at_moment(const ImageSpec& im) const {
    return im.up_to_layer < 0 && im.colour == Colouring::kTemperature &&
           moment_s(im) < toolpath().total_time_s();
  }
  std::pair<int, double> shape_key(const ImageSpec& im) const {
    return {im.up_to_layer, at_moment(im) ? moment_s(im) : std::numeric_limits<double>::infinity()};
  }
  const Shown& shape_of(const ImageSpec& im) {
    const auto [last_layer, until_s] = shape_key(im);
    return shape(last_layer, until_s);
  }

  // Which pictures share a view and are coloured on its traced rays: all that share it with another, and
  // those drawn after the thermal run. Not for pictures larger than 4K UHD: a traced view holds some 40
  // bytes a pixel (render::TracedPicture), and those of the thermal pictures are held through the thermal
  // stage; such pictures are each traced when drawn, as before.
  void plan_views() {
    constexpr long kMostTracedPixels = 3840L * 2160L;
    const std::vector<ImageSpec>& images = variant().render.images;
    view_of.assign(images.size(), -1);
    if (static_cast<long>(variant().render.width) * variant().render.height > kMostTracedPixels) return;
    for (std::size_t k = 0; k < images.size(); ++k) {
      const ImageSpec& im = images[k];
      if (left_out(im)) continue;
      const auto same = std::find_if(views.begin(), views.end(), [&](const View& v) {
        const ImageSpec& other = images[v.first];
        return shape_key(other) == shape_key(im) && same_camera(other.camera, im.camera) &&
               same_cut(other.cut, im.cut);
      });
      const auto v = static_cast<std::size_t>(same - views.begin());
      if (v == views.size()) views.push_back({k, 0, false, std::nullopt});
      ++views[v].pictures;
      views[v].after_thermal |= needs_thermal(im.colour);
      view_of[k] = static_cast<int>(v);
    }
    for (int& v : view_of)
      if (v >= 0 && views[v].pictures < 2 && !views[v].after_thermal) v = -1;
  }

  // The traced rays of picture k's view, traced now if they are not yet; null when it is drawn on its own.
  const render::TracedPicture* traced_for(std::size_t k) {
    if (view_of[k] < 0) return nullptr;
    View& v = views[static_cast<std::size_t>(view_of[k])];
    const ImageSpec& im = variant().render.images[k];
    if (!v.traced) v.traced.emplace(shape_of(im).prepared, picture_options(in, im.camera, im.cut));
    return &*v.traced;
  }
  // Picture k is drawn: its view's rays go with its last picture.
  void drawn_from_view(std::size_t k) {
    if (view_of[k] < 0) return;
    View& v = views[static_cast<std::size_t>(view_of[k])];
    if (--v.pictures == 0) v.traced.reset();
  }

  std::string scenario_line() const {
    return fmt::format("{} — variant {}", in.scenario->name, variant().name);
  }

  void draw_image(std::size_t k, const thermal::ThermalResult* thermal) {
    const Variant& v = variant();
    const ImageSpec& im = v.render.images[k];
    const Shown& shown = shape_of(im);
    const Field field = make_field(im.colour, in, thermal, *shown.fill, moment_s(im), im.range);
    std::string subtitle = scenario_line() + ", " + view_title(im.camera);
    if (im.up_to_layer >= 0) subtitle += fmt::format(", after layer {}", im.up_to_layer);
    if (at_moment(im)) subtitle += ", as it stood then";
    if (im.cut) subtitle += ", cut away";
    const render::FieldPicture picture =
        draw(shown.prepared, traced_for(k), field, im.camera, im.cut, in, field.heading, subtitle);
    drawn_from_view(k);
    write_picture(picture, dir, im.name, v.render.exr, v.name, drawn[k]);
  }

  void draw_progress(const thermal::ThermalResult* thermal) {
    const Variant& v = variant();
    const Toolpath& tp = toolpath();
    const ProgressSpec& p = *v.render.progress;
    const std::filesystem::path frames = dir / "progress";
    std::filesystem::create_directories(frames);
    int frame_index = 0;
    for (std::size_t i = 0; i < tp.layers.size(); ++i) {
      if ((i + 1) % static_cast<std::size_t>(p.every) != 0 && i + 1 != tp.layers.size()) continue;
      const int layer = static_cast<int>(i);
      const Shown& shown = shape(layer, std::numeric_limits<double>::infinity());
      const Field field =
          make_field(p.colour, in, thermal, *shown.fill, layer_end_s(tp, layer), std::nullopt);
      const render::FieldPicture picture =
          draw(shown.prepared, nullptr, field, p.camera, std::nullopt, in, field.heading,
               fmt::format("{}, layer {} of {}, {}", scenario_line(), layer, tp.layers.size(),
                           when(layer_end_s(tp, layer))));
      const std::string stem = fmt::format("frame-{:04}", frame_index++);
      render::write_png(picture.image, frames / (stem + ".png"));
      progress.progress.push_back(v.name + "/progress/" + stem + ".png");
      shapes.erase({layer, std::numeric_limits<double>::infinity()});  // each frame's shape is used once
    }
  }
};

PictureWriter::PictureWriter(const PictureInputs& in, std::filesystem::path dir)
    : state_(std::make_unique<State>()) {
  state_->in = in;
  state_->dir = std::move(dir);
  state_->drawn.resize(in.variant->render.images.size());
  state_->plan_views();
}

PictureWriter::~PictureWriter() = default;

void PictureWriter::without_thermal() {
  State& s = *state_;
  BT_CHECK(!s.early_done);
  s.early_done = true;
  const Variant& v = s.variant();
  for (std::size_t k = 0; k < v.render.images.size(); ++k) {
    const ImageSpec& im = v.render.images[k];
    if (s.left_out(im)) {
      if (v.render.images_given)
        s.notes.push_back(fmt::format("picture '{}' left out: there is no CAD to compare with ({})", im.name,
                                      v.program ? "a program is simulated" : "the sections print outlines"));
      continue;
    }
    if (needs_thermal(im.colour)) {  // drawn once the thermal run is done: its shape and rays made now
      (void)s.shape_of(im);
      (void)s.traced_for(k);
    } else {
      s.draw_image(k, nullptr);
    }
  }
  // The progress frames are drawn in one go (each shape dropped once drawn: none prepared ahead).
  if (v.render.progress && !needs_thermal(v.render.progress->colour)) s.draw_progress(nullptr);
}

PictureFiles PictureWriter::finish(const thermal::ThermalResult& thermal) {
  State& s = *state_;
  if (!s.early_done) without_thermal();
  const Variant& v = s.variant();
  for (std::size_t k = 0; k < v.render.images.size(); ++k) {
    const ImageSpec& im = v.render.images[k];
    if (!s.left_out(im) && needs_thermal(im.colour)) s.draw_image(k, &thermal);
  }
  if (v.render.progress && needs_thermal(v.render.progress->colour)) s.draw_progress(&thermal);
  s.shapes.clear();
  PictureFiles out;
  for (PictureFiles& d : s.drawn) {
    out.images.insert(out.images.end(), d.images.begin(), d.images.end());
    out.exr.insert(out.exr.end(), d.exr.begin(), d.exr.end());
  }
  out.progress = std::move(s.progress.progress);
  return out;
}

const std::vector<std::string>& PictureWriter::notes() const {
  return state_->notes;
}

std::vector<std::string> write_sheets(const RunResult& result, const std::filesystem::path& out_dir) {
  std::vector<std::string> out;
  if (result.variants.size() < 2 || !result.scenario) return out;
  const Variant& first = *result.variants.front().variant;
  if (!first.render.sheet) return out;
  // The pictures every variant has, by file name, in the first variant's order.
  for (const std::string& image : result.variants.front().images) {
    const std::string file = std::filesystem::path(image).filename().string();
    std::vector<render::Image> tiles;
    std::vector<std::string> captions;
    for (const VariantResult& v : result.variants) {
      const auto it = std::find_if(v.images.begin(), v.images.end(), [&](const std::string& p) {
        return std::filesystem::path(p).filename().string() == file;
      });
      if (it == v.images.end()) continue;
      tiles.push_back(render::read_image(out_dir / *it));
      captions.push_back(v.name);
    }
    if (tiles.size() < 2) continue;
    const std::string name = "comparison-" + file;
    render::write_png(render::compose_sheet(tiles, captions), out_dir / name);
    out.push_back(name);
  }
  return out;
}

}  // namespace beadtwin::scenarios
