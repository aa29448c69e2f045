// `ifem eigen`: the smallest Laplace–Beltrami eigenpairs L φ = λ M φ.
#include <cstdio>
#include <optional>

#include "cli.h"
#include "cli_refine.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "results.h"
#include "solvers/scalar/eigen.h"

namespace ifem::cli {
namespace {

int run_eigen(const Args& args) {
  const ResultOutput out = result_output(args);  // checked before any computation
  const Index k = args.count("k");               // ≥ 1 (table), < #V (prepare_surface)
  // refined: input vertices keep ids 0..#V_in-1, so the eigenvectors restricted to them are the
  // values on the input's vertices (inserted vertices only enrich the discretization)
  std::optional<solvers::SurfaceRefineOptions> refine;
  if (args.has("refine")) refine = refine_settings(args, 0.0, false);
  const PreparedSurface s = prepare_surface(args.positional()[0], args, refine);
  const Stopwatch watch;
  solvers::EigenOptions eo;
  eo.on_progress = progress_bar(args);
  if (args.has("coarse")) eo.coarse = args.count("coarse");
  if (args.has("coarse-iterations")) {
    if (!args.has("coarse")) throw UsageError("--coarse-iterations needs --coarse N");
    eo.coarse_iterations = args.count("coarse-iterations");
  }
  const solvers::EigenPairs ep = solvers::eigenmodes(s, k, eo);  // vectors on the input's vertices
  progress(args, "eigenpairs in " + std::to_string(watch.seconds()) + " s");
  std::vector<io::VertexProperty> props;
  for (Index j = 0; j < k; ++j) props.push_back({"phi" + std::to_string(j), ep.vectors.col(j)});
  write_results(out, s, props);
  const std::string values_path = out.path.substr(0, out.path.size() - 4) + ".eigenvalues.txt";
  io::write_values(values_path, ep.values);
  std::printf("wrote %s (phi0..phi%d) and %s\neigenvalues:", out.path.c_str(), k - 1,
              values_path.c_str());
  for (Index j = 0; j < k; ++j) std::printf(" %.10g", ep.values[j]);
  std::printf("\n");
  if (ep.coarse_vertices > 0) {
    std::printf(
        "approximation (spectral coarsening to %d vertices, %d block iterations)\n"
        "relative residuals ||L phi - lambda M phi|| / ||lambda M phi||:",
        ep.coarse_vertices, eo.coarse_iterations);
    for (Index j = 0; j < k; ++j) std::printf(" %.3g", ep.residuals[j]);
    std::printf("\n");
  }
  return 0;
}

}  // namespace

Command eigen_command() {
  Command c;
  c.summary = "smallest Laplace–Beltrami eigenpairs (L φ = λ M φ) as PLY properties";
  c.spec.name = "eigen";
  c.spec.positionals = {"MESH"};
  c.spec.prose =
      "Computes the K smallest eigenvalues λ and eigenvectors φ of L φ = λ M φ (L the\n"
      "intrinsic Delaunay cotan Laplacian, PSD; M the lumped mass) by shift-invert\n"
      "Lanczos with a sparse Cholesky factor.\n"
      "  λ ascending, ≥ 0; λ = 0 once per connected component (constant φ).\n"
      "  φ M-orthonormal: Σ_i M_ii φ_a(i) φ_b(i) = δ_ab (sign arbitrary).\n"
      "  Vertices used by no face get 0 in every φ.\n\n"
      "With --coarse N (spectral coarsening): MESH is simplified to N vertices (as\n"
      "`ifem simplify`), the coarse problem's 2(K + 6) smallest pairs are prolonged to\n"
      "the input as a subspace, and Rayleigh–Ritz with the fine L, M gives the pairs:\n"
      "an approximation without a factor of the fine matrices, each λ above the exact\n"
      "one, printed with its relative residual ||Lφ − λMφ|| / ||λMφ||.\n"
      "--coarse-iterations R then refines the subspace by R block iterations\n"
      "X ← (L − σM)⁻¹ M X (one fine Cholesky factor), which converge to the exact pairs.\n";
  c.spec.groups = {
      {"Options",
       {count("k", "K")
            .short_alias('k')
            .at_least(1)
            .defaults_to("10")
            .limited_by(InputLimit::kBelowVertexCount)
            .explain("number of eigenpairs (< the number of input vertices)"),
        text("output", "OUT.ply")
            .short_alias('o')
            .mandatory()
            .with_extensions({".ply"})
            .explain("the input mesh with per-vertex properties phi0..phiK-1, in the\n"
                     "input's vertex order; the eigenvalues go to OUT.eigenvalues.txt\n"
                     "(one per line) and to stdout"),
        count("coarse", "N")
            .at_least(1)
            .limited_by(InputLimit::kBelowVertexCount)
            .explain("spectral coarsening: approximate pairs from a simplification to N\n"
                     "vertices (K + 6 < N < the number of vertices)"),
        count("coarse-iterations", "R")
            .at_least(0)
            .explain("with --coarse: R block iterations with the fine factor (0: none)"),
        flag("refine").explain(
            "intrinsic Delaunay refinement first (options below); λ and φ are of the\n"
            "refined triangulation, φ reported on the input's vertices")}},
      refine_options_group(0.0),
      surface_options()};
  c.spec.epilogue =
      "example: ifem eigen spot.obj -k 20 -o spot_modes.ply\n"
      "         ifem eigen igea_268k.ply -k 16 --coarse 2000 -o igea_modes.ply\n";
  c.run = run_eigen;
  return c;
}

}  // namespace ifem::cli
