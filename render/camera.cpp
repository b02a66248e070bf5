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
  }
  throw InternalError("unknown View");
}

}  // namespace

Camera Camera::framed(View view, const Eigen::AlignedBox3f& bounds, int width, int height,
                      double field_of_view_deg, double margin) {
  BT_CHECK(!bounds.isEmpty());
  BT_CHECK(width > 0 && height > 0);
  BT_CHECK(field_of_view_deg >= 0.0 && field_of_view_deg <= 120.0);
  BT_CHECK(margin >= 0.0 && margin <= 0.45);

  Camera camera;
  const Orientation o = orientation(view);
  camera.forward_ = o.forward;
  camera.right_ = o.forward.cross(o.image_up).normalized();
  camera.up_ = camera.right_.cross(o.forward);
  camera.orthographic_ = view != View::kIsometric || field_of_view_deg <= 0.0;

  // Back off so the bounding sphere fills the field of view: every corner is then in front of the eye.
  const Eigen::Vector3f centre = bounds.center();
  const double radius = std::max(0.5 * static_cast<double>(bounds.diagonal().norm()), 1e-3);
  const double distance =
      camera.orthographic_ ? 2.0 * radius : radius / std::sin(0.5 * field_of_view_deg * kPi / 180.0);
  camera.eye_ = centre - static_cast<float>(distance) * camera.forward_;

  // The window is the outline of the corners on the image plane, grown by the margin and widened in one
  // direction to the image's aspect ratio. It need not be centred on the view axis (a shifted lens), so
  // the box sits in the middle of the image whatever its shape.
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector2d hi = -lo;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector2d p = camera.plane(bounds.corner(static_cast<Eigen::AlignedBox3f::CornerType>(i)));
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector2d mid = 0.5 * (lo + hi);
  const double tiny = 1e-6 * std::max(1.0, std::max(hi.cwiseAbs().maxCoeff(), lo.cwiseAbs().maxCoeff()));
  Eigen::Vector2d half = (0.5 * (hi - lo)).cwiseMax(tiny);
  half /= 1.0 - 2.0 * margin;
  const double aspect = static_cast<double>(width) / height;
  if (half.x() < aspect * half.y())
    half.x() = aspect * half.y();
  else
    half.y() = half.x() / aspect;
  camera.window_min_ = mid - half;
  camera.window_max_ = mid + half;
  return camera;
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

Eigen::Vector2d Camera::project(const Eigen::Vector3f& point) const {
  const Eigen::Vector2d p = plane(point);
  return {(p.x() - window_min_.x()) / (window_max_.x() - window_min_.x()),
          (window_max_.y() - p.y()) / (window_max_.y() - window_min_.y())};
}

}  // namespace beadtwin::render
