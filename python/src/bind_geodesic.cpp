// Bindings of the geodesic area (bindings.h).
#include "bindings.h"

namespace ifem::python {

void bind_geodesic(py::module_& /*m*/) {}

}  // namespace ifem::python
