#include "fem/prolongation.h"

#include <string>
#include <vector>

namespace ifem::fem {

SparseMatrix prolongation(const intrinsic::Simplification& s) {
  const Index n_fine = Index(s.fine_in_coarse.size());
  const Index n_coarse = s.coarse.n_vertices();
  std::vector<Index> fine_to_coarse(n_fine, kInvalidIndex);
  for (Index c = 0; c < Index(s.coarse_to_fine.size()); ++c) {
    const Index v = s.coarse_to_fine[c];
    if (v < 0 || v >= n_fine) {
      throw InvalidInput("prolongation: coarse_to_fine[" + std::to_string(c) +
                         "] = " + std::to_string(v) + " is not a fine vertex");
    }
    fine_to_coarse[v] = c;
  }
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(3 * std::size_t(n_fine));
  for (Index i = 0; i < n_fine; ++i) {
    const intrinsic::SurfacePoint& p = s.fine_in_coarse[i];
    if (p.face == kInvalidIndex) {
      if (fine_to_coarse[i] == kInvalidIndex) {
        throw InvalidInput("prolongation: fine vertex " + std::to_string(i) +
                           " has neither a coarse face nor a coarse copy");
      }
      entries.emplace_back(i, fine_to_coarse[i], 1.0);
      continue;
    }
    if (p.face < 0 || p.face >= s.coarse.n_faces()) {
      throw InvalidInput("prolongation: fine vertex " + std::to_string(i) + " names face " +
                         std::to_string(p.face) + " of a coarse mesh with " +
                         std::to_string(s.coarse.n_faces()) + " faces");
    }
    for (int k = 0; k < 3; ++k) {
      if (p.bary[k] != 0.0) entries.emplace_back(i, s.coarse.tail(3 * p.face + k), p.bary[k]);
    }
  }
  SparseMatrix P(n_fine, n_coarse);
  P.setFromTriplets(entries.begin(), entries.end());  // repeated corners (Δ-complex) add up
  return P;
}

}  // namespace ifem::fem
