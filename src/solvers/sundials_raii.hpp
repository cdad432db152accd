// RAII wrappers around the few SUNDIALS (6.x) C objects the time-domain
// simulator uses: context, serial vector, CVODE memory, fixed-point nonlinear
// solver. Every failed call throws chatter::NumericalError naming the call,
// SUNDIALS' flag name and the message CVODE produced (captured by an error
// handler instead of being printed on stderr). Internal header.
#pragma once

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <cstdlib>
#include <string>

#include "chatter/error.hpp"

namespace chatter::sundials {

class Context {
 public:
  Context() {
    if (SUNContext_Create(nullptr, &ctx_) != 0 || ctx_ == nullptr)
      throw NumericalError("SUNContext_Create failed (out of memory?)");
  }
  ~Context() { SUNContext_Free(&ctx_); }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  operator SUNContext() const { return ctx_; }

 private:
  SUNContext ctx_ = nullptr;
};

class SerialVector {
 public:
  SerialVector(sunindextype n, SUNContext ctx) : v_(N_VNew_Serial(n, ctx)) {
    if (v_ == nullptr) throw NumericalError("N_VNew_Serial failed (out of memory?)");
  }
  ~SerialVector() { N_VDestroy(v_); }
  SerialVector(const SerialVector&) = delete;
  SerialVector& operator=(const SerialVector&) = delete;
  operator N_Vector() const { return v_; }
  double* data() const { return N_VGetArrayPointer(v_); }

 private:
  N_Vector v_;
};

class FixedPointSolver {
 public:
  FixedPointSolver(N_Vector y, int acceleration_vectors, SUNContext ctx)
      : s_(SUNNonlinSol_FixedPoint(y, acceleration_vectors, ctx)) {
    if (s_ == nullptr) throw NumericalError("SUNNonlinSol_FixedPoint failed (out of memory?)");
  }
  ~FixedPointSolver() { SUNNonlinSolFree(s_); }
  FixedPointSolver(const FixedPointSolver&) = delete;
  FixedPointSolver& operator=(const FixedPointSolver&) = delete;
  operator SUNNonlinearSolver() const { return s_; }

 private:
  SUNNonlinearSolver s_;
};

/// CVODE memory with an error handler that keeps the last message. `label`
/// starts the messages of failed calls (the model integrated).
class Cvode {
 public:
  Cvode(int method, SUNContext ctx, const char* label = "time-domain") : mem_(CVodeCreate(method, ctx)), label_(label) {
    if (mem_ == nullptr) throw NumericalError("CVodeCreate failed (out of memory?)");
    CVodeSetErrHandlerFn(mem_, &Cvode::handler, this);
  }
  ~Cvode() { CVodeFree(&mem_); }
  Cvode(const Cvode&) = delete;
  Cvode& operator=(const Cvode&) = delete;
  void* get() const { return mem_; }

  /// Throws NumericalError when `flag` < 0 (a failed call).
  void check(int flag, const char* call) const {
    if (flag >= 0) return;
    char* name = CVodeGetReturnFlagName(flag);  // malloc'ed by SUNDIALS
    std::string what = std::string(label_) + ": " + call + " failed (" + (name ? name : "?") + ")";
    std::free(name);
    if (!last_message_.empty()) what += ": " + last_message_;
    throw NumericalError(what);
  }

 private:
  static void handler(int /*code*/, const char* module, const char* function, char* msg, void* self) {
    auto* me = static_cast<Cvode*>(self);
    me->last_message_ = std::string(module ? module : "") + "/" + (function ? function : "") + ": " +
                        (msg ? msg : "");
  }
  void* mem_;
  const char* label_;
  std::string last_message_;
};

}  // namespace chatter::sundials
