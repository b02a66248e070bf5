// A small RAII wrapper around SUNDIALS 6 CVODE (BDF, with a banded direct linear solver or preconditioned
// GMRES), internal to the thermal library. It is the one place where SUNDIALS is called and where its return
// codes become exceptions: every handle (context, vectors, matrix, linear solver,
// integrator memory) is owned here, CVODE's error handler is installed at creation, and an exception thrown
// by a callback is carried across the C boundary and rethrown to the caller.
#pragma once

#include <cstddef>
#include <exception>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

#include "thermal/communicator.hpp"

namespace beadtwin::thermal {

// Write access to the banded Jacobian matrix CVODE asks for. The matrix is zero when handed out.
class BandJacobian {
 public:
  BandJacobian(SUNMatrix matrix, std::size_t upper_bandwidth, std::size_t lower_bandwidth);
  // Sets J(row, col) = ∂f_row/∂y_col. The entry must lie inside the band (InternalError otherwise).
  void set(std::size_t row, std::size_t col, double value);

 private:
  SUNMatrix matrix_;
  std::size_t upper_;
  std::size_t lower_;
};

// The ODE system dy/dt = f(t, y) CVODE integrates. Callbacks may throw; the exception reaches the caller
// of Cvode::step. A system solved with the banded solver provides jacobian(); one solved with GMRES provides
// jacobian_times() and jacobian_diagonal() (the preconditioner is the diagonal of I − γJ).
class OdeSystem {
 public:
  virtual ~OdeSystem() = default;
  // ydot = f(t, y); t in s.
  virtual void rhs(double t, std::span<const double> y, std::span<double> ydot) = 0;
  // Fills the nonzero entries of ∂f/∂y at (t, y); entries not set are zero.
  virtual void jacobian(double t, std::span<const double> y, BandJacobian& jacobian);
  // Called before each linear solve with the (t, y) every jacobian_times() of that solve is taken at, so a
  // system can work out once what its products there share. Does nothing unless overridden.
  virtual void jacobian_times_setup(double t, std::span<const double> y);
  // Jv = (∂f/∂y at (t, y)) · v.
  virtual void jacobian_times(double t, std::span<const double> y, std::span<const double> v,
                              std::span<double> jv);
  // The diagonal of ∂f/∂y at (t, y).
  virtual void jacobian_diagonal(double t, std::span<const double> y, std::span<double> diagonal);
  // Error weights of the local error test: CVODE accepts a step when the weighted RMS norm of its local
  // error estimate is below 1, so weight_i = 1 / (the error allowed on y_i). All weights must be > 0.
  virtual void error_weights(std::span<const double> y, std::span<double> weights) = 0;
};

// The linear solver of CVODE's Newton iterations: banded direct, or GMRES preconditioned by the diagonal.
enum class LinearSolver { kBand, kGmres };

// How the integrator is set up.
struct CvodeOptions {
  LinearSolver solver = LinearSolver::kBand;
  std::size_t upper_bandwidth = 0;  // kBand
  std::size_t lower_bandwidth = 0;  // kBand
  int krylov_dimension = 10;        // kGmres: the largest Krylov subspace
  double max_step_s = 0.0;          // > 0: the longest step CVODE may take
  // Non-null: the state is shared among these ranks in SUNDIALS' MPI-parallel vectors (kGmres only). Every
  // vector the integrator sees is then this rank's part of the state, and every rank makes the same calls.
  Communicator* communicator = nullptr;
};

// CVODE's BDF integrator on one OdeSystem.
class Cvode {
 public:
  // `system` must outlive the integrator. y0.size() sets the (fixed) state size: of this rank's part when
  // the options name a communicator.
  Cvode(OdeSystem& system, double t0, std::span<const double> y0, const CvodeOptions& options);
  ~Cvode();
  Cvode(const Cvode&) = delete;
  Cvode& operator=(const Cvode&) = delete;

