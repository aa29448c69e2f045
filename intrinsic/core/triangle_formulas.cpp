// The out-of-line formulas of triangle_formulas.h.
#include "intrinsic/core/triangle_formulas.h"

#include <algorithm>
#include <cstddef>
#include <vector>

namespace ifem::intrinsic {

double robust_mean_length(std::vector<double> lengths) {
  if (lengths.empty()) return 0.0;
  const auto p99 = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() * 99 / 100);
  std::nth_element(lengths.begin(), p99, lengths.end());
  const double cap = kOutlierClip * *p99;
  std::size_t kept = 0;
  for (const double l : lengths) kept += l <= cap ? 1 : 0;
  double mean = 0.0;  // divided as it goes: huge lengths cannot overflow the sum
  const double inv_n = 1.0 / static_cast<double>(kept);
  for (const double l : lengths) mean += l <= cap ? l * inv_n : 0.0;
  return mean;
}

}  // namespace ifem::intrinsic
