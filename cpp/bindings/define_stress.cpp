// Ply stress recovery, strengths and failure indices (fem/ply_stress, fem/ply_envelope,
// material/failure_criteria, material/transverse_shear). Glue only; python/deployfx/stress.py is
// the public API.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "deployfx/fem/ply_envelope.hpp"
#include "deployfx/fem/ply_stress.hpp"
#include "deployfx/material/failure_criteria.hpp"
#include "deployfx/material/transverse_shear.hpp"

namespace py = pybind11;
using namespace deployfx::fem;
using deployfx::material::Criterion;
using deployfx::material::FailureModel;
using deployfx::material::Laminate;
using deployfx::material::Strengths;
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

namespace {

PlyFailureSetup make_setup(const std::vector<Strengths>& strengths, const std::vector<Criterion>& criteria,
                           const std::string& strain) {
  PlyFailureSetup setup;
  for (const Strengths& s : strengths) setup.ply_models.emplace_back(s);
  setup.criteria = criteria;
  setup.measure = strain_measure_from_name(strain);
  return setup;
}

void require_columns(const PlyRecovery& r, const RowMatrix& U) {
  if (U.cols() != r.num_dofs)
    throw std::invalid_argument("u_series has wrong shape: expected (n, " + std::to_string(r.num_dofs) +
                                ") (6 dofs per node), got (" + std::to_string(U.rows()) + ", " +
                                std::to_string(U.cols()) + ")");
}

// Runs f(first, count) over batches of rows with the GIL released, answering Ctrl-C in between.
template <class F>
void in_batches(int n, F&& f) {
  constexpr int kBatch = 32;
  for (int first = 0; first < n; first += kBatch) {
    const int count = std::min(kBatch, n - first);
    {
      py::gil_scoped_release release;
      f(first, count);
    }
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  }
}

py::array_t<double> field_array(const PlyRecovery& r) {
  return py::array_t<double>(std::vector<py::ssize_t>{r.num_elements, r.points_per_element, r.num_plies,
                                                      kPlyStations, kPlyComponents});
}

}  // namespace

