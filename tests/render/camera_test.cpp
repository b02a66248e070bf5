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
  for (const View view : {View::kIsometric, View::kTop, View::kFront})
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
  for (const View view : {View::kIsometric, View::kTop, View::kFront}) {
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

}  // namespace
}  // namespace beadtwin::render
