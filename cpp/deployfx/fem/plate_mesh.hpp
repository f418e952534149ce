#pragma once
// Structured mesh of a flat rectangle in the x-y plane: length along x, width along y.
// Node (i, j), i = 0..nx along x, j = 0..ny along y, has index j (nx + 1) + i; element (i, j)
// has index j nx + i and nodes counter-clockwise about +z (the numbering of the paper's Fig. 6).
#include "deployfx/fem/shell_model.hpp"

namespace deployfx::fem {

struct QuadMesh {
  NodeMatrix nodes;
  QuadMatrix quads;
};

/// Throws std::invalid_argument for non-positive sizes or element counts below 1.
QuadMesh rectangular_mesh(double length, double width, int nx, int ny);

}  // namespace deployfx::fem
