// deployfx._core: the private compiled module. Glue only; the public API is python/deployfx.
// C++ std::invalid_argument becomes ValueError, std::runtime_error becomes RuntimeError.
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <string>

namespace py = pybind11;

void define_material(py::module_& m);
void define_fem(py::module_& m);
void define_body(py::module_& m);
void define_integrate(py::module_& m);
void define_specs(py::module_& m);
void define_multibody(py::module_& m);
void define_contact(py::module_& m);
void define_stress(py::module_& m);
void define_groove(py::module_& m);

namespace {

// The vector instruction sets Eigen's kernels were compiled for (CMake option DEPLOYFX_NATIVE);
// Eigen's own SimdInstructionSetsInUse() does not tell AVX2 and FMA from AVX.
std::string vector_instructions() {
  std::string s;
  auto add = [&s](const char* name) { s += (s.empty() ? "" : ", ") + std::string(name); };
#ifdef EIGEN_VECTORIZE_AVX512
  add("AVX-512");
#endif
#ifdef EIGEN_VECTORIZE_AVX2
  add("AVX2");
#endif
#ifdef EIGEN_VECTORIZE_FMA
  add("FMA");
#endif
#ifdef EIGEN_VECTORIZE_AVX
  add("AVX");
#endif
#ifdef EIGEN_VECTORIZE_SSE4_2
  add("SSE4.2");
#endif
#ifdef EIGEN_VECTORIZE_SSE2
  add("SSE2");
#endif
#ifdef EIGEN_VECTORIZE_NEON
  add("NEON");
#endif
  return s.empty() ? "no vector instructions" : s;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "deployfx compiled core (private; use the deployfx package)";
  m.attr("simd") = vector_instructions();  // the bench scripts print it next to their timings
  define_material(m);
  define_fem(m);
  define_body(m);
  define_integrate(m);
  define_specs(m);
  define_multibody(m);
  define_contact(m);
  define_stress(m);
  define_groove(m);
}
