// Bindings of the refine area (bindings.h).
#include "bindings.h"

namespace ifem::python {

void bind_refine(py::module_& /*m*/) {}

}  // namespace ifem::python
