#include "cli.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <utility>

#include "intrinsic/core/errors.h"
#include "intrinsic/surface/build_surface.h"
#ifdef IFEM_HAVE_PCL
#include "pointcloud/pcl_adapter.h"
#endif

namespace ifem::cli {

namespace {
std::string format_default(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}
}  // namespace

OptionGroup surface_options() {
  return {"Surface options (any command that reads a mesh or point cloud)",
          {real("mollify", "F")
               .at_least(0)
               .at_most(1)
               .defaults_to(format_default(intrinsic::kDefaultMollifyEpsilon))
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
           flag("quiet").explain("no progress lines on stderr")}};
}

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void progress(const Args& args, const std::string& line) {
  if (!args.has("quiet")) std::fprintf(stderr, "ifem: %s\n", line.c_str());
}

// .pcd goes through the optional PCL adapter; everything else through io::read_surface.
static io::SurfaceInput read_input(const std::string& file) {
  if (io::file_extension(file) != ".pcd") return io::read_surface(file);
#ifdef IFEM_HAVE_PCL
  pointcloud::PclPoints pts = pointcloud::read_pcd(file);
  io::SurfaceInput in;
  in.positions = std::move(pts.positions);
  if (pts.has_normals()) in.normals = std::move(pts.normals);
  in.format = "pcd";
  if (pts.dropped_non_finite > 0) {
    std::fprintf(stderr, "ifem: %s: dropped %d points with non-finite coordinates\n", file.c_str(),
                 pts.dropped_non_finite);
  }
  return in;
#else
  throw IoError(file +
                ": this ifem was built without PCL: .pcd needs the PCL adapter "
                "(install libpcl-dev and reconfigure with -DIFEM_WITH_PCL=ON)");
#endif
}

PreparedSurface prepare_surface(const std::string& file, const Args& args) {
  PreparedSurface s;
  double t0 = now_seconds();
  s.input = read_input(file);
  s.seconds_load = now_seconds() - t0;
  const Index nv = static_cast<Index>(s.input.positions.rows());
  progress(args, "read " + file + ": " + std::to_string(nv) + " vertices, " +
                     std::to_string(s.input.n_polygons) + " faces (" + s.input.format + ")");
  check_input_limits(args, nv, !s.input.has_faces() || args.has("pointcloud"));
  s.stats = intrinsic::analyze_faces(s.input.triangles, nv);
  const double eps = args.real("mollify");
  t0 = now_seconds();

  // ---- point cloud: no faces, or --pointcloud
  if (!s.input.has_faces() || args.has("pointcloud")) {
    pointcloud::Options opt;
    opt.k = args.count("knn");
    opt.mollify_relative_epsilon = eps;
    opt.intrinsic_delaunay = !args.has("no-delaunay");
    const bool with_normals = s.input.normals.rows() == nv && nv > 0;
    s.tri = pointcloud::pointcloud_triangulation(
        s.input.positions, opt, with_normals ? &s.input.normals : nullptr, &s.cloud);
    s.path = "pointcloud";
    s.path_reason = std::string(s.input.has_faces() ? "--pointcloud" : "no faces") +
                    ": point cloud, k = " + std::to_string(s.cloud.k) +
                    (s.cloud.normals_from_input ? ", file normals" : ", PCA normals");
    s.mollify = s.cloud.mollify;
    s.flips = s.cloud.flips;
    s.build.input_faces = 0;
    s.build.unreferenced_vertices = s.cloud.isolated_points;
    s.seconds_build = s.cloud.seconds_knn + s.cloud.seconds_local + s.cloud.seconds_cover;
    s.seconds_flip = s.cloud.seconds_idt;
    std::ostringstream m;
    m << "point cloud: " << nv << " points, k = " << s.cloud.k << ", " << s.cloud.local_triangles
      << " local triangles, " << s.cloud.isolated_points << " isolated points; kNN "
      << s.cloud.seconds_knn << " s, local Delaunay " << s.cloud.seconds_local
      << " s, tufted cover " << s.cloud.seconds_cover << " s, intrinsic Delaunay "
      << s.cloud.seconds_idt << " s (" << s.flips.flips << " flips)";
    progress(args, m.str());
    return s;
  }

  // ---- mesh: manifold path when it represents the input with non-negative weights,
  //      tufted cover otherwise (the choice lives in the library: build_surface)
  intrinsic::SurfaceOptions opt;
  opt.mollify_relative_epsilon = eps;
  opt.intrinsic_delaunay = !args.has("no-delaunay");
  opt.force_tufted = args.has("tufted");
  intrinsic::SurfaceTriangulation st =
      intrinsic::build_surface(s.input.triangles, s.input.positions, opt);
  s.tri = std::move(st.tri);
  s.path = st.path_name();
  s.path_reason = opt.force_tufted ? "--tufted" : st.reason;
  s.build = std::move(st.build);
  s.tufted = std::move(st.tufted);
  s.mollify = st.mollify;
  s.flips = st.flips;
  s.boundary_vertex = std::move(st.boundary_vertex);
  s.seconds_build = st.seconds_build;
  s.seconds_flip = st.seconds_flip;
  progress(args, "path: " + s.path + " (" + s.path_reason + ")");
  if (s.build.dropped_faces) {
    progress(args,
             "dropped " + std::to_string(s.build.dropped_faces) + " faces that repeat a vertex");
  }
  if (s.build.reoriented_faces) {
    progress(args, "reoriented " + std::to_string(s.build.reoriented_faces) +
                       " faces for a consistent orientation");
  }
  if (s.mollify.delta > 0) {
    std::ostringstream m;
    m << "mollified " << s.mollify.faces_below_margin << " faces: every edge length + "
      << s.mollify.delta;
    progress(args, m.str());
  }
  if (opt.intrinsic_delaunay) {
    progress(args, "intrinsic Delaunay: " + std::to_string(s.flips.flips) + " flips");
  }
  return s;
}

}  // namespace ifem::cli
