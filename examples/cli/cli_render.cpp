// `ifem render`: a mesh, one per-vertex field and curves as a PNG, without a display
// (solvers/recipes/render.h).
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include "cli.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/timer.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/io/tokens.h"
#include "solvers/recipes/recipes.h"
#include "solvers/recipes/view_scene.h"

namespace ifem::cli {
namespace {

/// "800x600" → {800, 600}. @throws UsageError on anything else
std::array<int, 2> parse_size(const std::string& text) {
  const std::size_t x = text.find_first_of("xX");
  long long w = 0, h = 0;
  if (x == std::string::npos || !io::parse_whole_integer(text.substr(0, x), w) ||
      !io::parse_whole_integer(text.substr(x + 1), h) || w < 1 || h < 1 || w > 16384 || h > 16384) {
    throw UsageError("--size: expected WIDTHxHEIGHT with each side in [1, 16384], got " +
                     io::quoted_excerpt(text));
  }
  return {static_cast<int>(w), static_cast<int>(h)};
}

solvers::RenderOptions render_options(const Args& args) {
  solvers::RenderOptions o;
  try {
    const auto [w, h] = parse_size(args.get("size"));
    o.width = w;
    o.height = h;
    const auto [az, el] = solvers::named_view(args.get("view"));
    o.azimuth_deg = args.real_or("azimuth", az);
    o.elevation_deg = args.real_or("elevation", el);
    o.colormap = solvers::colormap_from_name(args.get("colormap"));
    if (args.has("min")) o.range_lo = args.real("min");
    if (args.has("max")) o.range_hi = args.real("max");
    o.isolines = args.count("isolines");
    o.wireframe = args.has("wireframe");
    o.supersample = args.count("supersample");
    o.fill = args.real("fill");
    o.curve_width = args.real("curve-width");
    o.legend = args.has("legend");
    o.validate();
  } catch (const InvalidInput& e) {
    throw UsageError(e.what());
  }
  return o;
}

std::string render_stem(const std::string& path) {
  return std::filesystem::path(path).stem().string();
}

/// What `ifem view` would show for the same inputs (recipes::Scene), MESH's own properties or
/// --field's, the curves and the traced intrinsic edges.
recipes::Scene read_scene(const Args& args) {
  const std::string mesh = args.positional()[0];
  io::SurfaceInput input = io::read_surface(mesh);
  std::vector<io::VertexProperty> properties = std::move(input.vertex_properties);
  input.vertex_properties.clear();
  if (args.has("field")) {
    io::SurfaceInput values = io::read_surface(args.get("field"));
    if (values.positions.rows() != input.positions.rows()) {
      throw InvalidInput("--field " + args.get("field") + " has " +
                         std::to_string(values.positions.rows()) + " vertices, " + mesh + " has " +
                         std::to_string(input.positions.rows()));
    }
    properties = std::move(values.vertex_properties);
  }
  recipes::Scene scene = recipes::view_scene(input, render_stem(mesh));
  recipes::add_properties(scene, properties, "", static_cast<int>(args.count("symmetry")));
  if (args.has("curves")) {
    const std::string file = args.get("curves");
    recipes::add_polylines(scene, render_stem(file), solvers::read_polylines(file));
  }
  add_triangulation(scene, args);
  return scene;
}

int run_render(const Args& args) {
  const solvers::RenderOptions options = render_options(args);  // checked before any reading
  const solvers::RenderScene scene =
      recipes::render_scene_of(read_scene(args), args.has("property") ? args.get("property") : "");
  const Stopwatch watch;
  const solvers::Rendering r = recipes::render(scene, options);
  const std::string out = args.get("output");
  solvers::write_png(out, r.image);
  progress(args, "rendered in " + std::to_string(watch.seconds()) + " s");
  std::printf("wrote %s (%dx%d)", out.c_str(), r.image.width, r.image.height);
  if (!scene.field_name.empty()) {
    std::printf(", colour: %s in [%.6g, %.6g]", scene.field_name.c_str(), r.range_lo, r.range_hi);
  }
  std::printf("\n");
  return 0;
}

OptionGroup render_options_group() {
  return {"Options",
          {text("output", "OUT.png")
               .short_alias('o')
               .mandatory()
               .with_extensions({".png"})
               .explain("the picture"),
           text("property", "NAME")
               .explain("the per-vertex property to colour by (default: the first one; none:\n"
                        "a grey surface)"),
           text("field", "VALUES.ply")
               .with_extensions({".ply"})
               .explain("take the properties from this PLY instead of MESH (same vertex count,\n"
                        "e.g. ifem render spot.obj --field spot_distance.ply)"),
           text("view", "NAME")
               .defaults_to("front")
               .explain("front (camera on +z), back, left, right (+x), top (+y), bottom"),
           real("azimuth", "DEG")
               .explain("camera direction about +y, degrees (0 = front, 90 = right);\n"
                        "overrides --view's"),
           real("elevation", "DEG")
               .at_least(-90)
               .at_most(90)
               .explain("camera height, degrees (90 = top); overrides --view's"),
           text("size", "WxH").defaults_to("800x600").explain("picture size in pixels"),
           text("colormap", "NAME")
               .defaults_to("viridis")
               .explain("viridis (dark violet low → yellow high), diverging (blue → grey → red,\n"
                        "range symmetric about 0 by default), gray"),
           real("min", "LO").explain("low end of the colour range (default: the field's minimum)"),
           real("max", "HI").explain("high end of the colour range (default: the field's maximum)"),
           count("isolines", "N")
               .at_most(1000)
               .defaults_to("0")
               .explain("N dark isolines at LO + k (HI − LO) / (N + 1), k = 1..N"),
           flag("legend").explain(
               "a colour bar at the right edge with the range's ends (and a tick per\n"
               "isoline); the mesh moves left to make room"),
           flag("wireframe").explain("the mesh's edges as thin dark lines"),
           text("curves", "CURVES")
               .with_extensions({".obj", ".ply"})
               .explain("polylines to draw in red: the 'l' lines of an OBJ (--curves-out,\n"
                        "ifem geodesic -o) or a PLY line set (ifem refine --lines: the\n"
                        "intrinsic edges over the input; add --wireframe for the input's)"),
           text("triangulation", "FILE.ifem")
               .explain("a saved intrinsic triangulation of MESH (ifem refine --save): its\n"
                        "edges traced over the surface, in blue (what ifem view shows)"),
           count("symmetry", "N")
               .at_least(1)
               .at_most(6)
               .defaults_to("1")
               .explain("directions per glyph when the properties hold fx fy fz (ifem field):\n"
                        "1 vectors, 2 lines, 4 crosses"),
           real("curve-width", "W")
               .above(0)
               .at_most(64)
               .defaults_to("3")
               .explain("the curves' width in pixels"),
           count("supersample", "S")
               .at_least(1)
               .at_most(4)
               .defaults_to("2")
               .explain("anti-aliasing: draw S× larger, then average S×S pixels"),
           real("fill", "F")
               .above(0)
               .at_most(10)
               .defaults_to("0.9")
               .explain("the scene's bounding sphere over half the picture (> 1 zooms in)"),
           flag("quiet").explain("no progress lines on stderr")}};
}

}  // namespace

Command render_command() {
  Command c;
  c.summary = "a PNG picture of a mesh, a per-vertex field and curves, without a display";
  c.spec.name = "render";
  c.spec.positionals = {"MESH"};
  c.spec.prose =
      "Draws MESH (any format ifem reads; a file without faces as points) into a PNG with a\n"
      "software rasterizer: no GPU, display or browser, and the same command gives the same\n"
      "bytes. The colour is a per-vertex property of MESH (a PLY that ifem distance, eigen,\n"
      "poisson ... wrote) or of --field, through a colour map, shaded by a light from the\n"
      "camera. Over it: the input's wireframe, a saved intrinsic triangulation's edges\n"
      "(blue), field glyphs (fx fy fz properties, dark) and curves (red): the scene ifem\n"
      "view shows, as a picture. Camera: orthographic, aimed at the centre of the\n"
      "bounding box; +y is up in the side views (front = camera on +z). The whole scene\n"
      "fits the picture whatever the view. stdout names the property and the colour range\n"
      "used.\n";
  c.spec.groups = {render_options_group()};
  c.spec.epilogue =
      "examples:\n"
      "  ifem distance spot.obj --source 0 -o spot_distance.ply\n"
      "  ifem render spot_distance.ply --isolines 12 --view right -o spot.png\n"
      "  ifem render spot.obj --field spot_modes.ply --property phi3 --colormap diverging -o "
      "m.png\n"
      "  ifem render spot.obj --wireframe --curves paths.obj --azimuth 30 --elevation 20 -o "
      "w.png\n"
      "  ifem refine spot.obj --save spot.ifem\n"
      "  ifem render spot.obj --triangulation spot.ifem --wireframe -o spot_idt.png\n";
  c.run = run_render;
  return c;
}

}  // namespace ifem::cli
