#include "render/camera.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "core/units.hpp"

namespace beadtwin::render {

namespace {

struct Orientation {
  Eigen::Vector3f forward;
  Eigen::Vector3f image_up;  // a world direction that should point up the image
};

Orientation orientation(View view) {
  switch (view) {
    case View::kIsometric:
      return {Eigen::Vector3f(-1, 1, -1).normalized(), Eigen::Vector3f::UnitZ()};
    case View::kTop:
      return {-Eigen::Vector3f::UnitZ(), Eigen::Vector3f::UnitY()};
    case View::kFront:
      return {Eigen::Vector3f::UnitY(), Eigen::Vector3f::UnitZ()};
    case View::kSide:
      return {-Eigen::Vector3f::UnitX(), Eigen::Vector3f::UnitZ()};
    case View::kUser:
      break;
  }
  throw InternalError("orientation: not a standard view");
}

// Up the image is +z unless the camera looks (nearly) straight up or down; then +y, as in the top view.
Eigen::Vector3f image_up_for(const Eigen::Vector3f& forward) {
  return std::abs(forward.z()) > 0.999f ? Eigen::Vector3f::UnitY() : Eigen::Vector3f::UnitZ();
}

void check_margins(const Margins& m) {
  for (const double f : {m.left, m.right, m.top, m.bottom}) BT_CHECK(f >= 0.0 && f <= 0.45);
}

}  // namespace

Camera Camera::framed(View view, const Eigen::AlignedBox3f& bounds, int width, int height,
                      double field_of_view_deg, double margin) {
  BT_CHECK(view != View::kUser);
  CameraSpec spec;
  spec.view = view;
  spec.field_of_view_deg = field_of_view_deg;
  BT_CHECK(field_of_view_deg >= 0.0 && field_of_view_deg <= 120.0);
  return make(spec, bounds, width, height, Margins::uniform(margin));
}

Camera Camera::make(const CameraSpec& spec, const Eigen::AlignedBox3f& bounds, int width, int height,
                    const Margins& margins) {
  BT_CHECK(!bounds.isEmpty());
  BT_CHECK(width > 0 && height > 0);
  check_margins(margins);
  const double fov = spec.field_of_view_deg;
  if (!(fov == 0.0 || (fov >= 1.0 && fov <= 120.0)))
    throw InputError({}, "camera.field_of_view",
                     "must be 0 (orthographic) or 1..120 degrees, got " + std::to_string(fov));

  Camera camera;
  const Eigen::Vector3f centre = bounds.center();
  const Eigen::Vector3f target = spec.target.value_or(centre);
  Eigen::Vector3f forward;
  if (spec.view != View::kUser) {
    forward = orientation(spec.view).forward;
  } else if (spec.position) {
    forward = target - *spec.position;
    if (!(forward.norm() > 1e-6f))
      throw InputError({}, "camera.position", "the eye is at the point it looks at: they must differ");
  } else {
    forward = spec.direction;
    if (!(forward.norm() > 1e-6f) || !forward.allFinite())
      throw InputError({}, "camera.direction", "must be a non-zero direction");
  }
  forward.normalize();
  camera.orient(forward, spec.view == View::kUser ? image_up_for(forward) : orientation(spec.view).image_up);
  camera.orthographic_ =
      fov <= 0.0 || spec.view == View::kTop || spec.view == View::kFront || spec.view == View::kSide;

  if (spec.view == View::kUser && spec.position && !camera.orthographic_) {
    // Placed in perspective: the eye and the lens are the user's, and the window is centred on the axis.
    camera.eye_ = *spec.position;
    const double half = std::tan(0.5 * fov * kPi / 180.0);
    const double aspect = static_cast<double>(width) / height;
    const Eigen::Vector2d extent =
        aspect >= 1.0 ? Eigen::Vector2d(half * aspect, half) : Eigen::Vector2d(half, half / aspect);
    camera.window_min_ = -extent;
    camera.window_max_ = extent;
    return camera;
  }
  // Back off so the bounding sphere fills the field of view: every corner is then in front of the eye.
  const double radius = std::max(0.5 * static_cast<double>(bounds.diagonal().norm()), 1e-3);
  const double distance = camera.orthographic_ ? 2.0 * radius : radius / std::sin(0.5 * fov * kPi / 180.0);
  const Eigen::Vector3f look_at = spec.view == View::kUser ? target : centre;
  camera.eye_ = look_at - (static_cast<float>(distance) + (look_at - centre).norm()) * camera.forward_;
  camera.frame_window(bounds, width, height, margins);
  return camera;
}

void Camera::orient(const Eigen::Vector3f& forward, const Eigen::Vector3f& image_up) {
  forward_ = forward;
  right_ = forward.cross(image_up).normalized();
  up_ = right_.cross(forward);
}

// The window is the outline of the corners on the image plane, grown by the margins and widened in one
// direction to the image's aspect ratio. It need not be centred on the view axis (a shifted lens), so the
// box sits in the middle of the free part of the image whatever its shape.
void Camera::frame_window(const Eigen::AlignedBox3f& bounds, int width, int height, const Margins& m) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector2d hi = -lo;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector2d p = plane(bounds.corner(static_cast<Eigen::AlignedBox3f::CornerType>(i)));
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double tiny = 1e-6 * std::max(1.0, std::max(hi.cwiseAbs().maxCoeff(), lo.cwiseAbs().maxCoeff()));
  const Eigen::Vector2d size = (hi - lo).cwiseMax(2.0 * tiny);
  // The window's size: the outline fills the free fraction of each axis, and the axis with room to spare
  // grows to the aspect ratio.
  const double free_x = 1.0 - m.left - m.right, free_y = 1.0 - m.top - m.bottom;
  BT_CHECK(free_x > 0.0 && free_y > 0.0);
  Eigen::Vector2d window(size.x() / free_x, size.y() / free_y);
  const double aspect = static_cast<double>(width) / height;
  if (window.x() < aspect * window.y())
    window.x() = aspect * window.y();
  else
    window.y() = window.x() / aspect;
  // Centre the outline in the free part: image u runs left to right, image v top to bottom, while the plane
  // coordinates' y runs upwards.
  const Eigen::Vector2d mid = 0.5 * (lo + hi);
  const double u_mid = m.left + 0.5 * free_x, v_mid = m.top + 0.5 * free_y;
  window_min_.x() = mid.x() - u_mid * window.x();
  window_max_.x() = window_min_.x() + window.x();
  window_max_.y() = mid.y() + v_mid * window.y();
  window_min_.y() = window_max_.y() - window.y();
}

