// The `ifem` command: intrinsic finite elements on meshes and point clouds from the wild.
// A thin layer: argument parsing and I/O here, all the work in the libraries.
// Exit codes: 0 success, 1 an input or computation failed (ifem::Error), 2 the command line is
// wrong (cli::UsageError: unknown option, bad value, value out of range), 3 internal error.
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "cli.h"
#include "intrinsic/core/errors.h"
#include "solvers/linalg/memory.h"

namespace {

constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;
constexpr int kExitInternal = 3;

void print_usage() {
  std::printf(
      "ifem — intrinsic finite elements on bad meshes and point clouds\n\n"
      "usage: ifem COMMAND [ARGS] [--help]\n\ncommands:\n");
  for (const auto& c : ifem::cli::all_commands()) {
    std::printf("  %-10s %s\n", c.spec.name.c_str(), c.summary.c_str());
  }
  std::printf(
      "\nInputs: OBJ, OFF, PLY, STL meshes; PLY/XYZ/OBJ point clouds (no faces).\n"
      "Outputs are always on the input's own vertices, in the input's order.\n"
      "Exit codes: 0 done, 1 the input or the computation failed, 2 bad command line.\n"
      "Run 'ifem COMMAND --help' for the options of one command.\n");
}

// Parses the command line against the command's table, then runs it.
int run_command(const ifem::cli::Command& cmd, int argc, const char* const* argv) {
  const ifem::cli::Args args(cmd.spec, argc, argv);
  if (args.has("help")) {
    std::printf("%s", ifem::cli::render_help(cmd.spec).c_str());
    return 0;
  }
  args.check_complete();
  try {
    const int status = cmd.run(args);
    ifem::cli::clear_progress_bar();
    return status;
  } catch (...) {
    ifem::cli::clear_progress_bar();  // the error line starts at the left margin
    throw;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // one job per process: memory freed between its steps is reused instead of faulted in again
  ifem::retain_freed_memory();
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    print_usage();
    return argc < 2 ? kExitUsage : 0;
  }
  const std::string name = argv[1];
  for (const auto& cmd : ifem::cli::all_commands()) {
    if (cmd.spec.name != name) continue;
    try {
      return run_command(cmd, argc - 2, argv + 2);
    } catch (const ifem::cli::UsageError& e) {
      std::fprintf(stderr, "ifem %s: error: %s\n", name.c_str(), e.what());
      return kExitUsage;
    } catch (const ifem::Error& e) {
      std::fprintf(stderr, "ifem %s: error: %s\n", name.c_str(), e.what());
      return kExitFailure;
    } catch (const std::bad_alloc&) {
      std::fprintf(stderr,
                   "ifem %s: error: out of memory (the input, or what refinement would make of "
                   "it, needs more than this machine or `ulimit -v` allows; refinement checks "
                   "--memory-budget up front, the rest does not)\n",
                   name.c_str());
      return kExitFailure;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "ifem %s: internal error: %s\n", name.c_str(), e.what());
      return kExitInternal;
    }
  }
  std::fprintf(stderr, "ifem: unknown command '%s' (run 'ifem --help')\n", name.c_str());
  return kExitUsage;
}
