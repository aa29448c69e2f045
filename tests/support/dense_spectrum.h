// Dense eigenvalues for the test suites' reference spectra. Eigen's SelfAdjointEigenSolver is
// the costliest template the tests instantiate, so it is compiled once, here, in the library
// ifem_test_support that every GoogleTest executable links (tests/CMakeLists.txt;
// docs/decisions.md D-185). Test files call these instead of instantiating the solver.
#pragma once

#include <Eigen/Core>

namespace ifem::test {

/// Eigenvalues of the symmetric matrix A (n × n, n ≥ 0; only its lower triangle is read),
/// ascending. Eigen's SelfAdjointEigenSolver (tridiagonalization + implicit QL), eigenvalues only.
Eigen::VectorXd self_adjoint_eigenvalues(const Eigen::MatrixXd& A);

/// Eigenvalues of the Hermitian matrix A (n × n, n ≥ 0; only its lower triangle is read), real
/// and ascending. The same solver as the real overload.
Eigen::VectorXd self_adjoint_eigenvalues(const Eigen::MatrixXcd& A);

}  // namespace ifem::test
