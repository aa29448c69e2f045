#include "support/dense_spectrum.h"

#include <Eigen/Eigenvalues>

namespace ifem::test {

Eigen::VectorXd self_adjoint_eigenvalues(const Eigen::MatrixXd& A) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A, Eigen::EigenvaluesOnly).eigenvalues();
}

Eigen::VectorXd self_adjoint_eigenvalues(const Eigen::MatrixXcd& A) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd>(A, Eigen::EigenvaluesOnly).eigenvalues();
}

}  // namespace ifem::test
