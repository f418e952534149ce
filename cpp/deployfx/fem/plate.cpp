#include "deployfx/fem/plate.hpp"

#include <stdexcept>

#include "deployfx/fem/constrained_solve.hpp"
#include "deployfx/fem/plate_mesh.hpp"
#include "deployfx/math/check.hpp"

namespace deployfx::fem {
namespace {

ShellModel make_model(double length, double width, const material::Laminate& laminate, int nx, int ny) {
  QuadMesh m = rectangular_mesh(length, width, nx, ny);
  return ShellModel(std::move(m.nodes), std::move(m.quads), laminate);
}

}  // namespace

RectangularPlate::RectangularPlate(double length, double width, const material::Laminate& laminate,
                                   int nx, int ny)
    : length_(length), width_(width), nx_(nx), ny_(ny),
      model_(make_model(length, width, laminate, nx, ny)) {}

std::vector<int> RectangularPlate::fixed_dofs(const std::string& boundary) const {
  const bool ok = boundary.size() == 4 && boundary.find_first_not_of("CSF") == std::string::npos;
  if (!ok)
    throw std::invalid_argument("boundary = '" + boundary +
                                "' is invalid: must be four letters from C, S, F for the edges "
                                "x=0, y=0, x=length, y=width (e.g. 'CFFF')");
  enum { UX, UY, UZ, TX, TY, TZ };
  std::vector<int> fixed;
  auto fix_edge = [&](char kind, bool along_y, int i0, int j0) {
    // Edges x = const run along y (tangent y, normal x); edges y = const run along x.
    const int count = along_y ? ny_ + 1 : nx_ + 1;
    for (int k = 0; k < count; ++k) {
      const int node = along_y ? k * (nx_ + 1) + i0 : j0 * (nx_ + 1) + k;
      const int base = kNodeDofs * node;
      if (kind == 'C') {
        for (int d = 0; d < kNodeDofs; ++d) fixed.push_back(base + d);
      } else if (kind == 'S') {
        fixed.push_back(base + UZ);
        fixed.push_back(base + (along_y ? UY : UX));  // tangential in-plane displacement
        fixed.push_back(base + (along_y ? TX : TY));  // rotation about the edge normal
      }
    }
  };
  fix_edge(boundary[0], true, 0, 0);
  fix_edge(boundary[1], false, 0, 0);
  fix_edge(boundary[2], true, nx_, 0);
  fix_edge(boundary[3], false, 0, ny_);
  return fixed;
}

Eigen::MatrixXd RectangularPlate::static_deflection(double pressure, const std::string& boundary) const {
  require_finite("pressure", pressure, "(Pa)");
  const Eigen::VectorXd u =
      static_solve(model_.stiffness(), model_.pressure_load(pressure), fixed_dofs(boundary));
  Eigen::MatrixXd w(ny_ + 1, nx_ + 1);
  for (int j = 0; j <= ny_; ++j)
    for (int i = 0; i <= nx_; ++i) w(j, i) = u(kNodeDofs * (j * (nx_ + 1) + i) + 2);
  return w;
}

ModalResult RectangularPlate::modes(int n, const std::string& boundary) const {
  return constrained_modes(model_.stiffness(), model_.mass(), n, fixed_dofs(boundary));
}

}  // namespace deployfx::fem