void define_stress(py::module_& m) {
  py::class_<Strengths>(m, "Strengths")
      .def(py::init([](double Xt, double Xc, double Yt, double Yc, double S12, std::optional<double> S13,
                       std::optional<double> S23, double F12_star) {
             Strengths s{Xt, Xc, Yt, Yc, S12, S13, S23, F12_star};
             s.validate();
             return s;
           }),
           py::arg("Xt"), py::arg("Xc"), py::arg("Yt"), py::arg("Yc"), py::arg("S12"), py::arg("S13"),
           py::arg("S23"), py::arg("F12_star"));

  py::enum_<Criterion>(m, "FailureCriterion")
      .value("max_stress", Criterion::MaxStress)
      .value("tsai_wu", Criterion::TsaiWu)
      .value("hashin_fibre", Criterion::HashinFibre)
      .value("hashin_matrix", Criterion::HashinMatrix);

  m.def("failure_indices",
        [](const RowMatrix& stress, const Strengths& strengths, Criterion criterion) {
          if (stress.cols() != kPlyComponents)
            throw std::invalid_argument("stresses must have 5 components (sigma_1, sigma_2, tau_12, tau_13, "
                                        "tau_23) on the last axis, got " + std::to_string(stress.cols()));
          if (!stress.allFinite()) throw std::invalid_argument("stresses have non-finite entries");
          const FailureModel model(strengths);
          model.require(criterion);
          Eigen::VectorXd out(stress.rows());
          for (Eigen::Index i = 0; i < stress.rows(); ++i)
            out(i) = model.index(criterion, stress.row(i).transpose());
          return out;
        },
        py::arg("stress"), py::arg("strengths"), py::arg("criterion"));

  m.def("equilibrium_shear",
        [](const Laminate& laminate, const std::vector<double>& z) {
          const std::vector<Eigen::Matrix2d> H = deployfx::material::equilibrium_shear(laminate, z);
          py::array_t<double> out(std::vector<py::ssize_t>{static_cast<py::ssize_t>(z.size()), 2, 2});
          auto o = out.mutable_unchecked<3>();
          for (std::size_t q = 0; q < H.size(); ++q)
            for (int i = 0; i < 2; ++i)
              for (int j = 0; j < 2; ++j) o(q, i, j) = H[q](i, j);
          return out;
        },
        py::arg("laminate"), py::arg("z"));

  py::class_<PlyRecovery>(m, "PlyRecovery")
      .def(py::init([](const ShellModel& model, const Laminate& laminate, bool gauss) {
             return make_ply_recovery(model, laminate, gauss ? Sampling::Gauss : Sampling::Centroid);
           }),
           py::arg("model"), py::arg("laminate"), py::arg("gauss"))
      .def_readonly("num_elements", &PlyRecovery::num_elements)
      .def_readonly("points_per_element", &PlyRecovery::points_per_element)
      .def_readonly("num_plies", &PlyRecovery::num_plies)
      .def_readonly("num_dofs", &PlyRecovery::num_dofs)
      .def_readonly("points", &PlyRecovery::points_W)
      .def_property_readonly("z", [](const PlyRecovery& r) {
        Eigen::MatrixXd z(r.num_plies, kPlyStations);
        for (int k = 0; k < r.num_plies; ++k)
          for (int j = 0; j < kPlyStations; ++j) z(k, j) = r.plies[k].z[j];
        return z;
      })
      .def("fields",
           [](const PlyRecovery& r, const Eigen::VectorXd& u, const std::string& strain) {
             const StrainMeasure measure = strain_measure_from_name(strain);
             py::array_t<double> stress = field_array(r), strains = field_array(r);
             double* s = stress.mutable_data();
             double* e = strains.mutable_data();
             {
               py::gil_scoped_release release;
               ply_fields(r, u, measure, s, e);
             }
             return py::make_tuple(stress, strains);
           },
           py::arg("u"), py::arg("strain"))
      .def("envelope",
           [](const PlyRecovery& r, const RowMatrix& U, const std::vector<Strengths>& strengths,
              const std::vector<Criterion>& criteria, const std::string& strain) {
             require_columns(r, U);
             const PlyFailureSetup setup = make_setup(strengths, criteria, strain);
             PlyEnvelope env = empty_envelope(r, setup);
             in_batches(static_cast<int>(U.rows()), [&](int first, int count) {
               accumulate_envelope(r, setup, U.data() + static_cast<std::ptrdiff_t>(first) * U.cols(), count,
                                   &env);
             });
             const std::vector<py::ssize_t> shape{env.num_criteria, env.num_elements, env.num_plies};
             auto as_array = [&](const auto& v) {
               using T = typename std::decay_t<decltype(v)>::value_type;
               py::array_t<T> a(shape);
               std::copy(v.begin(), v.end(), a.mutable_data());
               return a;
             };
             py::array_t<double> peak(std::vector<py::ssize_t>{env.samples, env.num_criteria});
             std::copy(env.peak.begin(), env.peak.end(), peak.mutable_data());
             py::dict out;
             out["index"] = as_array(env.index);
             out["sample"] = as_array(env.sample);
             out["point"] = as_array(env.point);
             out["station"] = as_array(env.station);
             out["peak"] = peak;
             return out;
           },
           py::arg("u_series"), py::arg("strengths"), py::arg("criteria"), py::arg("strain"))
      .def("index_series",
           [](const PlyRecovery& r, const RowMatrix& U, const std::vector<Strengths>& strengths,
              const std::vector<Criterion>& criteria, const std::string& strain, const std::vector<int>& elements) {
             require_columns(r, U);
             const PlyFailureSetup setup = make_setup(strengths, criteria, strain);
             check_setup(r, setup);
             const int n = static_cast<int>(U.rows());
             py::array_t<double> out(std::vector<py::ssize_t>{n, static_cast<py::ssize_t>(criteria.size()),
                                                              static_cast<py::ssize_t>(elements.size()),
                                                              r.num_plies});
             double* o = out.mutable_data();
             const std::ptrdiff_t per_sample = static_cast<std::ptrdiff_t>(criteria.size()) * elements.size() *
                                               r.num_plies;
             in_batches(n, [&](int first, int count) {
               index_series(r, setup, U.data() + static_cast<std::ptrdiff_t>(first) * U.cols(), count, elements,
                            o + first * per_sample);
             });
             return out;
           },
           py::arg("u_series"), py::arg("strengths"), py::arg("criteria"), py::arg("strain"),
           py::arg("elements"));
}
