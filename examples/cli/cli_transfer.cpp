// `ifem transfer`: per-vertex values carried from the input mesh onto its refined intrinsic
// triangulation, or back (fem::transfer: pointwise or L2).
#include <cmath>
#include <cstdio>
#include <string>

#include "cli.h"
#include "cli_refine.h"
#include "fem/attribute_transfer.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "solvers/recipes/recipes.h"

namespace ifem::cli {
namespace {

double integral(const intrinsic::IntrinsicTriangulation& t, const Eigen::VectorXd& u) {
  return fem::lumped_mass(t).dot(u);
}

int run_transfer(const Args& args) {
  fem::TransferMethod method;
  try {
    method = fem::parse_transfer_method(args.get("method"));
  } catch (const InvalidInput& e) {
    throw UsageError(std::string("--method: ") + e.what());
  }
  const bool back = args.has("back");
  const Eigen::VectorXd values = io::read_values(args.get("values"));  // fails before the mesh
  const PreparedSurface s =
      prepare_surface(args.positional()[0], args, refine_settings(args, 0.0, true));
  const intrinsic::CorrespondenceView view = *s.correspondence();  // refined: always set
  const Index n_in = view.n_input_vertices(), nv = view.intrinsic().n_vertices();
  if (values.size() != (back ? nv : n_in)) {
    throw InvalidInput(
        "--values " + args.get("values") + ": " + std::to_string(values.size()) +
        " values, expected one per " +
        (back ? "vertex of the refined triangulation (" + std::to_string(nv) +
                    " with these refinement options; the file `ifem transfer` wrote without "
                    "--back, with the same options)"
              : "input vertex (" + std::to_string(n_in) + ")"));
  }
  const Stopwatch watch;
  const Eigen::VectorXd out = recipes::transfer(s, values, method, back);
  progress(args, std::string(fem::to_string(method)) + " transfer in " +
                     std::to_string(watch.seconds()) + " s");
  io::write_values(args.get("output"), out);
  const double before = integral(back ? view.intrinsic() : view.input(), values);
  const double after = integral(back ? view.input() : view.intrinsic(), out);
  std::printf("wrote %s: %d values on the %s (%s transfer); integral %.12g -> %.12g\n",
              args.get("output").c_str(), int(out.size()),
              back ? "input vertices" : "refined triangulation's vertices, input vertices first",
              fem::to_string(method), before, after);
  return 0;
}

const char* const kTransferProse =
    "Carries a function given by one value per vertex (linear on each triangle) from\n"
    "MESH onto its intrinsic Delaunay refinement (refinement options below; the same\n"
    "options always give the same refinement), or with --back from the refinement\n"
    "back onto MESH's vertices.\n\n"
    "  pointwise  each target vertex takes the function's value at its place: inserted\n"
    "             vertices interpolate the input triangle they lie on; back, the input\n"
    "             vertices (which are vertices of the refinement) keep their values.\n"
    "  l2         Galerkin projection: the target u minimises the integral of (u - f)²,\n"
    "             solving M u = M_mixed f with the target's mass matrix M and the mixed\n"
    "             mass matrix integrated over the common subdivision (the overlay of both\n"
    "             triangulations). Keeps the integral of f and is exact for\n"
    "             functions linear on both (a linear function on a flat mesh).\n\n"
    "Values out: without --back, one per vertex of the refinement, the first #V_in\n"
    "being the input's vertices in the input's order, then the inserted ones (as\n"
    "`ifem refine --mesh` numbers them); with --back, one per input vertex. The summary\n"
    "line gives the integral of the function before and after (lumped mass).\n";

}  // namespace

Command transfer_command() {
  Command c;
  c.summary = "carry per-vertex values onto the refined triangulation or back (pointwise, L2)";
  c.spec.name = "transfer";
  c.spec.positionals = {"MESH"};
  c.spec.prose = kTransferProse;
  c.spec.groups = {
      {"Options",
       {text("values", "FILE")
            .mandatory()
            .explain("the function, one value per line: per input vertex, or with --back\n"
                     "per vertex of the refinement (a file this command wrote)"),
        text("method", "METHOD")
            .defaults_to("l2")
            .explain("'pointwise' (interpolate) or 'l2' (Galerkin projection, keeps the\n"
                     "integral)"),
        flag("back").explain("from the refinement's vertices back to the input's"),
        text("output", "OUT.txt")
            .short_alias('o')
            .mandatory()
            .with_extensions({".txt"})
            .explain("the transferred values, one per line")}},
      refine_options_group(0.0),
      surface_options()};
  c.spec.epilogue =
      "\nexamples: ifem transfer bunny.obj --values f.txt --method l2 -o on_refined.txt\n"
      "          ifem transfer bunny.obj --values on_refined.txt --back -o f_again.txt\n"
      "          ifem transfer bunny.obj --values f.txt --correspondence integer "
      "--min-angle 30 -o g.txt\n";
  c.run = run_transfer;
  return c;
}

}  // namespace ifem::cli
