#include "render/camera.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace beadtwin::render {
namespace {

// A 600 mm box of 250 mm walls, as the LSAM pictures show.
const Eigen::AlignedBox3f lsam_box(Eigen::Vector3f(-10, 0, 0), Eigen::Vector3f(610, 600, 250));

std::pair<Eigen::Vector2d, Eigen::Vector2d> outline(const Camera& camera, const Eigen::AlignedBox3f& box) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e9), hi = -lo;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector2d p = camera.project(box.corner(static_cast<Eigen::AlignedBox3f::CornerType>(i)));
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return {lo, hi};
}

TEST(Camera, FramesTheBoxWithTheMarginInEveryView) {
  for (const View view : {View::kIsometric, View::kTop, View::kFront, View::kSide})
    for (const double fov : {0.0, 30.0}) {
      const Camera camera = Camera::framed(view, lsam_box, 1280, 800, fov, 0.08);
      const auto [lo, hi] = outline(camera, lsam_box);
      SCOPED_TRACE(::testing::Message() << "view " << static_cast<int>(view) << " fov " << fov);
      EXPECT_GE(lo.minCoeff(), 0.08 - 1e-6);
      EXPECT_LE(hi.maxCoeff(), 0.92 + 1e-6);
      // Tight on one axis, centred on both.
      EXPECT_TRUE(std::abs(lo.x() - 0.08) < 1e-4 || std::abs(lo.y() - 0.08) < 1e-4) << lo.transpose();
      EXPECT_NEAR(lo.x() + hi.x(), 1.0, 1e-6);
      EXPECT_NEAR(lo.y() + hi.y(), 1.0, 1e-6);
    }
}

TEST(Camera, RaysAndProjectionAgree) {
  for (const View view : {View::kIsometric, View::kTop, View::kFront, View::kSide}) {
    const Camera camera = Camera::framed(view, lsam_box, 640, 480, 30.0);
    for (const auto& [u, v] : {std::pair{0.5, 0.5}, {0.1, 0.9}, {0.77, 0.2}}) {
      const Ray ray = camera.ray(u, v);
      EXPECT_NEAR(ray.direction.norm(), 1.0f, 1e-6f);
      const Eigen::Vector2d back = camera.project(ray.origin + 700.0f * ray.direction);
      EXPECT_NEAR(back.x(), u, 1e-5);
      EXPECT_NEAR(back.y(), v, 1e-5);
    }
  }
}

TEST(Camera, StandardViewsAreOrientedAsDrawings) {
  const Eigen::Vector3f c = lsam_box.center();
  const Camera top = Camera::framed(View::kTop, lsam_box, 800, 800, 30.0);
  EXPECT_TRUE(top.orthographic());
  EXPECT_GT(top.project(c + Eigen::Vector3f::UnitX()).x(), top.project(c).x());  // +x to the right
  EXPECT_LT(top.project(c + Eigen::Vector3f::UnitY()).y(), top.project(c).y());  // +y up the image
  const Camera front = Camera::framed(View::kFront, lsam_box, 800, 800, 30.0);
  EXPECT_GT(front.project(c + Eigen::Vector3f::UnitX()).x(), front.project(c).x());
  EXPECT_LT(front.project(c + Eigen::Vector3f::UnitZ()).y(), front.project(c).y());  // +z up
  // The side view from +x: +y runs to the right, as in a third-angle drawing beside the front view.
  const Camera side = Camera::framed(View::kSide, lsam_box, 800, 800, 30.0);
  EXPECT_TRUE(side.orthographic());
  EXPECT_GT(side.eye().x(), lsam_box.max().x());
  EXPECT_GT(side.project(c + Eigen::Vector3f::UnitY()).x(), side.project(c).x());
  EXPECT_LT(side.project(c + Eigen::Vector3f::UnitZ()).y(), side.project(c).y());
  const Camera iso = Camera::framed(View::kIsometric, lsam_box, 800, 800, 30.0);
  EXPECT_FALSE(iso.orthographic());
  EXPECT_LT(iso.project(c + Eigen::Vector3f::UnitZ()).y(), iso.project(c).y());
  EXPECT_FALSE(lsam_box.contains(iso.eye()));
  EXPECT_GT(iso.eye().x(), c.x());  // from the (+x, -y, +z) side
  EXPECT_LT(iso.eye().y(), c.y());
  EXPECT_GT(iso.eye().z(), c.z());
}

TEST(Camera, FlatAndTinyBoxesStillFrame) {
  const Eigen::AlignedBox3f flat(Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(100, 100, 0));
  const Camera front = Camera::framed(View::kFront, flat, 100, 100, 0.0);
  const auto [lo, hi] = outline(front, flat);
  EXPECT_GE(lo.minCoeff(), 0.0);
  EXPECT_LE(hi.maxCoeff(), 1.0);
  EXPECT_THROW(Camera::framed(View::kTop, Eigen::AlignedBox3f(), 100, 100, 0.0), InternalError);
}

