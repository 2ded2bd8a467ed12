// Helpers shared by the mesh tests: element volumes by Gauss quadrature, element corner
// coordinates, and the path of the test data files.
#pragma once
#include <string>

#include "math/small_matrix.hpp"
#include "mesh/hex8_reference.hpp"
#include "mesh/hex_mesh.hpp"
#include "support/source_tree.hpp"

namespace dipc::test {

inline std::string mesh_data(const std::string& file) { return dipc::test::source_dir() + "/tests/mesh/data/" + file; }

inline void element_coordinates(const HexMesh& mesh, std::size_t e, double X[24]) {
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i) X[3 * a + i] = mesh.nodes[mesh.hexes[e][a]][i];
}

// V_e = Σ_q w_q det J(ξ_q): exact for trilinear hexes because det J is a polynomial of
// degree ≤ 2 in each reference coordinate, which 2-point Gauss integrates exactly.
inline double element_volume(const HexMesh& mesh, std::size_t e) {
  double X[24], dN[24], J[9];
  element_coordinates(mesh, e, X);
  double v = 0;
  for (int q = 0; q < hex8::kQuadraturePoints; ++q) {
    double xi, eta, zeta;
    hex8::gauss_point(q, xi, eta, zeta);
    hex8::shape_gradient(xi, eta, zeta, dN);
    hex8::jacobian(X, dN, J);
    v += hex8::kGaussWeight * det3x3(J);
  }
  return v;
}

inline double mesh_volume(const HexMesh& mesh) {
  double v = 0;
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) v += element_volume(mesh, e);
  return v;
}

}  // namespace dipc::test
