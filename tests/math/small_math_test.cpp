// The 3-vector, 3x3 matrix and box helpers of src/math against hand-computed values and
// identities: det and inverse (A A⁻¹ = I, det of a product), cross and dot products (a × b ⊥ a,
// b; |a × b|² = |a|²|b|² − (a·b)²), the cross-product matrix, and the closed boxes (an empty box
// overlaps nothing, touching boxes overlap, growing, inflating and merging).
#include <gtest/gtest.h>

#include <cmath>

#include "math/aabb.hpp"
#include "math/small_matrix.hpp"
#include "math/vector3.hpp"

namespace dipc {
namespace {

TEST(SmallMatrix, DeterminantAndInverse) {
  const double A[9] = {2, -1, 0.5, 1, 3, -2, 0, 1, 4};
  // Cofactor expansion by hand: 2(12 + 2) + 1(4 − 0) + 0.5(1 − 0) = 32.5.
  EXPECT_DOUBLE_EQ(det3x3(A), 32.5);
  double Ainv[9], I[9];
  EXPECT_DOUBLE_EQ(inverse3x3(A, Ainv), 32.5);
  multiply3x3(A, Ainv, I);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(I[3 * i + j], i == j ? 1.0 : 0.0, 1e-15);
  const double B[9] = {1, 2, 0, 0, 1, 0, 3, 0, 2};
  double AB[9];
  multiply3x3(A, B, AB);
  EXPECT_NEAR(det3x3(AB), det3x3(A) * det3x3(B), 1e-12);
  double AtB[9], At[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) At[3 * i + j] = A[3 * j + i];
  multiply_transpose_a3x3(A, B, AtB);
  multiply3x3(At, B, AB);
  for (int k = 0; k < 9; ++k) EXPECT_DOUBLE_EQ(AtB[k], AB[k]);
}

TEST(Vector3, ProductsAndCrossMatrix) {
  const double a[3] = {1, -2, 3}, b[3] = {0.5, 4, -1};
  double c[3], d[3];
  cross3(a, b, c);
  EXPECT_DOUBLE_EQ(c[0], -10);  // (−2)(−1) − 3·4
  EXPECT_DOUBLE_EQ(c[1], 2.5);  // 3·0.5 − 1·(−1)
  EXPECT_DOUBLE_EQ(c[2], 5);    // 1·4 − (−2)·0.5
  EXPECT_DOUBLE_EQ(dot3(c, a), 0.0);
  EXPECT_DOUBLE_EQ(dot3(c, b), 0.0);
  EXPECT_DOUBLE_EQ(squared_norm3(c), squared_norm3(a) * squared_norm3(b) - dot3(a, b) * dot3(a, b));
  subtract3(a, b, d);
  EXPECT_DOUBLE_EQ(d[0], 0.5);
  EXPECT_DOUBLE_EQ(d[1], -6);
  EXPECT_DOUBLE_EQ(d[2], 4);
  double A[9];
  cross_matrix3(a, A);
  for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(A[3 * i] * b[0] + A[3 * i + 1] * b[1] + A[3 * i + 2] * b[2], c[i]);
  EXPECT_EQ(clamp01(-0.5), 0.0);
  EXPECT_EQ(clamp01(0.25), 0.25);
  EXPECT_EQ(clamp01(2.0), 1.0);
}

TEST(Aabb, GrowInflateMergeOverlap) {
  Aabb e = aabb_empty();
  EXPECT_TRUE(aabb_is_empty(e));
  const double p[3] = {1, 2, 3}, q[3] = {-1, 5, 3};
  Aabb b = aabb_empty();
  EXPECT_FALSE(aabbs_overlap(e, b));
  aabb_add_point(&b, p);
  EXPECT_FALSE(aabb_is_empty(b));
  EXPECT_FALSE(aabbs_overlap(e, b));
  aabb_add_point(&b, q);
  const Aabb expected{{-1, 2, 3}, {1, 5, 3}};
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(b.lo[k], expected.lo[k]);
    EXPECT_EQ(b.hi[k], expected.hi[k]);
  }
  const Aabb touching{{1, 5, 3}, {2, 6, 4}}, apart{{1.5, 0, 0}, {2, 6, 4}};
  EXPECT_TRUE(aabbs_overlap(b, touching));  // closed boxes
  EXPECT_FALSE(aabbs_overlap(b, apart));
  Aabb grown = b;
  aabb_inflate(&grown, 0.5);
  EXPECT_TRUE(aabbs_overlap(grown, apart));
  EXPECT_EQ(grown.lo[0], -1.5);
  EXPECT_EQ(grown.hi[2], 3.5);
  Aabb merged = aabb_empty();
  aabb_merge(&merged, b);
  aabb_merge(&merged, apart);
  EXPECT_EQ(merged.lo[1], 0);
  EXPECT_EQ(merged.hi[0], 2);
  EXPECT_EQ(merged.hi[1], 6);
}

}  // namespace
}  // namespace dipc