// Margins that differ side by side (room for a legend on the right, a title at the top): the outline
// touches the free area's edges on its tight axis and is centred in it on the other.
TEST(Camera, UnequalMarginsKeepTheirSides) {
  const Margins m{0.05, 0.25, 0.12, 0.06};
  for (const View view : {View::kIsometric, View::kTop, View::kFront, View::kSide}) {
    CameraSpec spec;
    spec.view = view;
    const Camera camera = Camera::make(spec, lsam_box, 1920, 1080, m);
    const auto [lo, hi] = outline(camera, lsam_box);
    SCOPED_TRACE(::testing::Message() << "view " << static_cast<int>(view));
    EXPECT_GE(lo.x(), m.left - 1e-6);
    EXPECT_LE(hi.x(), 1.0 - m.right + 1e-6);
    EXPECT_GE(lo.y(), m.top - 1e-6);
    EXPECT_LE(hi.y(), 1.0 - m.bottom + 1e-6);
    EXPECT_NEAR(0.5 * (lo.x() + hi.x()), m.left + 0.5 * (1.0 - m.left - m.right), 1e-6);
    EXPECT_NEAR(0.5 * (lo.y() + hi.y()), m.top + 0.5 * (1.0 - m.top - m.bottom), 1e-6);
  }
}

// A placed perspective camera looks where it is told: the target in the image's centre, the eye where it
// was put, a point off the axis at the angle the field of view gives.
TEST(Camera, PlacedUserCameraKeepsItsEyeAndLens) {
  CameraSpec spec;
  spec.view = View::kUser;
  spec.position = Eigen::Vector3f(2000, -1500, 1200);
  spec.target = Eigen::Vector3f(300, 300, 0);
  spec.field_of_view_deg = 40.0;
  const Camera camera = Camera::make(spec, lsam_box, 1000, 500);
  EXPECT_FALSE(camera.orthographic());
  EXPECT_TRUE(camera.eye().isApprox(*spec.position));
  const Eigen::Vector2d centre = camera.project(*spec.target);
  EXPECT_NEAR(centre.x(), 0.5, 1e-6);
  EXPECT_NEAR(centre.y(), 0.5, 1e-6);
  // 20 degrees above the axis is the top edge of the image (the shorter side spans the 40 degrees).
  const Eigen::Vector3f axis = (*spec.target - *spec.position).normalized();
  const Eigen::Vector3f tilted =
      Eigen::AngleAxisf(static_cast<float>(20.0 * 3.14159265358979 / 180.0), camera.right()) * axis;
  EXPECT_NEAR(camera.project(*spec.position + 1000.0f * tilted).y(), 0.0, 1e-5);
}

// An aimed user camera (a direction, no eye) is framed like a standard view; orthographic with fov 0.
TEST(Camera, AimedUserCameraIsFramed) {
  CameraSpec spec;
  spec.view = View::kUser;
  spec.direction = Eigen::Vector3f(1, 2, -0.5);
  for (const double fov : {0.0, 25.0}) {
    spec.field_of_view_deg = fov;
    const Camera camera = Camera::make(spec, lsam_box, 800, 600, Margins::uniform(0.1));
    EXPECT_EQ(camera.orthographic(), fov == 0.0);
    EXPECT_TRUE(camera.forward().isApprox(spec.direction.normalized(), 1e-6f));
    const auto [lo, hi] = outline(camera, lsam_box);
    EXPECT_GE(lo.minCoeff(), 0.1 - 1e-6);
    EXPECT_LE(hi.maxCoeff(), 0.9 + 1e-6);
    EXPECT_FALSE(lsam_box.contains(camera.eye()));
  }
  // Looking straight down, +y is up the image as in the top view.
  spec.direction = -Eigen::Vector3f::UnitZ();
  spec.field_of_view_deg = 0.0;
  const Camera down = Camera::make(spec, lsam_box, 800, 600);
  const Eigen::Vector3f c = lsam_box.center();
  EXPECT_LT(down.project(c + Eigen::Vector3f::UnitY()).y(), down.project(c).y());
}

TEST(Camera, BadUserCamerasAreInputErrors) {
  CameraSpec spec;
  spec.view = View::kUser;
  spec.position = spec.target = Eigen::Vector3f(1, 2, 3);
  EXPECT_THROW(Camera::make(spec, lsam_box, 100, 100), InputError);
  spec.position.reset();
  spec.direction = Eigen::Vector3f::Zero();
  EXPECT_THROW(Camera::make(spec, lsam_box, 100, 100), InputError);
  spec.direction = Eigen::Vector3f::UnitX();
  spec.field_of_view_deg = 150.0;
  EXPECT_THROW(Camera::make(spec, lsam_box, 100, 100), InputError);
}

// The scale bar's mm per pixel: a 600 mm edge seen square-on spans 600 / (mm per pixel) pixels, in an
// orthographic view everywhere and in perspective at the edge's depth.
TEST(Camera, MillimetresPerPixelMeasureTheImage) {
  const Eigen::Vector3f a(0, 0, 0), b(600, 0, 0);
  const Camera front = Camera::framed(View::kFront, lsam_box, 1200, 800, 0.0);
  const double ortho_px = (front.project(b).x() - front.project(a).x()) * 1200;
  EXPECT_NEAR(600.0 / front.mm_per_pixel_at(a, 1200), ortho_px, 1e-3);
  CameraSpec spec;
  spec.view = View::kUser;
  spec.position = Eigen::Vector3f(300, -2000, 0);
  spec.target = Eigen::Vector3f(300, 0, 0);
  const Camera persp = Camera::make(spec, lsam_box, 1200, 800);
  const double persp_px = (persp.project(b).x() - persp.project(a).x()) * 1200;
  // The edge's ends are a little deeper than its middle (the point measured): within 5 %.
  EXPECT_NEAR(600.0 / persp.mm_per_pixel_at(Eigen::Vector3f(300, 0, 0), 1200), persp_px, 0.05 * persp_px);
}

}  // namespace
}  // namespace beadtwin::render
