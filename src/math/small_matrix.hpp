// Tiny dense 3x3 helpers: determinant, inverse, products. Matrices are row-major plain arrays
// (A[3*i + j] = A_ij) so the same code runs on the host and inside CUDA kernels (the element
// physics, the hex8 reference element, mesh checks). 3-vectors are in vector3.hpp.
#pragma once
#include "math/host_device.hpp"

namespace dipc {

// det A by cofactor expansion along the first row.
DIPC_HD double det3x3(const double A[9]) {
  return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) + A[2] * (A[3] * A[7] - A[4] * A[6]);
}

// Inverse through the adjugate: A^{-1} = adj(A) / det A. Returns det A; the output is
// unspecified when det A == 0 (callers reject degenerate or inverted states first).
DIPC_HD double inverse3x3(const double A[9], double Ainv[9]) {
  const double c00 = A[4] * A[8] - A[5] * A[7];
  const double c01 = A[5] * A[6] - A[3] * A[8];
  const double c02 = A[3] * A[7] - A[4] * A[6];
  const double det = A[0] * c00 + A[1] * c01 + A[2] * c02;
  const double s = 1.0 / det;
  Ainv[0] = c00 * s;
  Ainv[1] = (A[2] * A[7] - A[1] * A[8]) * s;
  Ainv[2] = (A[1] * A[5] - A[2] * A[4]) * s;
  Ainv[3] = c01 * s;
  Ainv[4] = (A[0] * A[8] - A[2] * A[6]) * s;
  Ainv[5] = (A[2] * A[3] - A[0] * A[5]) * s;
  Ainv[6] = c02 * s;
  Ainv[7] = (A[1] * A[6] - A[0] * A[7]) * s;
  Ainv[8] = (A[0] * A[4] - A[1] * A[3]) * s;
  return det;
}

// A^{-T} (the cofactor matrix divided by det A). Returns det A.
DIPC_HD double inverse_transpose3x3(const double A[9], double AinvT[9]) {
  double Ainv[9];
  const double det = inverse3x3(A, Ainv);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) AinvT[3 * i + j] = Ainv[3 * j + i];
  return det;
}

// C = A B
DIPC_HD void multiply3x3(const double A[9], const double B[9], double C[9]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

// C = A^T B
DIPC_HD void multiply_transpose_a3x3(const double A[9], const double B[9], double C[9]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C[3 * i + j] = A[i] * B[j] + A[3 + i] * B[3 + j] + A[6 + i] * B[6 + j];
}

// A : B = sum_ij A_ij B_ij
DIPC_HD double double_contraction3x3(const double A[9], const double B[9]) {
  double s = 0;
  for (int k = 0; k < 9; ++k) s += A[k] * B[k];
  return s;
}

}  // namespace dipc
