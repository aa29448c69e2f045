#include "cli.h"

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <utility>

#include "intrinsic/core/errors.h"
#include "progress_bar.h"
#ifdef IFEM_HAVE_PCL
#include "pointcloud/pcl_adapter.h"
#endif

namespace ifem::cli {

OptionGroup surface_options() {
  return {"Surface options (any command that reads a mesh or point cloud)",
          {real("mollify", "F")
               .at_least(0)
               .at_most(1)
               .defaults_to(format_number(intrinsic::kDefaultMollifyEpsilon))
               .explain("relative mollification margin: the smallest uniform length δ is added\n"
                        "to every edge so each triangle satisfies a+b−c ≥ F·(mean edge length)\n"
                        "(0 repairs only strict violations)"),
           flag("no-delaunay").explain("keep the input triangulation (no intrinsic edge flips)"),
           flag("tufted").explain("force the tufted cover even on an edge-manifold mesh"),
           flag("pointcloud").explain("treat the input as a point cloud even if it has faces"),
           count("knn", "K")
               .at_least(2)
               .defaults_to("30")
               .limited_by(InputLimit::kBelowPointCount)
               .explain("neighbours per point for point clouds (< the number of points)"),
           flag("quiet").explain(
               "no progress lines and no progress bar on stderr (the bar is drawn\nonly when "
               "stderr is a terminal, once the command has run 2 s)")}};
}

void progress(const Args& args, const std::string& line) {
  if (args.has("quiet")) return;
  clear_progress_bar();
  std::fprintf(stderr, "ifem: %s\n", line.c_str());
}

solvers::PrepareOptions prepare_options(const Args& args) {
  solvers::PrepareOptions opt;
  opt.mollify_relative_epsilon = args.real("mollify");
  opt.intrinsic_delaunay = !args.has("no-delaunay");
  opt.force_tufted = args.has("tufted");
  opt.force_pointcloud = args.has("pointcloud");
  opt.knn = args.count("knn");
  if (!args.has("quiet")) {
    opt.progress = [](const std::string& line) {
      clear_progress_bar();
      std::fprintf(stderr, "ifem: %s\n", line.c_str());
    };
  }
  opt.on_progress = progress_bar(args);
  return opt;
}

// .pcd goes through the optional PCL adapter; everything else through io::read_surface.
static io::SurfaceInput read_file(const std::string& file, const Args& args) {
  if (io::file_extension(file) != ".pcd") return io::read_surface(file, progress_bar(args));
#ifdef IFEM_HAVE_PCL
  pointcloud::PclPoints pts = pointcloud::read_pcd(file);
  io::SurfaceInput in;
  in.positions = std::move(pts.positions);
  if (pts.has_normals()) in.normals = std::move(pts.normals);
  in.format = "pcd";
  if (pts.dropped_non_finite > 0) {
    progress(args, file + ": dropped " + std::to_string(pts.dropped_non_finite) +
                       " points with non-finite coordinates");
  }
  return in;
#else
  (void)args;
  throw IoError(file +
                ": this ifem was built without PCL: .pcd needs the PCL adapter "
                "(install libpcl-dev and reconfigure with -DIFEM_WITH_PCL=ON)");
#endif
}

io::SurfaceInput read_input(const std::string& file, const Args& args) {
  io::SurfaceInput in = read_file(file, args);
  const Index nv = static_cast<Index>(in.positions.rows());
  progress(args, "read " + file + ": " + std::to_string(nv) + " vertices, " +
                     std::to_string(in.n_polygons) + " faces (" + in.format + ")");
  check_input_limits(args, nv, !in.has_faces() || args.has("pointcloud"));
  return in;
}

PreparedSurface prepare_surface(io::SurfaceInput input, const Args& args,
                                const std::optional<solvers::SurfaceRefineOptions>& refine) {
  solvers::PrepareOptions opt = prepare_options(args);
  opt.refine = refine;
  return solvers::prepare_surface(std::move(input), opt);
}

PreparedSurface prepare_surface(const std::string& file, const Args& args,
                                const std::optional<solvers::SurfaceRefineOptions>& refine) {
  return prepare_surface(read_input(file, args), args, refine);
}

}  // namespace ifem::cli
