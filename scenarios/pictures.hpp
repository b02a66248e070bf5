// The pictures of a run (the render: block): for every picture of a variant, the quantity it colours the part
// by worked out from the run's results, rendered, annotated with a title, legend and scale bar, and written;
// the build's progress frames; and the comparison sheets that put the variants' pictures side by side.
//
// Pictures compare across variants because they share a frame (PictureFrame): one camera box around every
// variant's part and one colour scale per colouring, fixed before any variant is rendered.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "core/toolpath.hpp"
#include "render/annotate.hpp"
#include "render/surface.hpp"
#include "scenarios/input/result.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/variant_run.hpp"
#include "sim/deposit.hpp"
#include "thermal/thermal.hpp"

namespace beadtwin::scenarios {

// What the variants' pictures share.
struct PictureFrame {
  Eigen::AlignedBox3f bounds;        // mm: every variant's print, beads and all
  double print_time_s = 0.0;         // the longest print
  int layers = 0;                    // the most layers
  double cold_c = 20.0;              // temperature scales: the lowest ambient...
  double hot_c = 240.0;              // ...and the highest deposition temperature
  double stock_centre_mm = 0.0;      // deviation scale: the requested stock (the least over the variants)...
  double stock_half_range_mm = 5.0;  // ...± the largest layer height
  render::LengthUnit length_unit = render::LengthUnit::kMetric;  // inches when the scenario writes inches
};

// The frame of `variants`, whose toolpaths are `toolpaths` (same order). `inches`: the scale bars in inches.
PictureFrame picture_frame(const std::vector<const Variant*>& variants,
                           const std::vector<const Toolpath*>& toolpaths, bool inches);

// The moments the pictures of `spec` need the temperature of every thermal cell at (pictures coloured by
// temperature, and progress frames so coloured), s from the start of the print; a picture without a time
// takes the end of its layer (or of the print).
std::vector<double> picture_snapshot_times(const RenderSpec& spec, const Toolpath& toolpath);

struct PictureInputs {
  const Scenario* scenario = nullptr;
  const Variant* variant = nullptr;
  const Toolpath* toolpath = nullptr;
  const sim::Deposit* deposit = nullptr;
  const CadCheck* cad = nullptr;  // null without a CAD to compare with
  const PictureFrame* frame = nullptr;
  // The whole deposit's surface as the pictures draw it, when it was meshed already (for the skin: one
  // meshing for both); none, or nullopt from it, and the pictures mesh the fill grid themselves. Called at
  // most once, when the pictures of the whole part are prepared.
  std::function<std::optional<render::SurfaceMesh>()> whole_surface;
};

// What PictureWriter wrote, relative to the run's output directory.
struct PictureFiles {
  std::vector<std::string> images;    // PNG, one per picture, in the order of the render block
  std::vector<std::string> exr;       // with render.exr
  std::vector<std::string> progress;  // the progress frames, in layer order
};

// Whether pictures so coloured need the thermal run (temperatures, fusion verdicts, healing).
bool needs_thermal(Colouring colouring);

// Renders the variant's pictures into `dir` (the variant's own directory, named after it under the run's
// output directory), in two goes so that most of the work can run beside the thermal stage:
// - without_thermal() needs only the deposit and the CAD comparison: it prepares the shape of every picture
//   (its surface and ray-tracing scene) and draws the pictures not coloured by a thermal result;
// - finish() draws the rest from the thermal run and returns every file, in the order of the render block.
// The two may run on different threads, one after the other. A picture that cannot be drawn for this variant
// (a deviation without a CAD) is left out with a note when the scenario asked for it, silently when it is one
// of the defaults. What `in` points to must outlive the writer.
class PictureWriter {
 public:
  PictureWriter(const PictureInputs& in, std::filesystem::path dir);
  ~PictureWriter();
  PictureWriter(const PictureWriter&) = delete;
  PictureWriter& operator=(const PictureWriter&) = delete;

  void without_thermal();
  PictureFiles finish(const thermal::ThermalResult& thermal);
  // What the pictures had to say (left-out pictures), in the order of the render block.
  const std::vector<std::string>& notes() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// For every picture name, the variants' pictures side by side with their names (comparison-<name>.png in
// `out_dir`), when there are two variants or more and render.sheet is on. Returns the files, relative to
// `out_dir`.
std::vector<std::string> write_sheets(const RunResult& result, const std::filesystem::path& out_dir);

}  // namespace beadtwin::scenarios
