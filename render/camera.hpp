// Cameras of the render stage: the standard views of a part, framed automatically on its bounding box.
//
// The machine frame is z up. The isometric view looks from the (+x, -y, +z) corner at the
// centre of the box; the top view looks down -z with +y up the image; the front view looks along +y with
// +z up the image. Framing fits the box's eight corners into the image with a margin on every side.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace beadtwin::render {

enum class View { kIsometric, kTop, kFront };

struct Ray {
  Eigen::Vector3f origin = Eigen::Vector3f::Zero();      // mm
  Eigen::Vector3f direction = Eigen::Vector3f::UnitZ();  // unit length
};

class Camera {
 public:
  // A camera for `view` that frames `bounds` (world, mm; non-empty) in an image of width x height pixels,
  // leaving `margin` (a fraction of the image, 0..0.45) free on each side of the box's outline.
  // `field_of_view_deg` (0..120) applies to the isometric view: 0 makes it orthographic; the top and front
  // views are always orthographic, as engineering drawings are.
  static Camera framed(View view, const Eigen::AlignedBox3f& bounds, int width, int height,
                       double field_of_view_deg, double margin = 0.08);

  // The ray through image position (u, v): u across 0..1 from the left edge, v down 0..1 from the top edge.
  Ray ray(double u, double v) const;
  // Where a world point lands in the image, in the same (u, v). Perspective: the point must be in front.
  Eigen::Vector2d project(const Eigen::Vector3f& point) const;

  bool orthographic() const { return orthographic_; }
  const Eigen::Vector3f& eye() const { return eye_; }
  const Eigen::Vector3f& forward() const { return forward_; }  // viewing direction
  const Eigen::Vector3f& right() const { return right_; }      // image +u
  const Eigen::Vector3f& up() const { return up_; }            // image -v

 private:
  // Image-plane coordinates of a point: mm for orthographic, tangents for perspective.
  Eigen::Vector2d plane(const Eigen::Vector3f& point) const;

  Eigen::Vector3f eye_ = Eigen::Vector3f::Zero();
  Eigen::Vector3f forward_ = -Eigen::Vector3f::UnitZ();
  Eigen::Vector3f right_ = Eigen::Vector3f::UnitX();
  Eigen::Vector3f up_ = Eigen::Vector3f::UnitY();
  Eigen::Vector2d window_min_ = Eigen::Vector2d::Zero();  // image plane seen by the image, left/bottom
  Eigen::Vector2d window_max_ = Eigen::Vector2d::Ones();  // right/top
  bool orthographic_ = true;
};

}  // namespace beadtwin::render
