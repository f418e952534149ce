// deployfx._core: the private compiled module. Glue only; the public API is python/deployfx.
// C++ std::invalid_argument becomes ValueError, std::runtime_error becomes RuntimeError.
#include <pybind11/pybind11.h>

namespace py = pybind11;

void define_material(py::module_& m);
void define_fem(py::module_& m);
void define_body(py::module_& m);
void define_integrate(py::module_& m);
void define_system(py::module_& m);
void define_contact(py::module_& m);
void define_chain(py::module_& m);

PYBIND11_MODULE(_core, m) {
  m.doc() = "deployfx compiled core (private; use the deployfx package)";
  define_material(m);
  define_fem(m);
  define_body(m);
  define_integrate(m);
  define_system(m);
  define_contact(m);
  define_chain(m);
}