Eigen::Vector2d Camera::plane(const Eigen::Vector3f& point) const {
  const Eigen::Vector3d rel = (point - eye_).cast<double>();
  const Eigen::Vector2d p(rel.dot(right_.cast<double>()), rel.dot(up_.cast<double>()));
  return orthographic_ ? p : Eigen::Vector2d(p / rel.dot(forward_.cast<double>()));
}

Ray Camera::ray(double u, double v) const {
  const double px = window_min_.x() + u * (window_max_.x() - window_min_.x());
  const double py = window_max_.y() - v * (window_max_.y() - window_min_.y());
  const Eigen::Vector3f offset = static_cast<float>(px) * right_ + static_cast<float>(py) * up_;
  if (orthographic_) return {eye_ + offset, forward_};
  return {eye_, (forward_ + offset).normalized()};
}

double Camera::mm_per_pixel_at(const Eigen::Vector3f& point, int width) const {
  BT_CHECK(width > 0);
  const double across = window_max_.x() - window_min_.x();
  if (orthographic_) return across / width;
  const double depth = (point - eye_).cast<double>().dot(forward_.cast<double>());
  BT_CHECK(depth > 0.0);
  return across * depth / width;
}

Eigen::Vector2d Camera::project(const Eigen::Vector3f& point) const {
  const Eigen::Vector2d p = plane(point);
  return {(p.x() - window_min_.x()) / (window_max_.x() - window_min_.x()),
          (window_max_.y() - p.y()) / (window_max_.y() - window_min_.y())};
}

}  // namespace beadtwin::render
