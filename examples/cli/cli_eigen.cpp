// `ifem eigen`: the smallest Laplace–Beltrami eigenpairs L φ = λ M φ.
#include <cstdio>
#include <optional>

#include "cli.h"
#include "cli_refine.h"
#include "cli_solver_util.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "solvers/eigen.h"

namespace ifem::cli {
namespace {

int run(const Args& args) {
  if (args.positional().size() != 1) throw InvalidInput("expected one input file (see --help)");
  if (!args.has("output")) throw InvalidInput("missing -o OUT.ply (see --help)");
  const std::string out = args.get("output");
  if (extension_of(out) != ".ply") throw InvalidInput("-o " + out + ": the output must be .ply");
  const long k = args.get_int("k", 10);
  if (k < 1) throw InvalidInput("-k must be ≥ 1");
  // refined: input vertices keep ids 0..#V_in-1, so the eigenvectors restricted to them are the
  // values on the input's vertices (inserted vertices only enrich the discretization)
  std::optional<solvers::RefineSettings> refine;
  if (args.has("refine")) refine = refine_settings(args, 0.0, false);
  const PreparedSurface s = prepare_surface(args.positional()[0], args, refine);
  const Stopwatch watch;
  const solvers::EigenPairs ep = solvers::eigenmodes(s, Index(k));
  progress(args, "eigenpairs in " + std::to_string(watch.seconds()) + " s");
  std::vector<io::VertexProperty> props;
  for (long j = 0; j < k; ++j) props.push_back({"phi" + std::to_string(j), ep.vectors.col(j)});
  io::write_ply(out, s.input.positions, s.input.triangles, props);
  const std::string values_path = out.substr(0, out.size() - 4) + ".eigenvalues.txt";
  io::write_values(values_path, ep.values);
  std::printf("wrote %s (phi0..phi%ld) and %s\neigenvalues:", out.c_str(), k - 1,
              values_path.c_str());
  for (long j = 0; j < k; ++j) std::printf(" %.10g", ep.values[j]);
  std::printf("\n");
  return 0;
}

}  // namespace

Command eigen_command() {
  Command c;
  c.name = "eigen";
  c.summary = "smallest Laplace–Beltrami eigenpairs (L φ = λ M φ) as PLY properties";
  c.help = std::string(
               "usage: ifem eigen MESH -k K -o OUT.ply [--refine [refinement options]] "
               "[surface options]\n\n"
               "Computes the K smallest eigenvalues λ and eigenvectors φ of L φ = λ M φ (L the\n"
               "intrinsic Delaunay cotan Laplacian, PSD; M the lumped mass) by shift-invert\n"
               "Lanczos with a sparse Cholesky factor.\n"
               "  λ ascending, ≥ 0; λ = 0 once per connected component (constant φ).\n"
               "  φ M-orthonormal: Σ_i M_ii φ_a(i) φ_b(i) = δ_ab (sign arbitrary).\n"
               "  Vertices used by no face get 0 in every φ.\n\n"
               "  -k K                 number of eigenpairs (default 10)\n"
               "  -o, --output OUT.ply the input mesh with per-vertex properties phi0..phiK-1,\n"
               "                       in the input's vertex order; the eigenvalues go to\n"
               "                       OUT.eigenvalues.txt (one per line) and to stdout\n\n"
               "  --refine             intrinsic Delaunay refinement first (options below); λ and\n"
               "                       φ are of the refined triangulation, φ reported on the\n"
               "                       input's vertices (manifold path only)\n\n"
               "example: ifem eigen spot.obj -k 20 -o spot_modes.ply\n\n") +
           kRefineHelp + "\n" + kSurfaceHelp;
  c.flags = kSurfaceFlags;
  c.flags.insert("refine");
  c.options = kSurfaceOptions;
  c.options.insert({"output", "k"});
  c.options.insert(kRefineOptions.begin(), kRefineOptions.end());
  c.run = run;
  return c;
}

}  // namespace ifem::cli
