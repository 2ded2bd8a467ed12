// find_nested_bodies / check_no_nested_bodies: a body inside another is found (whichever
// order the bodies come in, and when it touches the outer surface from inside); bodies side by
// side, touching from outside, in a cavity of the other, or in the notch of an L-shaped body
// (inside its bounding box, outside its material) are not.
#include <gtest/gtest.h>

#include "mesh/box_generator.hpp"
#include "mesh/mesh_error.hpp"
#include "mesh/nested_bodies.hpp"
#include "mesh/surface_mesh.hpp"
#include "surface_test_support.hpp"

namespace dipc {
namespace {

HexMesh box(std::array<double, 3> size, std::array<double, 3> origin, int body, const std::string& name, int n = 2) {
  return generate_box(size, {n, n, n}, origin, body, name);
}

HexMesh two_bodies(const HexMesh& a, const HexMesh& b) {
  HexMesh all = a;
  all.append(b);
  return all;
}

TEST(NestedBodies, BoxInsideBoxIsFoundInEitherOrder) {
  const HexMesh outer = box({1, 1, 1}, {0, 0, 0}, 0, "outer", 4);
  const HexMesh inner = box({0.2, 0.2, 0.2}, {0.4, 0.4, 0.4}, 1, "inner");
  NestedBodies n = find_nested_bodies(two_bodies(outer, inner));
  EXPECT_EQ(n.inner, 1);
  EXPECT_EQ(n.outer, 0);
  EXPECT_GE(n.node, static_cast<std::int64_t>(outer.num_nodes()));

  const HexMesh inner_first = box({0.2, 0.2, 0.2}, {0.4, 0.4, 0.4}, 0, "inner");
  const HexMesh outer_second = box({1, 1, 1}, {0, 0, 0}, 1, "outer", 4);
  n = find_nested_bodies(two_bodies(inner_first, outer_second));
  EXPECT_EQ(n.inner, 0);
  EXPECT_EQ(n.outer, 1);
}

TEST(NestedBodies, InnerBoxTouchingTheOuterSurfaceFromInsideIsFound) {
  // The inner box's bottom face lies on the outer box's bottom face: those vertices decide
  // nothing (winding number ½), the others do.
  const HexMesh mesh = two_bodies(box({1, 1, 1}, {0, 0, 0}, 0, "outer", 4),
                                  box({0.5, 0.5, 0.5}, {0.25, 0.25, 0}, 1, "inner"));
  EXPECT_EQ(find_nested_bodies(mesh).inner, 1);
}

TEST(NestedBodies, SeparateAndTouchingBoxesAreNotNested) {
  EXPECT_EQ(find_nested_bodies(two_bodies(box({1, 1, 1}, {0, 0, 0}, 0, "a"), box({1, 1, 1}, {2, 0, 0}, 1, "b"))).inner,
            -1);
  EXPECT_EQ(find_nested_bodies(two_bodies(box({1, 1, 1}, {0, 0, 0}, 0, "a"), box({1, 1, 1}, {1, 0, 0}, 1, "b"))).inner,
            -1);
  // A small box standing on a larger one.
  EXPECT_EQ(find_nested_bodies(
                two_bodies(box({1, 1, 1}, {0, 0, 0}, 0, "a"), box({0.5, 0.5, 0.5}, {0.25, 0.25, 1}, 1, "b")))
                .inner,
            -1);
}

TEST(NestedBodies, BoxInACavityIsNotInside) {
  HexMesh hollow = test::box_with_cavity(3);  // cavity [1, 2]^3
  const HexMesh mesh = two_bodies(hollow, box({0.5, 0.5, 0.5}, {1.25, 1.25, 1.25}, 1, "pebble"));
  EXPECT_EQ(find_nested_bodies(mesh).inner, -1);
}

TEST(NestedBodies, BoxInTheNotchOfAnLShapeIsNotInside) {
  // An L: a 2x2x1 block of unit cubes with the (1, 1) cube missing; the small box sits in the
  // missing cube, inside the L's bounding box but outside its material.
  HexMesh l_shape = generate_box({2, 2, 1}, {2, 2, 1}, {0, 0, 0}, 0, "l");
  l_shape.hexes.erase(l_shape.hexes.begin() + 3);
  l_shape.body.erase(l_shape.body.begin() + 3);
  const HexMesh mesh = two_bodies(l_shape, box({0.5, 0.5, 0.5}, {1.25, 1.25, 0.25}, 1, "pebble"));
  EXPECT_EQ(find_nested_bodies(mesh).inner, -1);
}

TEST(NestedBodies, MessageNamesBothBodies) {
  const HexMesh mesh = two_bodies(box({1, 1, 1}, {0, 0, 0}, 0, "outer", 4),
                                  box({0.2, 0.2, 0.2}, {0.4, 0.4, 0.4}, 1, "inner"));
  try {
    check_no_nested_bodies(mesh, {"outer", "inner"}, "scene.json");
    FAIL() << "no error";
  } catch (const MeshError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("scene.json: body \"inner\" lies inside body \"outer\""), std::string::npos) << what;
  }
  EXPECT_NO_THROW(
      check_no_nested_bodies(two_bodies(box({1, 1, 1}, {0, 0, 0}, 0, "a"), box({1, 1, 1}, {2, 0, 0}, 1, "b")),
                             {"a", "b"}, "scene.json"));
}

TEST(NestedBodies, WindingNumberOfABox) {
  const HexMesh mesh = box({1, 1, 1}, {0, 0, 0}, 0, "cube");
  std::vector<std::array<std::int64_t, 3>> triangles;
  for (const auto& t : build_surface_mesh(mesh).triangles) triangles.push_back(t);
  EXPECT_NEAR(winding_number(mesh, triangles, {0.5, 0.5, 0.5}), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(mesh, triangles, {0.01, 0.99, 0.5}), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(mesh, triangles, {1.5, 0.5, 0.5}), 0.0, 1e-12);
  EXPECT_NEAR(winding_number(mesh, triangles, {-3, 7, 2}), 0.0, 1e-12);
}

}  // namespace
}  // namespace dipc
