// Benchmark section `vector_repeat`: repeated queries on one vector heat solver (a user's
// steady state: the solver built once, then one query after another), each against one scalar
// heat query on the same surface measured in the same rounds (interleaved): the solver-level
// transport and log map, the recipes' transport_on() and log_map_on() (3D vectors and uv), and
// the smoothest 4-direction field (a whole computation: factorization and iterations).
//
//   ifem_bench vector_repeat [--n 23 | --mesh FILE] [--repeat 7] [--what LIST] [--cpu]
//     --cpu: the process's CPU seconds instead of wall seconds (a loaded machine: with
//            OMP_NUM_THREADS=1 the work, not the waits for a core)
//     --what: comma-separated among heat, transport, transport_on, log_map (the default
//             method), log_map_affine, log_map_vector_heat, log_map_on, field
//             (default: these), solves (M + tL∇ alone, one point source and one dense
//             right-hand side, CHOLMOD's solve and our kernel's on two factors of the matrix);
//             `--what memory` builds the solver, runs one transport and one log map
//             (`--log-map blend|affine|vector-heat`, default blend) and prints the peak RSS
//             by stage (for /usr/bin/time -v); `--what parts` what a solver's
//             parts add to the resident set
#include <complex>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bench_util.h"
#include "fem/connection.h"
#include "fem/operators.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/linalg/cholesky.h"
#include "solvers/recipes/pipeline.h"
#include "solvers/recipes/tangent_fields.h"
#include "solvers/scalar/heat_distance.h"
#include "solvers/vector/direction_field.h"
#include "solvers/vector/vector_heat.h"

