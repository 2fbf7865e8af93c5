// The compiled part of `import fq` (fq/_fq*.so); fq/__init__.py re-exports it.
#include "common/version.h"
#include "python/bindings.h"

PYBIND11_MODULE(_fq, m) {
  m.doc() = "fq: filtered quadrics smoothing and clustering of triangle meshes (Legrand et al. 2019)";
  m.attr("__version__") = fq::version_string();
  m.attr("built_with_cuda") = fq::built_with_cuda();
  fq::py::bind_engine_functions(m);
  fq::py::bind_mesh_functions(m);
  fq::py::bind_surface_measures(m);
  fq::py::bind_stream(m);
  fq::py::bind_wire(m);
  fq::py::bind_client(m);
}
