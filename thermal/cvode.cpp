#include "thermal/cvode.hpp"

#include <algorithm>
#include <cstdlib>
#include <utility>

#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunmatrix/sunmatrix_band.h>

#include "core/error.hpp"

namespace beadtwin::thermal {

namespace {

std::span<double> values(N_Vector v) {
  return {N_VGetArrayPointer(v), static_cast<std::size_t>(N_VGetLength(v))};
}

std::string flag_name(int flag) {
  // CVodeGetReturnFlagName hands back a malloc'ed string.
  char* name = CVodeGetReturnFlagName(flag);
  std::string result = name != nullptr ? name : "unknown";
  std::free(name);
  return result;
}

}  // namespace

BandJacobian::BandJacobian(SUNMatrix matrix, std::size_t upper_bandwidth, std::size_t lower_bandwidth)
    : matrix_(matrix), upper_(upper_bandwidth), lower_(lower_bandwidth) {}

void BandJacobian::set(std::size_t row, std::size_t col, double value) {
  BT_CHECK_OP(col, <=, row + upper_);
  BT_CHECK_OP(row, <=, col + lower_);
  // SUNBandMatrix_Column points at the diagonal entry of column `col`; row `row` is offset row − col.
  double* column = SUNBandMatrix_Column(matrix_, static_cast<sunindextype>(col));
  column[static_cast<std::ptrdiff_t>(row) - static_cast<std::ptrdiff_t>(col)] = value;
}

void Cvode::free_context(SUNContext ctx) noexcept {
  SUNContext_Free(&ctx);
}
void Cvode::free_cvode(void* mem) noexcept {
  CVodeFree(&mem);
}

Cvode::Cvode(OdeSystem& system, double t0, std::span<const double> y0, const CvodeOptions& options)
    : system_(system), size_(y0.size()), upper_(options.upper_bandwidth), lower_(options.lower_bandwidth) {
  BT_CHECK_OP(size_, >, 0u);
  SUNContext ctx = nullptr;
  // SUNDIALS 6 without MPI: the communicator argument is a null pointer.
  if (SUNContext_Create(nullptr, &ctx) != 0 || ctx == nullptr)
    throw InternalError("SUNDIALS: SUNContext_Create failed");
  context_.reset(ctx);

  y_ = make_vector(y0);
  scratch_ = make_vector(y0);

  const auto n = static_cast<sunindextype>(size_);
  matrix_.reset(
      SUNBandMatrix(n, static_cast<sunindextype>(upper_), static_cast<sunindextype>(lower_), context_.get()));
  if (!matrix_) throw InternalError("SUNDIALS: SUNBandMatrix failed");
  solver_.reset(SUNLinSol_Band(y_.get(), matrix_.get(), context_.get()));
  if (!solver_) throw InternalError("SUNDIALS: SUNLinSol_Band failed");

  mem_.reset(CVodeCreate(CV_BDF, context_.get()));
  if (!mem_) throw InternalError("SUNDIALS: CVodeCreate failed");
  check(CVodeSetErrHandlerFn(mem_.get(), &Cvode::error_handler, this), "CVodeSetErrHandlerFn");
  check(CVodeInit(mem_.get(), &Cvode::rhs_trampoline, t0, y_.get()), "CVodeInit");
  check(CVodeSetUserData(mem_.get(), this), "CVodeSetUserData");
  check(CVodeWFtolerances(mem_.get(), &Cvode::weights_trampoline), "CVodeWFtolerances");
  check(CVodeSetLinearSolver(mem_.get(), solver_.get(), matrix_.get()), "CVodeSetLinearSolver");
  check(CVodeSetJacFn(mem_.get(), &Cvode::jacobian_trampoline), "CVodeSetJacFn");
}

Cvode::~Cvode() = default;

Cvode::VectorHandle Cvode::make_vector(std::span<const double> init) {
  VectorHandle v(N_VNew_Serial(static_cast<sunindextype>(init.size()), context_.get()));
  if (!v) throw InternalError("SUNDIALS: N_VNew_Serial failed");
  std::span<double> out = values(v.get());
  std::copy(init.begin(), init.end(), out.begin());
  return v;
}

void Cvode::check(int flag, const char* call) {
  if (flag >= 0) return;
  if (callback_error_) {
    std::exception_ptr error = std::exchange(callback_error_, nullptr);
    std::rethrow_exception(error);
  }
  std::string message = std::string("CVODE: ") + call + " failed with " + flag_name(flag);
  if (!last_message_.empty()) message += ": " + last_message_;
  throw InternalError(message);
}

void Cvode::reinit(double t0, std::span<const double> y0) {
  BT_CHECK_OP(y0.size(), ==, size_);
  long steps_now = 0;
  check(CVodeGetNumSteps(mem_.get(), &steps_now), "CVodeGetNumSteps");
  steps_before_reinit_ += steps_now;
  std::span<double> y = values(y_.get());
  std::copy(y0.begin(), y0.end(), y.begin());
  last_message_.clear();
  check(CVodeReInit(mem_.get(), t0, y_.get()), "CVodeReInit");
}

void Cvode::set_stop_time(double t_stop) {
  check(CVodeSetStopTime(mem_.get(), t_stop), "CVodeSetStopTime");
}

double Cvode::step(double t_out) {
  double t_reached = 0.0;
  check(CVode(mem_.get(), t_out, y_.get(), &t_reached, CV_ONE_STEP), "CVode");
  return t_reached;
}

std::span<const double> Cvode::state() const {
  return values(y_.get());
}

std::span<const double> Cvode::interpolate(double t) {
  check(CVodeGetDky(mem_.get(), t, 0, scratch_.get()), "CVodeGetDky");
  return values(scratch_.get());
}

long Cvode::steps() const {
  long steps_now = 0;
  if (CVodeGetNumSteps(mem_.get(), &steps_now) < 0) throw InternalError("CVODE: CVodeGetNumSteps failed");
  return steps_before_reinit_ + steps_now;
}

int Cvode::rhs_trampoline(double t, N_Vector y, N_Vector ydot, void* user_data) {
  auto* self = static_cast<Cvode*>(user_data);
  try {
    self->system_.rhs(t, values(y), values(ydot));
    return 0;
  } catch (...) {
    self->callback_error_ = std::current_exception();
    return -1;  // unrecoverable: CVODE stops and check() rethrows
  }
}

int Cvode::jacobian_trampoline(double t, N_Vector y, N_Vector /*fy*/, SUNMatrix jac, void* user_data,
                               N_Vector /*tmp1*/, N_Vector /*tmp2*/, N_Vector /*tmp3*/) {
  auto* self = static_cast<Cvode*>(user_data);
  try {
    if (SUNMatZero(jac) != 0) throw InternalError("SUNDIALS: SUNMatZero failed");
    BandJacobian band(jac, self->upper_, self->lower_);
    self->system_.jacobian(t, values(y), band);
    return 0;
  } catch (...) {
    self->callback_error_ = std::current_exception();
    return -1;
  }
}

int Cvode::weights_trampoline(N_Vector y, N_Vector weights, void* user_data) {
  auto* self = static_cast<Cvode*>(user_data);
  try {
    self->system_.error_weights(values(y), values(weights));
    return 0;
  } catch (...) {
    self->callback_error_ = std::current_exception();
    return -1;
  }
}

void Cvode::error_handler(int error_code, const char* module, const char* function, char* message,
                          void* user_data) {
  auto* self = static_cast<Cvode*>(user_data);
  if (error_code == CV_WARNING) return;  // warnings (e.g. t + h == t) are not failures
  self->last_message_ = std::string(module != nullptr ? module : "") + "/" +
                        (function != nullptr ? function : "") + ": " + (message != nullptr ? message : "");
}

}  // namespace beadtwin::thermal
