// `ifem poisson`: L u = M f with Dirichlet values on chosen vertices.
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>
#include <utility>

#include "cli.h"
#include "cli_refine.h"
#include "cli_solver_util.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "solvers/poisson.h"

namespace ifem::cli {
namespace {

// "vertex value" lines; '#' comments and blank lines skipped.
void read_dirichlet(const std::string& path, Index nv, std::vector<Index>& vertices,
                    std::vector<double>& values) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open");
  std::string line;
  long lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream ss(line);
    long v;
    double x;
    if (!(ss >> v)) continue;  // blank
    std::string rest;
    if (!(ss >> x) || (ss >> rest)) {
      throw IoError(path + ":" + std::to_string(lineno) + ": expected 'vertex value'");
    }
    if (v < 0 || v >= nv) {
      throw InvalidInput(path + ":" + std::to_string(lineno) + ": vertex " + std::to_string(v) +
                         " out of range [0, " + std::to_string(nv) + ")");
    }
    vertices.push_back(Index(v));
    values.push_back(x);
  }
}

int run(const Args& args) {
  if (args.positional().size() != 1) throw InvalidInput("expected one input file (see --help)");
  if (!args.has("output")) throw InvalidInput("missing -o OUT (see --help)");
  const std::string out = args.get("output");
  const std::string ext = extension_of(out);
  if (ext != ".ply" && ext != ".txt") throw InvalidInput("-o " + out + ": use .ply or .txt");
  // read the data before the (slow) preparation and refinement so bad files fail fast
  io::SurfaceInput input = read_input(args.positional()[0], args);
  const Index nv = static_cast<Index>(input.positions.rows());
  Eigen::VectorXd f = Eigen::VectorXd::Zero(nv);
  if (args.has("rhs")) {
    f = io::read_values(args.get("rhs"));
    if (f.size() != nv) {
      throw InvalidInput("--rhs " + args.get("rhs") + ": " + std::to_string(f.size()) +
                         " values, expected one per input vertex (" + std::to_string(nv) + ")");
    }
  }
  std::vector<Index> dv;
  std::vector<double> dval;
  if (args.has("dirichlet")) read_dirichlet(args.get("dirichlet"), nv, dv, dval);
  // refined: f is interpolated linearly onto the inserted vertices (signposts: their places on
  // the input faces); the Dirichlet vertices are input vertices, which keep their ids
  std::optional<solvers::RefineSettings> refine;
  if (args.has("refine")) refine = refine_settings(args, 0.0, true);
  const PreparedSurface s = prepare_surface(std::move(input), args, refine);
  solvers::PoissonOptions opt;
  opt.screening = args.get_double("screening", 0.0);
  const Stopwatch watch;
  const Eigen::VectorXd g =
      Eigen::Map<const Eigen::VectorXd>(dval.data(), Eigen::Index(dval.size()));
  const Eigen::VectorXd u = solvers::poisson(s, f, dv, g, opt);
  progress(args, "solved in " + std::to_string(watch.seconds()) + " s");
  if (ext == ".ply") {
    io::write_ply(out, s.input.positions, s.input.triangles, {{"u", u}});
  } else {
    io::write_values(out, u);
  }
  std::printf("wrote %s: %d values, %zu Dirichlet vertices%s\n", out.c_str(), nv, dv.size(),
              dv.empty() && opt.screening == 0 ? " (none: zero-mean solution per component)" : "");
  return 0;
}

}  // namespace

Command poisson_command() {
  Command c;
  c.name = "poisson";
  c.summary = "solve (L + cM) u = M f with Dirichlet values on any vertices";
  c.help = std::string(
               "usage: ifem poisson MESH [--dirichlet FILE] [--rhs FILE] [--screening c] -o OUT "
               "[--refine [refinement options]] [surface options]\n\n"
               "Solves the Poisson problem −Δu = f, i.e. L u = M f (L the intrinsic Delaunay\n"
               "cotan Laplacian, PSD; M the lumped mass), or the screened problem\n"
               "(L + cM) u = M f, with u fixed on the Dirichlet vertices and natural (zero\n"
               "Neumann) conditions everywhere else, including on the mesh boundary.\n\n"
               "  --dirichlet FILE   lines 'vertex value' (0-based input vertex id, then the\n"
               "                     value); '#' starts a comment. Example:\n"
               "                         0 1.0\n"
               "                         57 -2.5\n"
               "  --rhs FILE         f, one value per line, one line per input vertex (default 0:\n"
               "                     Laplace's equation)\n"
               "  --screening c      c ≥ 0 (default 0)\n"
               "  -o, --output OUT   OUT.ply (mesh + per-vertex property 'u') or OUT.txt (one\n"
               "                     value per line), in the input's vertex order\n\n"
               "Without Dirichlet data (and c = 0) a connected component is pure Neumann: f is\n"
               "made compatible by removing its mass-weighted mean and the zero-mean solution is\n"
               "returned. Vertices used by no face get 0 (or their Dirichlet value).\n\n"
               "  --refine           intrinsic Delaunay refinement first (options below): f is\n"
               "                     interpolated linearly onto inserted vertices, the Dirichlet\n"
               "                     vertices stay input vertices, u is reported on the input's\n"
               "                     vertices (manifold path only)\n\n"
               "example: ifem poisson disk.obj --dirichlet bc.txt -o u.ply\n\n") +
           kRefineHelp + "\n" + kSurfaceHelp;
  c.flags = kSurfaceFlags;
  c.flags.insert("refine");
  c.options = kSurfaceOptions;
  c.options.insert({"output", "dirichlet", "rhs", "screening"});
  c.options.insert(kRefineOptions.begin(), kRefineOptions.end());
  c.run = run;
  return c;
}

}  // namespace ifem::cli
