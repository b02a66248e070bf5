// The render: block: picture settings, the pictures of every variant, and the progress frames.
#include <set>

#include <fmt/format.h>

#include "scenarios/input/params.hpp"
#include "scenarios/input/scenario_blocks.hpp"

namespace beadtwin::scenarios {
namespace {

// The view keys of an image or of the progress frames, read into `camera`, and what they mean together.
void read_camera(BlockReader& r, render::CameraSpec& camera) {
  const std::set<std::string_view> given = r.read(camera_params(), camera);
  if (camera.field_of_view_deg > 0.0 && camera.field_of_view_deg < 1.0)
    r.fail(r.take("field_of_view"), "field_of_view",
           fmt::format("must be 0 (orthographic) or 1..120 deg, got {:g} deg", camera.field_of_view_deg));
  const bool user_keys = given.contains("camera.position") || given.contains("camera.target") ||
                         given.contains("camera.direction");
  if (user_keys && camera.view != render::View::kUser)
    r.fail(r.take("view"), "view", "the camera keys place a user camera: set view: user");
  if (camera.position && camera.target && (*camera.position - *camera.target).norm() < 1e-3f)
    r.fail(r.take("camera.target"), "camera.target", "the eye is at the point it looks at: they must differ");
}

// The unit a colouring's range is written in.
Dimension colouring_dimension(Colouring c) {
  switch (c) {
    case Colouring::kTime:
      return Dimension::kTime;
    case Colouring::kSubstrate:
    case Colouring::kSurface:
    case Colouring::kTemperature:
      return Dimension::kTemperature;
    case Colouring::kHealing:
    case Colouring::kPorosity:
      return Dimension::kFraction;
    case Colouring::kDeviation:
      return Dimension::kLength;
    default:
      return Dimension::kDimensionless;
  }
}

// A cutaway: a point of the plane and its normal (the half it points into is taken away).
std::optional<CutSpec> read_cut(BlockReader& r) {
  const auto& t = image_params();
  if (!r.has("cut.point")) {
    if (r.has("cut.normal")) r.fail(r.take("cut.normal"), "cut.normal", "a cut needs cut.point too");
    return std::nullopt;
  }
  const auto corner = [&](const char* key) {
    const ParamInfo& info = find_param(t, key);
    const YAML::Node node = r.take(key);
    const ParamValue::List v = (node.IsDefined() ? r.value(node, info, ParamShape::kPoint, 3, {})
                                                 : r.default_value(info, ParamShape::kPoint, 3, {}))
                                   .list();
    return Eigen::Vector3d(v[0].number(), v[1].number(), v[2].number());
  };
  CutSpec cut;
  cut.point = corner("cut.point");
  cut.normal = corner("cut.normal");
  if (!(cut.normal.norm() > 0.0))
    r.fail(r.take("cut.normal"), "cut.normal", "a direction cannot be [0, 0, 0]");
  cut.normal.normalize();
  return cut;
}

// The colour scale's ends [low, high], in the colouring's unit.
std::optional<std::pair<double, double>> read_range(BlockReader& r, Colouring colour) {
  const YAML::Node range = r.take("range");
  if (!range.IsDefined()) return std::nullopt;
  if (colour == Colouring::kFusion || colour == Colouring::kSection)
    r.fail(range, "range", "fusion and section colour by category: they have no range");
  if (!range.IsSequence() || range.size() != 2) r.fail(range, "range", "expected [low, high]");
  const Dimension dim = colouring_dimension(colour);
  const double lo = r.parse(range[0], dim, "range"), hi = r.parse(range[1], dim, "range");
  if (!(lo < hi)) r.fail(range, "range", fmt::format("low ({:g}) must be below high ({:g})", lo, hi));
  return std::pair{lo, hi};
}

ImageSpec read_image(BlockReader& r) {
  ImageSpec im;
  const std::set<std::string_view> given = r.read(image_params(), im);
  read_camera(r, im.camera);
  im.cut = read_cut(r);
  if (given.contains("time") && im.colour != Colouring::kTemperature)
    r.fail(r.take("time"), "time", "only a picture coloured by temperature has a time");
  im.range = read_range(r, im.colour);
  const std::string view(render::to_string(im.camera.view));
  const YAML::Node name = r.take("name");
  if (name.IsDefined() && !name.IsScalar()) r.fail(name, "name", "expected a text value");
  im.name = name.IsDefined() ? name.Scalar()
                             : std::string(to_string(im.colour)) + (view == "isometric" ? "" : "-" + view);
  if (im.name.empty() || im.name.find_first_of("/\\:*?\"<>|") != std::string::npos || im.name[0] == '.')
    r.fail(name, "name", fmt::format("'{}' cannot be a file name", im.name));
  r.finish(image_params(), camera_params());
  return im;
}

// The pictures a scenario gets without a render.images list.
std::vector<ImageSpec> default_images() {
  std::vector<ImageSpec> out;
  const auto add = [&](Colouring c, render::View view, std::string name) {
    ImageSpec im;
    im.colour = c;
    im.camera.view = view;
    im.name = std::move(name);
    out.push_back(im);
  };
  add(Colouring::kFusion, render::View::kIsometric, "fusion");
  add(Colouring::kFusion, render::View::kTop, "fusion-top");
  add(Colouring::kSection, render::View::kIsometric, "sections");
  add(Colouring::kSubstrate, render::View::kIsometric, "substrate");
  add(Colouring::kDeviation, render::View::kIsometric, "deviation");
  return out;
}

std::vector<ImageSpec> read_images(BlockReader& r, const YAML::Node& images) {
  if (!images.IsSequence())
    r.fail(images, "images", "expected a list of pictures such as [{colour: fusion, view: top}]");
  std::vector<ImageSpec> out;
  for (std::size_t i = 0; i < images.size(); ++i) {
    BlockReader ir(images[i], r.full_key(fmt::format("images[{}]", i)), r.shared_source(), r.overridden());
    if (!images[i].IsMap()) r.fail(images[i], "images", "each picture is a map {colour: ..., view: ...}");
    ImageSpec im = read_image(ir);
    for (const ImageSpec& other : out)
      if (other.name == im.name)
        ir.fail(images[i], "name",
                fmt::format("two pictures are named '{}': give one a name of its own", im.name));
    out.push_back(std::move(im));
  }
  return out;
}

// render.progress: none, or a map {colour, every, and the view keys}.
std::optional<ProgressSpec> read_progress(BlockReader& r) {
  const YAML::Node progress = r.take("progress");
  if (!progress.IsDefined() || progress.IsNull() || (progress.IsScalar() && progress.Scalar() == "none"))
    return std::nullopt;
  if (!progress.IsMap())
    r.fail(progress, "progress", "expected none or a map {colour: layer, view: isometric, every: 1}");
  BlockReader pr(progress, r.full_key("progress"), r.shared_source(), r.overridden());
  ProgressSpec ps;
  pr.read(progress_params(), ps);
  read_camera(pr, ps.camera);
  pr.finish(progress_params(), camera_params());
  return ps;
}

}  // namespace

RenderSpec read_render(BlockReader& r) {
  RenderSpec rs;
  r.read(render_params(), rs);
  const YAML::Node images = r.take("images");
  rs.images_given = images.IsDefined();
  rs.images = rs.images_given ? read_images(r, images) : default_images();
  rs.progress = read_progress(r);
  r.finish(render_params());
  return rs;
}

}  // namespace beadtwin::scenarios
