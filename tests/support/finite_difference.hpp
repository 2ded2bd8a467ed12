// Central finite differences: the one helper with which the tests check analytic derivatives
// (gradients, Jacobians, Hessians as Jacobians of gradients).
#pragma once
#include <type_traits>
#include <vector>

namespace dipc::test {

// Central differences of f: R^n -> R^m at x with step h, into J (m x n, row-major):
// J[i * n + j] ~ d f_i / d x_j. f(const double* x, double* out) writes its m values; where it
// returns bool, false (it cannot be evaluated there, e.g. an inverted element) makes this
// return false. The denominator is the step actually taken, (x_j + h) - (x_j - h) as rounded,
// so the rounding of x_j +- h does not bias the quotient.
template <class F>
bool central_difference(F&& f, const double* x, int n, int m, double h, double* J) {
  std::vector<double> y(x, x + n), up(m), down(m);
  const auto evaluate = [&f](const double* at, double* out) {
    if constexpr (std::is_same_v<std::invoke_result_t<F&, const double*, double*>, bool>)
      return f(at, out);
    else
      return f(at, out), true;
  };
  for (int j = 0; j < n; ++j) {
    const double xj = x[j];
    y[j] = xj + h;
    const double plus = y[j];
    if (!evaluate(y.data(), up.data())) return false;
    y[j] = xj - h;
    const double minus = y[j];
    if (!evaluate(y.data(), down.data())) return false;
    y[j] = xj;
    for (int i = 0; i < m; ++i) J[i * n + j] = (up[i] - down[i]) / (plus - minus);
  }
  return true;
}

// The gradient of a scalar function double f(const double* x), by central_difference.
template <class F>
std::vector<double> central_difference_gradient(F&& f, const double* x, int n, double h) {
  std::vector<double> g(n);
  central_difference([&f](const double* at, double* out) { *out = f(at); }, x, n, 1, h, g.data());
  return g;
}

// The Jacobian (m x n, row-major) of void f(const double* x, double* out), by central_difference.
template <class F>
std::vector<double> central_difference_jacobian(F&& f, const double* x, int n, int m, double h) {
  std::vector<double> J(static_cast<std::size_t>(m) * n);
  central_difference(f, x, n, m, h, J.data());
  return J;
}

}  // namespace dipc::test
