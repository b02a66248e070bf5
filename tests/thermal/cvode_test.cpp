// Tests of the SUNDIALS wrapper: a linear test problem with a known solution, and errors as exceptions.
#include "thermal/cvode.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace beadtwin::thermal {
namespace {

// y0' = −y0, y1' = y0 − 2 y1 (lower bidiagonal), y(0) = (1, 0):
// y0 = e^−t, y1 = e^−t − e^−2t.
class Decay : public OdeSystem {
 public:
  bool throw_in_rhs = false;
  void rhs(double /*t*/, std::span<const double> y, std::span<double> ydot) override {
    if (throw_in_rhs) throw std::runtime_error("rhs failed on purpose");
    ydot[0] = -y[0];
    ydot[1] = y[0] - 2.0 * y[1];
  }
  void jacobian(double /*t*/, std::span<const double> /*y*/, BandJacobian& jac) override {
    jac.set(0, 0, -1.0);
    jac.set(1, 0, 1.0);
    jac.set(1, 1, -2.0);
  }
  void error_weights(std::span<const double> y, std::span<double> weights) override {
    for (std::size_t i = 0; i < y.size(); ++i) weights[i] = 1.0 / (1e-8 * std::abs(y[i]) + 1e-10);
  }
};

CvodeOptions band(std::size_t upper, std::size_t lower) {
  CvodeOptions options;
  options.upper_bandwidth = upper;
  options.lower_bandwidth = lower;
  return options;
}

TEST(CvodeTest, IntegratesALinearSystemToItsTolerance) {
  Decay system;
  const std::vector<double> y0{1.0, 0.0};
  Cvode cvode(system, 0.0, y0, band(0, 1));
  cvode.set_stop_time(2.0);
  double t = 0.0;
  while (t < 2.0) {
    const double t_prev = t;
    t = cvode.step(2.0);
    // Interpolation inside the step agrees with the exact solution too.
    const double mid = 0.5 * (t_prev + t);
    EXPECT_NEAR(cvode.interpolate(mid)[0], std::exp(-mid), 1e-6);
  }
  EXPECT_DOUBLE_EQ(t, 2.0);  // returns exactly at the stop time
  EXPECT_NEAR(cvode.state()[0], std::exp(-2.0), 1e-7);
  EXPECT_NEAR(cvode.state()[1], std::exp(-2.0) - std::exp(-4.0), 1e-7);
  const long steps = cvode.steps();
  EXPECT_GT(steps, 10);

  // Restart from a new state: the step count keeps growing.
  cvode.reinit(2.0, y0);
  cvode.set_stop_time(3.0);
  while (t < 3.0) t = cvode.step(3.0);
  EXPECT_NEAR(cvode.state()[0], std::exp(-1.0), 1e-7);
  EXPECT_GT(cvode.steps(), steps);
}

TEST(CvodeTest, CallbackExceptionsReachTheCaller) {
  Decay system;
  const std::vector<double> y0{1.0, 0.0};
  Cvode cvode(system, 0.0, y0, band(0, 1));
  system.throw_in_rhs = true;
  EXPECT_THROW(cvode.step(1.0), std::runtime_error);
}

TEST(CvodeTest, SundialsFailuresAreInternalErrors) {
  Decay system;
  const std::vector<double> y0{1.0, 0.0};
  Cvode cvode(system, 0.0, y0, band(0, 1));
  cvode.step(1.0);
  try {
    cvode.interpolate(100.0);  // far outside the last step
    FAIL() << "expected an InternalError";
  } catch (const InternalError& e) {
    EXPECT_NE(std::string(e.what()).find("CVodeGetDky"), std::string::npos) << e.what();
  }
}

TEST(CvodeTest, JacobianEntriesOutsideTheBandAreRejected) {
  // A Jacobian that writes outside the declared band (upper 0) is a bug, caught as an InternalError.
  class Wide : public Decay {
    void jacobian(double, std::span<const double>, BandJacobian& jac) override { jac.set(0, 1, 1.0); }
  } system;
  const std::vector<double> y0{1.0, 0.0};
  Cvode cvode(system, 0.0, y0, band(0, 1));
  EXPECT_THROW(cvode.step(1.0), InternalError);
}

}  // namespace
}  // namespace beadtwin::thermal
