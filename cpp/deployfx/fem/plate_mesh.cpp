#include "deployfx/fem/plate_mesh.hpp"

#include <cmath>
#include <utility>

#include "deployfx/math/check.hpp"

namespace deployfx::fem {

QuadMesh rectangular_mesh(double length, double width, int nx, int ny) {
  // At most 1000 km: beyond any spacecraft structure, and L * i / n cannot overflow (a fuzz case
  // at 1.8e308 m failed on non-finite nodes, naming neither the length nor a range).
  constexpr double kMaxSize = 1e6;  // m
  for (const auto& [name, value] : {std::pair<const char*, double>{"Plate.length", length}, {"Plate.width", width}})
    if (!(std::isfinite(value) && value > 0.0 && value <= kMaxSize)) throw_out_of_range(name, value, "in (0, 1e6] (m)");
  if (nx < 1 || nx > 2000) throw_out_of_range("Plate.nx", nx, "an integer in [1, 2000]");
  if (ny < 1 || ny > 2000) throw_out_of_range("Plate.ny", ny, "an integer in [1, 2000]");
  QuadMesh m;
  m.nodes.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.nodes.row(j * (nx + 1) + i) << length * i / nx, width * j / ny, 0.0;
  m.quads.resize(nx * ny, 4);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int n0 = j * (nx + 1) + i;
      m.quads.row(j * nx + i) << n0, n0 + 1, n0 + nx + 2, n0 + nx + 1;
    }
  return m;
}

}  // namespace deployfx::fem
