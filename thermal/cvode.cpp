#include "thermal/cvode.hpp"

#include <algorithm>
#include <cstdlib>
#include <utility>
#include <vector>

#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunlinsol/sunlinsol_spgmr.h>
#include <sunmatrix/sunmatrix_band.h>

#include "core/error.hpp"
#include "thermal/vector_ops.hpp"

namespace beadtwin::thermal {

namespace {

std::string flag_name(int flag) {
  // CVodeGetReturnFlagName hands back a malloc'ed string.
  char* name = CVodeGetReturnFlagName(flag);
  std::string result = name != nullptr ? name : "unknown";
  std::free(name);
  return result;
}

}  // namespace

void OdeSystem::jacobian(double, std::span<const double>, BandJacobian&) {
  throw InternalError("this ODE system has no banded Jacobian: solve it with GMRES");
}
void OdeSystem::jacobian_times_setup(double, std::span<const double>) {}
void OdeSystem::jacobian_times(double, std::span<const double>, std::span<const double>, std::span<double>) {
  throw InternalError("this ODE system has no Jacobian-vector product: solve it with the banded solver");
}
void OdeSystem::jacobian_diagonal(double, std::span<const double>, std::span<double>) {
  throw InternalError("this ODE system has no Jacobian diagonal: solve it with the banded solver");
}

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
    : system_(system),
      size_(y0.size()),
      upper_(options.upper_bandwidth),
      lower_(options.lower_bandwidth),
      kind_(options.solver) {
  BT_CHECK_OP(size_, >, 0u);
  SUNContext ctx = nullptr;
  // SUNDIALS 6 without MPI: the communicator argument is a null pointer.
  if (SUNContext_Create(nullptr, &ctx) != 0 || ctx == nullptr)
    throw InternalError("SUNDIALS: SUNContext_Create failed");
  context_.reset(ctx);

  Communicator* comm = options.communicator;
  BT_CHECK(comm == nullptr || kind_ == LinearSolver::kGmres);
  y_ = make_vector(y0, comm);
  scratch_ = make_vector(y0, comm);

  const auto n = static_cast<sunindextype>(size_);
  if (kind_ == LinearSolver::kBand) {
    matrix_.reset(SUNBandMatrix(n, static_cast<sunindextype>(upper_), static_cast<sunindextype>(lower_),
                                context_.get()));
    if (!matrix_) throw InternalError("SUNDIALS: SUNBandMatrix failed");
    solver_.reset(SUNLinSol_Band(y_.get(), matrix_.get(), context_.get()));
    if (!solver_) throw InternalError("SUNDIALS: SUNLinSol_Band failed");
  } else {
    BT_CHECK_OP(options.krylov_dimension, >, 0);
    preconditioner_.assign(size_, 1.0);
    solver_.reset(SUNLinSol_SPGMR(y_.get(), SUN_PREC_LEFT, options.krylov_dimension, context_.get()));
    if (!solver_) throw InternalError("SUNDIALS: SUNLinSol_SPGMR failed");
    // Classical Gram-Schmidt with the vectors' fused operations: one pass over memory for all the dot
    // products of an iteration, where modified Gram-Schmidt makes one pass each.
    if (SUNLinSol_SPGMRSetGSType(solver_.get(), SUN_CLASSICAL_GS) != 0)
      throw InternalError("SUNDIALS: SUNLinSol_SPGMRSetGSType failed");
  }

  mem_.reset(CVodeCreate(CV_BDF, context_.get()));
  if (!mem_) throw InternalError("SUNDIALS: CVodeCreate failed");
  check(CVodeSetErrHandlerFn(mem_.get(), &Cvode::error_handler, this), "CVodeSetErrHandlerFn");
  check(CVodeInit(mem_.get(), &Cvode::rhs_trampoline, t0, y_.get()), "CVodeInit");
  check(CVodeSetUserData(mem_.get(), this), "CVodeSetUserData");
  check(CVodeWFtolerances(mem_.get(), &Cvode::weights_trampoline), "CVodeWFtolerances");
  check(CVodeSetLinearSolver(mem_.get(), solver_.get(), matrix_.get()), "CVodeSetLinearSolver");
  if (kind_ == LinearSolver::kBand) {
    check(CVodeSetJacFn(mem_.get(), &Cvode::jacobian_trampoline), "CVodeSetJacFn");
  } else {
    check(CVodeSetJacTimes(mem_.get(), &Cvode::jtsetup_trampoline, &Cvode::jtimes_trampoline),
          "CVodeSetJacTimes");
    check(CVodeSetPreconditioner(mem_.get(), &Cvode::psetup_trampoline, &Cvode::psolve_trampoline),
          "CVodeSetPreconditioner");
    // GMRES stops at this fraction of the Newton iteration's tolerance (CVODE's default is 0.05). With only
    // a diagonal preconditioner, long conduction paths converge slowly, and at 0.05 the leftover residual
    // lets a steady state drift by kelvins from step to step; 1e-3 holds it.
    check(CVodeSetEpsLin(mem_.get(), 1e-3), "CVodeSetEpsLin");
  }
  if (options.max_step_s > 0.0) check(CVodeSetMaxStep(mem_.get(), options.max_step_s), "CVodeSetMaxStep");
}

Cvode::~Cvode() = default;

Cvode::VectorHandle Cvode::make_vector(std::span<const double> init, Communicator* comm) {
  VectorHandle v;
  if (comm == nullptr) {
    v.reset(N_VNew_Serial(static_cast<sunindextype>(init.size()), context_.get()));
    if (!v) throw InternalError("SUNDIALS: N_VNew_Serial failed");
    if (N_VEnableFusedOps_Serial(v.get(), SUNTRUE) != 0)
      throw InternalError("SUNDIALS: N_VEnableFusedOps_Serial failed");
  } else {
    // The global length is the sum of the ranks' parts.
    std::size_t global = 0;
    for (const double l : comm->gather_each(static_cast<double>(init.size())))
      global += static_cast<std::size_t>(l);
    v.reset(comm->new_vector(init.size(), global, context_.get()));
    if (!v) throw InternalError("SUNDIALS: N_VNew_Parallel failed");
  }
  use_blocked_vector_ops(v.get(), comm != nullptr);
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

void Cvode::reinit(double t0, std::span<const double> y0, double first_step_s) {
  BT_CHECK_OP(y0.size(), ==, size_);
  long steps_now = 0, rhs_now = 0, linear_now = 0;
  check(CVodeGetNumSteps(mem_.get(), &steps_now), "CVodeGetNumSteps");
  check(CVodeGetNumRhsEvals(mem_.get(), &rhs_now), "CVodeGetNumRhsEvals");
  check(CVodeGetNumLinIters(mem_.get(), &linear_now), "CVodeGetNumLinIters");
  steps_before_reinit_ += steps_now;
  rhs_before_reinit_ += rhs_now;
  linear_before_reinit_ += linear_now;
  check(CVodeSetInitStep(mem_.get(), std::max(first_step_s, 0.0)), "CVodeSetInitStep");
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

double Cvode::last_step() const {
  double h = 0.0;
  if (CVodeGetLastStep(mem_.get(), &h) < 0) throw InternalError("CVODE: CVodeGetLastStep failed");
  return h;
}

long Cvode::rhs_evaluations() const {
  long n = 0;
  if (CVodeGetNumRhsEvals(mem_.get(), &n) < 0) throw InternalError("CVODE: CVodeGetNumRhsEvals failed");
  return rhs_before_reinit_ + n;
}

long Cvode::linear_iterations() const {
  long n = 0;
  if (CVodeGetNumLinIters(mem_.get(), &n) < 0) throw InternalError("CVODE: CVodeGetNumLinIters failed");
  return linear_before_reinit_ + n;
}

// CVODE calls it before every linear solve, with the y its products are then taken at (cvLsSolve).
int Cvode::jtsetup_trampoline(double t, N_Vector y, N_Vector /*fy*/, void* user_data) {
  auto* self = static_cast<Cvode*>(user_data);
  try {
    self->system_.jacobian_times_setup(t, self->values(y));
    return 0;
  } catch (...) {
    self->callback_error_ = std::current_exception();
    return -1;
  }
}

int Cvode::jtimes_trampoline(N_Vector v, N_Vector jv, double t, N_Vector y, N_Vector /*fy*/, void* user_data,
                             N_Vector /*tmp*/) {
  auto* self = static_cast<Cvode*>(user_data);
  try {
    self->system_.jacobian_times(t, self->values(y), self->values(v), self->values(jv));
    return 0;
  } catch (...) {
    self->callback_error_ = std::current_exception();
    return -1;
  }
}

// The preconditioner P = diag(I − γJ): the Jacobian's diagonal is taken when CVODE asks (it is cheap, so
// always afresh), γ is the one of each solve.
int Cvode::psetup_trampoline(double t, N_Vector y, N_Vector /*fy*/, int /*jok*/, int* jcur, double /*gamma*/,
                             void* user_data) {
  auto* self = static_cast<Cvode*>(user_data);
  try {
    self->system_.jacobian_diagonal(t, self->values(y), self->preconditioner_);
    *jcur = 1;
    return 0;
  } catch (...) {
    self->callback_error_ = std::current_exception();
    return -1;
  }
}

int Cvode::psolve_trampoline(double /*t*/, N_Vector /*y*/, N_Vector /*fy*/, N_Vector r, N_Vector z,
                             double gamma, double /*delta*/, int /*lr*/, void* user_data) {
  auto* self = static_cast<Cvode*>(user_data);
  const std::span<const double> in = self->values(r);
  const std::span<double> out = self->values(z);
  const std::vector<double>& jd = self->preconditioner_;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double m = 1.0 - gamma * jd[i];
    out[i] = m != 0.0 ? in[i] / m : in[i];
  }
  return 0;
}

int Cvode::rhs_trampoline(double t, N_Vector y, N_Vector ydot, void* user_data) {
  auto* self = static_cast<Cvode*>(user_data);
  try {
    self->system_.rhs(t, self->values(y), self->values(ydot));
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
    self->system_.jacobian(t, self->values(y), band);
    return 0;
  } catch (...) {
    self->callback_error_ = std::current_exception();
    return -1;
  }
}

int Cvode::weights_trampoline(N_Vector y, N_Vector weights, void* user_data) {
  auto* self = static_cast<Cvode*>(user_data);
  try {
    self->system_.error_weights(self->values(y), self->values(weights));
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
