// Bindings of the curves area (bindings.h).
#include "bindings.h"

namespace ifem::python {

void bind_curves(py::module_& /*m*/) {}

}  // namespace ifem::python
