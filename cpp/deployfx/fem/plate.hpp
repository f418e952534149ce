#pragma once
// A rectangular laminated plate in the x-y plane (length along x, 0-degree plies along x) with
// per-edge boundary conditions. `boundary` names the edges x = 0, y = 0, x = length, y = width
// in that order, each
//   C  clamped: all six dofs fixed;
//   S  simply supported ("hard", SS-1 of Reddy 2004 Sec. 6.2): w = 0, in-plane displacement
//      along the edge = 0, rotation about the edge normal (the slope along the edge) = 0;
//   F  free.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "deployfx/fem/modal.hpp"
#include "deployfx/fem/shell_model.hpp"

namespace deployfx::fem {

class RectangularPlate {
 public:
  RectangularPlate(double length, double width, const material::Laminate& laminate, int nx, int ny);

  double length() const { return length_; }
  double width() const { return width_; }
  int nx() const { return nx_; }
  int ny() const { return ny_; }
  const ShellModel& model() const { return model_; }

  /// Dofs fixed by `boundary`; throws std::invalid_argument unless it is four of C, S, F.
  std::vector<int> fixed_dofs(const std::string& boundary) const;
  /// Transverse displacement w (m) at the nodes, (ny + 1) x (nx + 1), under uniform pressure (Pa)
  /// along +z.
  Eigen::MatrixXd static_deflection(double pressure, const std::string& boundary) const;
  /// Lowest n modes; eigenvalues omega^2 in (rad/s)^2.
  ModalResult modes(int n, const std::string& boundary) const;

 private:
  double length_, width_;
  int nx_, ny_;
  ShellModel model_;
};

}  // namespace deployfx::fem
