// The list of `ifem` subcommands (one function per subcommand, each in its cli_<name>.cpp).
#include "cli.h"

namespace ifem::cli {

Command info_command();
Command laplacian_command();
Command refine_command();
Command distance_command();
Command eigen_command();
Command poisson_command();
Command geodesic_command();
Command field_command();
Command transport_command();
Command logmap_command();
Command view_command();
Command render_command();
Command isolines_command();
Command trace_command();
Command simplify_command();
Command transfer_command();

std::vector<Command> all_commands() {
  return {info_command(),      laplacian_command(), refine_command(),   distance_command(),
          eigen_command(),     poisson_command(),   geodesic_command(), field_command(),
          transport_command(), logmap_command(),    view_command(),     render_command(),
          isolines_command(),  trace_command(),     simplify_command(), transfer_command()};
}

}  // namespace ifem::cli
