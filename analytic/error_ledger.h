// The error bound that `furnace analytic` prints beside each value: a scoped
// ledger that the quadratures in analytic/ report their own error estimates
// to, so that a caller can learn how far a value may be from the exact one
// without every function returning an (value, error) pair.
//
// What a ledger holds: the sum of the relative error estimates reported while
// it was the innermost open ledger of its thread (each report is a
// quadrature's own estimate |K − G| of its integral divided by the integral's
// magnitude, or a bisection cap's leftover). Summing relative errors bounds
// the relative error of a sum or product of positive pieces; it does not see
// cancellation between pieces, which the callers that subtract (variances)
// account for themselves. A round-off term is added by the caller
// (kRoundoffUlps below). This is a documented estimate, not a proof.
#pragma once

#include <cmath>
#include <limits>

namespace furnace::analytic {

// Round-off allowance of a closed form or a rule evaluated in double, in
// units of machine epsilon relative to the value: the closed forms here are
// tested to ≤ 64 ε (tests/analytic/precision_sweep_test.cpp) on geometry whose
// inputs are exact in double. Inputs that are themselves rounded (a receiver
// normal nearly in the light's plane, coordinates far from the origin) add
// their own conditioning, which this allowance does not cover.
inline constexpr double kRoundoffUlps = 64;

class ErrorLedger {
 public:
  ErrorLedger() : outer_(current()) { current() = this; }
  ~ErrorLedger() {
    current() = outer_;
    if (outer_ != nullptr) outer_->relative_ += relative_;
  }
  ErrorLedger(const ErrorLedger&) = delete;
  ErrorLedger& operator=(const ErrorLedger&) = delete;

  // The relative quadrature error reported so far.
  double relative_quadrature_error() const { return relative_; }
  // Returns the relative error reported so far and clears it, so that none of
  // it reaches the enclosing ledger (the caller reports it in another form).
  double take_relative() {
    const double r = relative_;
    relative_ = 0;
    return r;
  }
  // |value|·(reported relative error + kRoundoffUlps·ε).
  double bound(double value) const {
    return std::fabs(value) * (relative_ + kRoundoffUlps * std::numeric_limits<double>::epsilon());
  }

  // Reports a quadrature's absolute error estimate `abs_error` relative to
  // `scale`, the magnitude of the quantity it is an error of (the integral,
  // or the whole a piece contributes to), to the innermost open ledger
  // (none: ignored). A zero scale with a nonzero error is infinitely wrong.
  static void report(double abs_error, double scale) {
    ErrorLedger* ledger = current();
    if (ledger == nullptr || !(abs_error > 0)) return;
    ledger->relative_ += scale != 0 ? std::fabs(abs_error / scale) : INFINITY;
  }

 private:
  static ErrorLedger*& current() {
    thread_local ErrorLedger* ledger = nullptr;
    return ledger;
  }
  ErrorLedger* outer_;
  double relative_ = 0;
};

// The error of a sum of terms, each computed under its own ledger: a term's
// relative error becomes an absolute error |term|·r, and the sum reports
// Σ|termᵢ|·rᵢ relative to |Σ termᵢ|. Summing the terms' relative errors
// instead would let a negligible term with a poorly resolved value (a tiny
// far light whose contour integral cancels to 1e-12 of its edge terms)
// swamp the bound of the whole.
class ErrorSum {
 public:
  // Evaluates `term()` under its own ledger and returns its value.
  template <class Term>
  double term(Term&& term) {
    ErrorLedger ledger;
    const double value = term();
    absolute_ += std::fabs(value) * ledger.take_relative();
    return value;
  }
  // Reports the accumulated error of the terms relative to `sum`, their sum.
  void report(double sum) const { ErrorLedger::report(absolute_, sum); }

 private:
  double absolute_ = 0;
};

}  // namespace furnace::analytic
