// The `ifem` command: intrinsic finite elements on meshes and point clouds from the wild.
// A thin layer: argument parsing and I/O here, all the work in the libraries.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "cli.h"
#include "intrinsic/core/errors.h"

namespace ifem::cli {
// One function per subcommand, each defined in its cli_<name>.cpp.
Command info_command();
Command laplacian_command();
Command refine_command();
Command distance_command();
Command eigen_command();
Command poisson_command();
}  // namespace ifem::cli

namespace {

std::vector<ifem::cli::Command> commands() {
  using namespace ifem::cli;
  return {info_command(),     laplacian_command(), refine_command(),
          distance_command(), eigen_command(),     poisson_command()};
}

void print_usage() {
  std::printf(
      "ifem — intrinsic finite elements on bad meshes and point clouds\n\n"
      "usage: ifem COMMAND [ARGS] [--help]\n\ncommands:\n");
  for (const auto& c : commands()) std::printf("  %-10s %s\n", c.name.c_str(), c.summary.c_str());
  std::printf(
      "\nInputs: OBJ, OFF, PLY, STL meshes; PLY/XYZ/OBJ point clouds (no faces).\n"
      "Outputs are always on the input's own vertices, in the input's order.\n"
      "Run 'ifem COMMAND --help' for the options of one command.\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    print_usage();
    return argc < 2 ? 2 : 0;
  }
  const std::string name = argv[1];
  for (const auto& cmd : commands()) {
    if (cmd.name != name) continue;
    try {
      const ifem::cli::Args args(argc - 2, argv + 2, cmd.flags, cmd.options);
      if (args.has("help")) {
        std::printf("%s", cmd.help.c_str());
        return 0;
      }
      return cmd.run(args);
    } catch (const ifem::Error& e) {
      std::fprintf(stderr, "ifem %s: error: %s\n", name.c_str(), e.what());
      return 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "ifem %s: internal error: %s\n", name.c_str(), e.what());
      return 3;
    }
  }
  std::fprintf(stderr, "ifem: unknown command '%s' (run 'ifem --help')\n", name.c_str());
  return 2;
}
