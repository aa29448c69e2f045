// Intrinsic Delaunay refinement for the `ifem` commands: `ifem refine`, and `--refine` in the
// solver commands (distance, eigen, poisson), which call refine_prepared() on their surface.
#pragma once

#include <optional>
#include <string>

#include "cli.h"
#include "intrinsic/refine/delaunay_refine.h"
#include "intrinsic/refine/signpost.h"

namespace ifem::cli {

/// The options refinement understands, appended to refine and to the solver commands:
/// --min-angle, --resolution (shown with default `resolution_default`: refine_target_length()'s
/// default_resolution at that command), --max-area, --max-insertions, --relax, --max-edge.
OptionGroup refine_options_group(double resolution_default);

/// The error message for a surface refinement does not support: point clouds, and, when
/// signposts are needed, anything but the manifold path.
std::string refine_unsupported(const PreparedSurface& s, bool need_signposts);

/// The target edge length asked for by --resolution C (default `default_resolution`): C × the
/// input's mean edge length; 0 when C = 0 (no size bound).
double refine_target_length(const PreparedSurface& s, const Args& args, double default_resolution);

/// Reads --min-angle (default 25), --max-area (default none; with target_length > 0 at most the
/// area of the equilateral triangle of that side), --max-insertions (default: the library's,
/// RefineOptions::max_insertions).
intrinsic::RefineOptions refine_options(const Args& args, double target_length);

/// Refines a prepared surface in place. Edge-manifold orientable inputs (the manifold path, or
/// the tufted path taken only for negative boundary weights): rebuilds the intrinsic
/// triangulation with signposts from the input (same faces, same mollification), refines it,
/// relaxes the inserted vertices (--relax ITER passes, default 0), stores the result in s.tri
/// and returns the signpost triangulation. Nonmanifold / non-orientable / --tufted inputs (the
/// tufted path), unless need_signposts: refines the tufted cover s.tri itself, without
/// signposts, and returns nothing. Either way input vertices keep their ids 0..n_input-1 and
/// inserted vertices follow, so a result vector x on s.tri is on the input vertices as
/// x.head(n_input); use SignpostTriangulation::input_to_intrinsic() for data given on the
/// input vertices. `default_resolution` is --resolution's default (refine_target_length()).
/// Prints a progress line unless --quiet.
/// @throws InvalidInput on point clouds, and on the tufted path when need_signposts or --relax
std::optional<intrinsic::SignpostTriangulation> refine_prepared(
    PreparedSurface& s, const Args& args, double default_resolution = 0.0,
    bool need_signposts = false, intrinsic::RefineReport* report = nullptr,
    intrinsic::RelaxReport* relax_report = nullptr);

}  // namespace ifem::cli
