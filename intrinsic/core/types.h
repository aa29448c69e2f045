// Index type and small shared aliases.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ifem {

/// 32-bit ids everywhere: they match Eigen's sparse StorageIndex and halve memory traffic.
using Index = std::int32_t;
inline constexpr Index kInvalidIndex = -1;

/// Loops over fewer elements than this run on one thread: waking a second one costs more than
/// it saves (and much more when the other core is busy).
inline constexpr Index kParallelMin = 50000;

/// One triangle as three vertex ids, counter-clockwise as seen from the front.
using Triangle = std::array<Index, 3>;

/// Vertex positions, one row per vertex.
using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Whether element i is flagged in a per-element flag vector (edges that are constrained, fixed,
/// ...): false when `flags` is null or shorter than i + 1 (missing entries count as 0).
inline bool is_flagged(const std::vector<char>* flags, Index i) {
  return flags != nullptr && i >= 0 && i < static_cast<Index>(flags->size()) && (*flags)[i] != 0;
}

/// Converts a size to Index, throwing InvalidInput when it does not fit in 31 bits.
Index checked_index(std::size_t n, const char* what);

}  // namespace ifem