  // Restarts the integration at (t0, y0) after a discontinuity (element birth); keeps the step count. With
  // first_step_s > 0 the first step tries that size instead of CVODE's own estimate.
  void reinit(double t0, std::span<const double> y0, double first_step_s = 0.0);
  // The integrator never steps past t_stop, and returns exactly at it. Must lie ahead of the current time.
  void set_stop_time(double t_stop);
  // Takes one internal step towards t_out and returns the time reached; the state is state().
  double step(double t_out);
  // State after the last step (or at the last (re)initialisation); this rank's part of it with a
  // communicator.
  std::span<const double> state() const;
  // State interpolated at t, which must lie within the last step. Valid until the next call.
  std::span<const double> interpolate(double t);
  // Internal steps taken since construction, over all restarts.
  long steps() const;
  // The size of the last step taken, s (0 before the first).
  double last_step() const;
  // Right-hand side evaluations, GMRES iterations (0 with the banded solver), over all restarts.
  long rhs_evaluations() const;
  long linear_iterations() const;

 private:
  template <class T, void (*Free)(T)>
  struct Deleter {
    void operator()(T handle) const noexcept { Free(handle); }
  };
  static void free_context(SUNContext ctx) noexcept;
  static void free_cvode(void* mem) noexcept;
  using ContextHandle = std::unique_ptr<std::remove_pointer_t<SUNContext>, Deleter<SUNContext, free_context>>;
  using VectorHandle = std::unique_ptr<std::remove_pointer_t<N_Vector>, Deleter<N_Vector, N_VDestroy>>;
  using MatrixHandle = std::unique_ptr<std::remove_pointer_t<SUNMatrix>, Deleter<SUNMatrix, SUNMatDestroy>>;
  struct SolverFree {
    void operator()(SUNLinearSolver ls) const noexcept { SUNLinSolFree(ls); }
  };
  using SolverHandle = std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, SolverFree>;
  struct CvodeFree {
    void operator()(void* mem) const noexcept { free_cvode(mem); }
  };
  using CvodeHandle = std::unique_ptr<void, CvodeFree>;

  static int rhs_trampoline(double t, N_Vector y, N_Vector ydot, void* user_data);
  static int jacobian_trampoline(double t, N_Vector y, N_Vector fy, SUNMatrix jac, void* user_data,
                                 N_Vector tmp1, N_Vector tmp2, N_Vector tmp3);
  static int weights_trampoline(N_Vector y, N_Vector weights, void* user_data);
  static int jtsetup_trampoline(double t, N_Vector y, N_Vector fy, void* user_data);
  static int jtimes_trampoline(N_Vector v, N_Vector jv, double t, N_Vector y, N_Vector fy, void* user_data,
                               N_Vector tmp);
  static int psetup_trampoline(double t, N_Vector y, N_Vector fy, int jok, int* jcur, double gamma,
                               void* user_data);
  static int psolve_trampoline(double t, N_Vector y, N_Vector fy, N_Vector r, N_Vector z, double gamma,
                               double delta, int lr, void* user_data);
  static void error_handler(int error_code, const char* module, const char* function, char* message,
                            void* user_data);
  // Throws (the callback's exception if one is pending, else InternalError naming `call`) when flag < 0.
  void check(int flag, const char* call);
  VectorHandle make_vector(std::span<const double> values, Communicator* communicator);
  // This rank's values of a vector of the integrator's.
  std::span<double> values(N_Vector v) const { return {N_VGetArrayPointer(v), size_}; }

  OdeSystem& system_;
  std::size_t size_;
  std::size_t upper_;
  std::size_t lower_;
  long steps_before_reinit_ = 0;
  long rhs_before_reinit_ = 0;
  long linear_before_reinit_ = 0;
  LinearSolver kind_;
  std::vector<double> preconditioner_;  // kGmres: the Jacobian's diagonal J_ii
  std::string last_message_;
  std::exception_ptr callback_error_;
  // Declaration order is destruction order reversed: CVODE memory goes first, the context last.
  ContextHandle context_;
  VectorHandle y_;
  VectorHandle scratch_;
  MatrixHandle matrix_;
  SolverHandle solver_;
  CvodeHandle mem_;
};

}  // namespace beadtwin::thermal
