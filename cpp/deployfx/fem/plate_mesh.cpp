#include "deployfx/fem/plate_mesh.hpp"

#include <cmath>

#include "deployfx/math/check.hpp"

namespace deployfx::fem {

QuadMesh rectangular_mesh(double length, double width, int nx, int ny) {
  require_positive("Plate.length", length, "(m)");
  require_positive("Plate.width", width, "(m)");
  if (nx < 1 || nx > 2000) throw_out_of_range("Plate.nx", nx, "an integer in [1, 2000]");
  if (ny < 1 || ny > 2000) throw_out_of_range("Plate.ny", ny, "an integer in [1, 2000]");
  QuadMesh m;
  m.nodes.resize((nx + 1) * (ny + 1), 3);
  // L * i / n, or L * (i / n) where L * i overflows (a length near the largest double).
  auto at = [](double L, int i, int n) {
    const double x = L * i / n;
    return std::isfinite(x) ? x : L * (static_cast<double>(i) / n);
  };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.nodes.row(j * (nx + 1) + i) << at(length, i, nx), at(width, j, ny), 0.0;
  m.quads.resize(nx * ny, 4);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int n0 = j * (nx + 1) + i;
      m.quads.row(j * nx + i) << n0, n0 + 1, n0 + nx + 2, n0 + nx + 1;
    }
  return m;
}

}  // namespace deployfx::fem
