// Bindings of the solvers area (bindings.h).
#include "bindings.h"

namespace ifem::python {

void bind_solvers(py::module_& /*m*/) {}

}  // namespace ifem::python
