// PolyFEM's `transformation.dimensions` (Body/Obstacle::dimensions): scale a mesh, axis by
// axis, so that its bounding box gets the given sizes. PolyFEM (mesh/GeometryReader.cpp,
// construct_affine_transformation) takes the factor dimensions[c] / extent[c], with an axis
// of zero extent counted as extent 1, so a flat OBJ plane given 0 for its flat axis keeps a
// factor of 0 there (its points go to coordinate 0 on that axis, then `translation` applies).
// The factors act first: x = scale·(linear·diag(f)·X) + translation, as PolyFEM scales before
// it rotates and translates. They need the mesh's points, so the app computes them where it
// reads the file; the scene reader only validates the sizes.
#pragma once
#include <array>
#include <optional>
#include <vector>

namespace dipc {

// Bounding-box sizes (max − min per axis) of `points`; zeros for none.
std::array<double, 3> bounding_box_extent(const std::vector<std::array<double, 3>>& points);

// The factors f above; {1, 1, 1} without `dimensions`. Throws std::invalid_argument (a message
// without a location: the caller names the key) for a size of 0 along an axis where the
// points extend, which would flatten the mesh: PolyFEM does so, but flattened hexahedra have
// det J = 0 and a flattened obstacle has triangles of zero area, which dipc's contact cannot
// take.
std::array<double, 3> dimension_factors(const std::optional<std::array<double, 3>>& dimensions,
                                        const std::vector<std::array<double, 3>>& points);

}  // namespace dipc
