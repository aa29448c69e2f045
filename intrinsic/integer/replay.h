// Integer coordinates for a triangulation changed through signposts: the operations a
// SignpostTriangulation logged (flips, insertions, splits: SignpostTriangulation::operation_log)
// replayed in order on a NormalCoordinateTriangulation over the same input. Used where an
// algorithm runs on signposts only (FlipOut for curves) but the result is wanted with integer
// coordinates. docs/decisions.md D-260.
#pragma once

#include <string>

#include "intrinsic/core/triangulation.h"
#include "intrinsic/integer/normal_coordinates.h"
#include "intrinsic/refine/signpost.h"

namespace ifem::intrinsic {

/// Builds a NormalCoordinateTriangulation from st's input (its faces as given, positions and
/// mollification) and replays st.operation_log() on it, oldest first. The log must have been
/// started on the freshly built st (before any change). O(log length) integer updates, plus
/// the tracing each insertion and split costs.
/// @returns integer coordinates whose intrinsic() equals st.intrinsic()
/// @throws InvalidInput when the replay does not give st.intrinsic() (require_same_gluing)
NormalCoordinateTriangulation replay_on_integer(const SignpostTriangulation& st);

/// Checks that two intrinsic triangulations are the same: counts, every halfedge's tail, twin
/// and edge id, every length bit for bit.
/// @throws InvalidInput naming `what` and the first difference
void require_same_gluing(const IntrinsicTriangulation& a, const IntrinsicTriangulation& b,
                         const std::string& what);

}  // namespace ifem::intrinsic
