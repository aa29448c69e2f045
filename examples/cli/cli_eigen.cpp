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

int run(const Args& args) {
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
      "  Vertices used by no face get 0 in every φ.\n";
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
        flag("refine").explain(
            "intrinsic Delaunay refinement first (options below); λ and φ are of the\n"
            "refined triangulation, φ reported on the input's vertices")}},
      refine_options_group(0.0),
      surface_options()};
  c.spec.epilogue = "example: ifem eigen spot.obj -k 20 -o spot_modes.ply\n";
  c.run = run;
  return c;
}

}  // namespace ifem::cli
