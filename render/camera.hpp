// Cameras of the render stage: the standard views of a part and the user's own, framed automatically on
// its bounding box.
//
// The machine frame is z up. The isometric view looks from the (+x, -y, +z) corner at the centre of the
// box; the top view looks down -z with +y up the image; the front view looks along +y (from the -y side)
// and the side view along -x (from the +x side), both with +z up the image, as third-angle drawings place
// them. A user camera is either placed (an eye position and a point it looks at) or only aimed (a viewing
// direction, the eye then backed off along it until the part fits). Framing fits the box's eight corners
// into the image with a margin on every side, which may differ side by side (room for a title or a
// legend).
#pragma once

#include <optional>
#include <string_view>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/enum_names.hpp"

namespace beadtwin::render {

// Where the camera looks from: the standard views, or one the user places or aims.
enum class View { kIsometric, kTop, kFront, kSide, kUser };
inline constexpr EnumName<View> kViewNames[] = {{View::kIsometric, "isometric"},
                                                {View::kTop, "top"},
                                                {View::kFront, "front"},
                                                {View::kSide, "side"},
                                                {View::kUser, "user"}};
constexpr std::span<const EnumName<View>> enum_names(View) {
  return kViewNames;
}
// The view's name in scenario files ("isometric", "top", "front", "side", "user").
inline std::string_view to_string(View view) {
  return name_of(view);
}

// A camera as a scenario states it.
struct CameraSpec {
  View view = View::kIsometric;
  // kUser: the eye (world, mm). Without it the camera looks along `direction` and is framed on the part.
  std::optional<Eigen::Vector3f> position;
  // kUser: the point looked at (world, mm); without it, the centre of the part's bounding box.
  std::optional<Eigen::Vector3f> target;
  // kUser without a position: the viewing direction (need not be unit length, must not be zero).
  Eigen::Vector3f direction = Eigen::Vector3f(-1, 1, -1);
  // Perspective, degrees of the image's shorter side (1..120), or 0 for orthographic. The isometric view
  // and user cameras take it; the top, front and side views are always orthographic, as drawings are.
  double field_of_view_deg = 30.0;
};

// Free space left between the part's outline and each edge of the image, as fractions of the image's
// width (left, right) and height (top, bottom); each 0..0.45.
struct Margins {
  double left = 0.08, right = 0.08, top = 0.08, bottom = 0.08;
  static Margins uniform(double m) { return {m, m, m, m}; }
};

// A ray in the world frame.
struct Ray {
  Eigen::Vector3f origin = Eigen::Vector3f::Zero();      // mm
  Eigen::Vector3f direction = Eigen::Vector3f::UnitZ();  // unit length
};

// A camera framed on a part: orthographic or perspective, mapping image positions to rays and back.
class Camera {
 public:
  // A camera for `view` that frames `bounds` (world, mm; non-empty) in an image of width x height pixels,
  // leaving `margin` (a fraction of the image, 0..0.45) free on each side of the box's outline.
  // `field_of_view_deg` (0..120) applies to the isometric view: 0 makes it orthographic; the top and front
  // views are always orthographic, as engineering drawings are.
  static Camera framed(View view, const Eigen::AlignedBox3f& bounds, int width, int height,
                       double field_of_view_deg, double margin = 0.08);
  // The camera `spec` describes, for the part in `bounds` (world, mm; non-empty) in an image of width x
  // height pixels. Standard views and aimed user cameras are framed within `margins`. A placed user camera
  // keeps its eye and target: perspective, its field of view is what it sees; orthographic, its window is
  // the part's outline within the margins. Throws InputError for a spec that cannot make a camera (eye at
  // the target, zero direction, field of view out of range).
  static Camera make(const CameraSpec& spec, const Eigen::AlignedBox3f& bounds, int width, int height,
                     const Margins& margins = {});

  // The ray through image position (u, v): u across 0..1 from the left edge, v down 0..1 from the top edge.
  Ray ray(double u, double v) const;
  // Where a world point lands in the image, in the same (u, v). Perspective: the point must be in front.
  Eigen::Vector2d project(const Eigen::Vector3f& point) const;

  // Image scale at a world point, mm per pixel across the image (the scale bar's length): the same
  // everywhere for an orthographic camera, at the point's depth for a perspective one (which must be in
  // front of the eye).
  double mm_per_pixel_at(const Eigen::Vector3f& point, int width) const;

  bool orthographic() const { return orthographic_; }
  const Eigen::Vector3f& eye() const { return eye_; }
  const Eigen::Vector3f& forward() const { return forward_; }  // viewing direction
  const Eigen::Vector3f& right() const { return right_; }      // image +u
  const Eigen::Vector3f& up() const { return up_; }            // image -v

 private:
  // Image-plane coordinates of a point: mm for orthographic, tangents for perspective.
  Eigen::Vector2d plane(const Eigen::Vector3f& point) const;
  // Looking along `forward` (unit) with `image_up` (not parallel to it) up the image.
  void orient(const Eigen::Vector3f& forward, const Eigen::Vector3f& image_up);
  // Sets the window to the outline of `bounds` grown by `margins`, widened to the image's aspect ratio.
  void frame_window(const Eigen::AlignedBox3f& bounds, int width, int height, const Margins& margins);

  Eigen::Vector3f eye_ = Eigen::Vector3f::Zero();
  Eigen::Vector3f forward_ = -Eigen::Vector3f::UnitZ();
  Eigen::Vector3f right_ = Eigen::Vector3f::UnitX();
  Eigen::Vector3f up_ = Eigen::Vector3f::UnitY();
  Eigen::Vector2d window_min_ = Eigen::Vector2d::Zero();  // image plane seen by the image, left/bottom
  Eigen::Vector2d window_max_ = Eigen::Vector2d::Ones();  // right/top
  bool orthographic_ = true;
};

}  // namespace beadtwin::render