namespace ifem::bench {
namespace {
// `--what memory`: one solver, one transport, one log map; times and the peak RSS by stage.
int memory_by_stage(const solvers::PreparedSurface& s, const std::string& name,
                    solvers::LogMapMethod method) {
  const Index nv = s.n_input_vertices();
  const Index a = nv / 3, b = (2 * nv) / 3;
  const double peak_surface = peak_rss_mib();
  double t0 = seconds_now();
  const solvers::VectorHeatSolver vh = solvers::vector_heat_solver(s);
  const double pre = seconds_now() - t0;
  const double peak_pre = peak_rss_mib(), held_pre = rss_mib();
  t0 = seconds_now();
  solvers::transport_on(s, vh, a, Eigen::Vector3d(1.0, 0.5, 0.25));
  const double tr = seconds_now() - t0;
  const double peak_transport = peak_rss_mib();
  t0 = seconds_now();
  solvers::log_map_on(s, vh, b, method);
  const double lm = seconds_now() - t0;
  std::printf(
      "%s | %ld faces | precompute %.3f s | transport_on %.4f s | first log_map_on %.4f s "
      "| peak %.0f MiB (after the surface %.0f, the precompute %.0f, the transport %.0f; held "
      "after the precompute %.0f, at the end %.0f)\n",
      name.c_str(), long(s.tri.n_faces()), pre, tr, lm, peak_rss_mib(), peak_surface, peak_pre,
      peak_transport, held_pre, rss_mib());
  return 0;
}

// `--what memory` with `--log-map blend|affine|vector-heat` (default blend).
int memory_mode(int argc, char** argv, const solvers::PreparedSurface& s, const std::string& name) {
  const std::string lm = string_option(argc, argv, "--log-map", "blend");
  const solvers::LogMapMethod method = solvers::log_map_method_from(lm);
  return memory_by_stage(s, name + " (log map: " + lm + ")", method);
}

// `--what parts`: the resident set's growth as the parts of a vector heat solver are built.
int memory_by_part(const solvers::PreparedSurface& s) {
  double last = rss_mib();
  auto report = [&last](const char* what, double extra = 0.0) {
    const double now = rss_mib();
    std::printf("%-44s +%6.0f MiB (held %.0f)", what, now - last, now);
    if (extra > 0.0) std::printf("  nnz(L) %.3g", extra);
    std::printf("\n");
    last = now;
  };
  intrinsic::IntrinsicTriangulation tri = s.tri;
  report("triangulation copy");
  const fem::TangentFrames fr = fem::tangent_frames(tri);
  report("tangent frames");
  const double h = intrinsic::mean_edge_length(tri);
  solvers::ComplexSparseMatrix A = h * h * fem::connection_laplacian(tri, fr, 1);
  const Eigen::VectorXd mass = fem::lumped_mass(tri);
  for (Index v = 0; v < A.rows(); ++v) A.coeffRef(v, v) += mass[v] > 0.0 ? mass[v] : 1.0;
  A.makeCompressed();
  report("M + tL∇ (complex sparse)");
  solvers::CholeskyOptions o;
  o.solve_kernel = solvers::CholeskyOptions::SolveKernel::kSupernodalDouble;
  const solvers::ComplexCholeskySolver cc(A, o);
  report("complex factor (CHOLMOD + kernel pattern)", cc.factor_nonzeros());
  fem::SparseMatrix S = h * h * fem::cotan_laplacian(tri);
  for (Index v = 0; v < S.rows(); ++v) S.coeffRef(v, v) += mass[v];
  S.makeCompressed();
  report("M + tL (real sparse)");
  const solvers::CholeskySolver rc(S);
  report("real factor (simplicial solves)", rc.factor_nonzeros());
  const solvers::TangentBasis3d basis = solvers::tangent_basis_3d(s.input, tri, fr);
  report("3D tangent bases");
  std::printf("peak %.0f MiB\n", peak_rss_mib());
  return 0;
}

using Ops = std::vector<std::pair<std::string, std::function<void()>>>;

// The solver's log map, per method asked for (--what log_map, log_map_affine,
// log_map_vector_heat), from the sources next() gives.
template <class Next, class Wants>
void add_log_map_ops(const solvers::VectorHeatSolver& vh, Next& next, const Wants& wants,
                     Ops& ops) {
  using solvers::LogMapMethod;
  const std::pair<const char*, std::pair<const char*, LogMapMethod>> methods[] = {
      {"log_map", {"log map (solver, blend)", LogMapMethod::kBlend}},
      {"log_map_affine", {"log map (solver, affine)", LogMapMethod::kAffine}},
      {"log_map_vector_heat", {"log map (solver, vector heat)", LogMapMethod::kVectorHeat}}};
  for (const auto& [key, op] : methods) {
    const LogMapMethod method = op.second;
    if (wants(key)) ops.push_back({op.first, [&vh, &next, method] { vh.log_map(next(), method); }});
  }
}

// A warm-up round (the first log map builds its helpers), then `repeat` rounds of every
// operation in turn; one row per operation: median, minimum and the median's ratio to the first
// operation's (the scalar heat query, when `heat_first`).
void time_rounds(const Ops& ops, int repeat, bool cpu, bool heat_first) {
  auto now = [cpu] {
    if (!cpu) return seconds_now();
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
  };
  for (const auto& op : ops) op.second();
  std::vector<std::vector<double>> t(ops.size());
  for (int r = 0; r < repeat; ++r) {
    for (std::size_t i = 0; i < ops.size(); ++i) {
      const double t0 = now();
      ops[i].second();
      t[i].push_back(now() - t0);
    }
  }
  std::printf("## repeated queries, median of %d interleaved rounds (%s seconds)\n\n", repeat,
              cpu ? "CPU" : "wall");
  std::printf("| operation | median s | min s | / scalar heat query |\n|---|---:|---:|---:|\n");
  const double heat_median = heat_first && !t.empty() ? median(t[0]) : 0.0;
  for (std::size_t i = 0; i < ops.size(); ++i) {
    const double m = median(t[i]);
    std::printf("| %s | %.5f | %.5f | %.2f |\n", ops[i].first.c_str(), m,
                *std::min_element(t[i].begin(), t[i].end()),
                heat_median > 0.0 ? m / heat_median : 0.0);
  }
}

}  // namespace

// --what's default: every repeated query.
constexpr const char* kDefaultOps =
    "heat,transport,transport_on,log_map,log_map_affine,log_map_vector_heat,log_map_on,field";

int vector_repeat(int argc, char** argv) {
  const int repeat = int(int_option(argc, argv, "--repeat", 7));
  const int n = int(int_option(argc, argv, "--n", 23));
  const std::string mesh = string_option(argc, argv, "--mesh", "");
  const bool cpu = has_flag(argc, argv, "--cpu");
  const std::string what = "," + string_option(argc, argv, "--what", kDefaultOps) + ",";
  auto wants = [&what](const char* op) {
    return what.find("," + std::string(op) + ",") != std::string::npos;
  };
  io::SurfaceInput input;
  std::string name;
  if (mesh.empty()) {
    const auto m = intrinsic::icosphere(n);
    input.positions = m.positions;
    input.triangles = m.faces;
    name = "icosphere(" + std::to_string(n) + ")";
  } else {
    input = io::read_surface(mesh);
    name = mesh.substr(mesh.find_last_of('/') + 1);
  }
  const solvers::PreparedSurface s = solvers::prepare_surface(std::move(input));
  const Index nv = s.n_input_vertices();
  if (wants("memory")) return memory_mode(argc, argv, s, name);
  if (wants("parts")) return memory_by_part(s);
  print_load_average();
  const solvers::HeatDistanceSolver heat(s.tri, solvers::distance_options(s));
  const solvers::VectorHeatSolver vh = solvers::vector_heat_solver(s);
  const Eigen::Vector3d vec(1.0, 0.5, 0.25);
  const fem::TangentFrames frames = fem::tangent_frames(s.tri);
  Ops ops;
  Index q = 0;  // the queries' sources move through the vertices
  auto next = [&q, nv] { return (q = (q + 7919) % nv); };
  if (wants("heat")) ops.push_back({"scalar heat query", [&] { heat.compute_distance({next()}); }});
  if (wants("transport")) {
    ops.push_back({"transport (solver)", [&] {
                     vh.transport({{next(), std::complex<double>(1.0, 0.5)}});
                   }});
  }
  if (wants("transport_on")) {
    ops.push_back({"transport_on (recipe)", [&] { solvers::transport_on(s, vh, next(), vec); }});
  }
  add_log_map_ops(vh, next, wants, ops);
  if (wants("log_map_on")) {
    ops.push_back({"log_map_on (recipe)", [&] { solvers::log_map_on(s, vh, next()); }});
  }
  if (wants("field")) {
    ops.push_back({"smoothest field n = 4", [&] {
                     solvers::DirectionFieldOptions o;
                     o.symmetry = 4;
                     solvers::smoothest_field(s.tri, frames, o);
                   }});
  }
  std::optional<solvers::ComplexCholeskySolver> chol_cholmod, chol_kernel;
  Eigen::VectorXcd point, dense;
  if (wants("solves")) {
    const double h = intrinsic::mean_edge_length(s.tri);
    solvers::ComplexSparseMatrix A = h * h * fem::connection_laplacian(s.tri, frames, 1);
    const Eigen::VectorXd mass = fem::lumped_mass(s.tri);
    for (Index v = 0; v < A.rows(); ++v) A.coeffRef(v, v) += mass[v] > 0.0 ? mass[v] : 1.0;
    A.makeCompressed();
    solvers::CholeskyOptions o;
    chol_cholmod.emplace(A, o);
    o.solve_kernel = solvers::CholeskyOptions::SolveKernel::kSupernodalDouble;
    chol_kernel.emplace(A, o);
    point = Eigen::VectorXcd::Zero(A.rows());
    point[A.rows() / 3] = 1.0;
    dense = Eigen::VectorXcd::Constant(A.rows(), std::complex<double>(1.0, -0.5));
    ops.push_back({"M + tL∇ point source, CHOLMOD", [&] { chol_cholmod->solve(point); }});
    ops.push_back({"M + tL∇ point source, our kernel", [&] { chol_kernel->solve(point); }});
    ops.push_back({"M + tL∇ dense rhs, CHOLMOD", [&] { chol_cholmod->solve(dense); }});
    ops.push_back({"M + tL∇ dense rhs, our kernel", [&] { chol_kernel->solve(dense); }});
  }
  time_rounds(ops, repeat, cpu, wants("heat"));
  std::printf("\npeak RSS %.0f MiB (%s, %ld faces)\n", peak_rss_mib(), name.c_str(),
              long(s.tri.n_faces()));
  return 0;
}

}  // namespace ifem::bench
