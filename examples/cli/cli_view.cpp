// `ifem view`: one self-contained HTML page of a mesh or point cloud and the outputs of the
// other commands (solvers/recipes/view_scene.h builds the scene and the page).
#include <cstdio>
#include <filesystem>
#include <string>

#include "cli.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/integer/correspondence.h"
#include "solvers/recipes/render.h"
#include "solvers/recipes/text_formats.h"
#include "solvers/recipes/view_scene.h"

namespace ifem::cli {
namespace {

std::string stem(const std::string& path) { return std::filesystem::path(path).stem().string(); }

// --field: PLY files give their vertex properties, .txt files one value per line.
void add_field_files(recipes::Scene& scene, const Args& args) {
  if (!args.has("field")) return;
  const std::vector<std::string> files = recipes::split_fields(args.get("field"), ',');
  const int symmetry = static_cast<int>(args.count("symmetry"));
  for (const std::string& file : files) {
    if (file.empty())
      throw UsageError("--field: an empty file name in '" + args.get("field") + "'");
    const std::string prefix = files.size() > 1 ? stem(file) + ": " : "";
    if (io::file_extension(file) == ".txt") {
      recipes::add_field(scene, {stem(file), "", io::read_values(file)});
      continue;
    }
    const io::SurfaceInput in = io::read_surface(file);
    if (in.positions.rows() != scene.positions.rows()) {
      throw InvalidInput("--field " + file + ": " + std::to_string(in.positions.rows()) +
                         " vertices, the mesh has " + std::to_string(scene.positions.rows()));
    }
    if (in.vertex_properties.empty()) {
      throw InvalidInput("--field " + file + ": no per-vertex property to show");
    }
    recipes::add_properties(scene, in.vertex_properties, prefix, symmetry);
  }
}

int run_view(const Args& args) {
  const std::string mesh = args.positional()[0];
  const std::string out = args.get("output");
  // three.js first: a missing install fails before any work
  const std::string three = recipes::find_three_js(args.has("three") ? args.get("three") : "");
  io::SurfaceInput input = read_input(mesh, args);
  std::vector<io::VertexProperty> own = std::move(input.vertex_properties);
  input.vertex_properties.clear();
  recipes::Scene scene =
      recipes::view_scene(input, args.has("title") ? args.get("title") : stem(mesh));
  // MESH's own properties (a PLY output given as MESH), with its glyphs at --symmetry
  recipes::add_properties(scene, own, "", static_cast<int>(args.count("symmetry")));
  add_field_files(scene, args);
  if (args.has("units")) {
    for (recipes::SceneField& f : scene.fields) f.units = args.get("units");
  }
  if (args.has("curves")) {
    for (const std::string& file : recipes::split_fields(args.get("curves"), ',')) {
      if (io::file_extension(file) != ".obj") {
        throw UsageError("--curves: '" + file + "' is not an .obj polyline file");
      }
      recipes::add_polylines(scene, stem(file), solvers::read_polylines_obj(file));
    }
  }
  add_triangulation(scene, args);
  recipes::write_view_page(out, scene, three);
  std::printf(
      "wrote %s: %d %s, %zu fields, %zu curve files, %zu intrinsic edges, %d glyphs, %zu "
      "singularities\n",
      out.c_str(), int(scene.positions.rows()), scene.faces.empty() ? "points" : "vertices",
      scene.fields.size(), scene.curves.size(), scene.intrinsic_edges.size(),
      int(scene.glyph_segments.rows() / 2), scene.singularities.size());
  return 0;
}

}  // namespace

void add_triangulation(recipes::Scene& scene, const Args& args) {
  if (!args.has("triangulation")) return;
  const std::string file = args.get("triangulation");
  const intrinsic::SavedTriangulation saved = intrinsic::load_triangulation(file);
  try {
    recipes::add_intrinsic_edges(scene, saved.view());
  } catch (const InvalidInput& e) {  // another mesh, or coordinates that do not trace
    throw InvalidInput(file + ": " + e.what());
  }
  progress(args, "traced " + std::to_string(scene.intrinsic_edges.size()) +
                     " intrinsic edges over the input");
}

Command view_command() {
  Command c;
  c.summary = "one HTML page (offline, any browser) of a mesh and the other commands' outputs";
  c.spec.name = "view";
  c.spec.positionals = {"MESH"};
  c.spec.prose =
      "Writes OUT.html, a single file that opens offline in any browser with WebGL: the\n"
      "mesh (a point cloud as points) with orbit (left drag), zoom (wheel) and pan (right\n"
      "drag); a menu to colour it by any per-vertex property with a perceptual colour\n"
      "map and a legend of its min / max (and --units); toggles for isolines (10 bands),\n"
      "the input wireframe, each curve file, the field glyphs, the singularities and\n"
      "the intrinsic edges; a button saving the view as PNG.\n"
      "What it shows:\n"
      "  MESH's own PLY vertex properties, and those of every --field file: the PLY\n"
      "  outputs of distance, poisson, eigen, field, transport, logmap on the same mesh\n"
      "  (same vertices), or a .txt file of one value per vertex (-o OUT.txt outputs).\n"
      "  A file with fx fy fz (ifem field, transport) also gives glyphs: N segments per\n"
      "  vertex (--symmetry N as given to ifem field); its property singularity marks\n"
      "  the singular vertices (red: positive index, blue: negative).\n"
      "  --curves: OBJ polylines ('v' and 'l' lines): ifem geodesic -o OUT.obj and\n"
      "  the --curves-out files of poisson, distance, field.\n"
      "  --triangulation: a saved intrinsic triangulation (ifem refine --save FILE.ifem,\n"
      "  made on MESH; signposts or integer coordinates): every intrinsic edge traced\n"
      "  over the input surface, drawn over the input's wireframe (the common\n"
      "  subdivision's edges).\n"
      "The page embeds three.js (npm package three, installed by scripts/setup.sh into\n"
      "build/web) and the data; it loads nothing from the network.\n";
  c.spec.groups = {
      {"Options",
       {text("output", "OUT")
            .short_alias('o')
            .mandatory()
            .with_extensions({".html"})
            .explain("the page to write"),
        text("field", "FILES").explain("comma-separated .ply / .txt files of per-vertex values"),
        text("curves", "FILES").explain("comma-separated .obj polyline files"),
        text("triangulation", "FILE.ifem").explain("intrinsic triangulation to trace over MESH"),
        count("symmetry", "N")
            .at_least(1)
            .at_most(6)
            .defaults_to("1")
            .explain("directions per glyph (1 vectors, 2 lines, 4 crosses)"),
        text("units", "U").explain("units of the values, shown in the legend"),
        text("title", "T").explain("the page's title (default: MESH's name)"),
        text("three", "DIR")
            .explain("the three.js package directory (default: $IFEM_THREE_DIR,\n"
                     "then where scripts/setup.sh installs it)"),
        flag("quiet").explain("no progress lines on stderr")}}};
  c.spec.epilogue =
      "examples:\n"
      "  ifem distance spot.obj --source 0 -o spot_distance.ply\n"
      "  ifem view spot.obj --field spot_distance.ply --units m -o spot.html\n"
      "  ifem field spot.obj --symmetry 4 -o cross.ply\n"
      "  ifem view spot.obj --field cross.ply --symmetry 4 -o cross.html\n"
      "  ifem refine spot.obj --save spot.ifem\n"
      "  ifem geodesic spot.obj --path 0,500 -o path.obj\n"
      "  ifem view spot.obj --triangulation spot.ifem --curves path.obj -o spot_idt.html\n";
  c.run = run_view;
  return c;
}

}  // namespace ifem::cli
