// The contact obstacles of a run as grids of the output (XdmfWriter's OutputObstacle): each
// half-space plane as a finite square patch, each triangle-mesh obstacle as its triangles, and
// the displacements of those that move.
#pragma once
#include <array>
#include <vector>

#include "contact/distributed/contact_parameters.hpp"
#include "io/xdmf_writer.hpp"

namespace dipc {

// An axis-aligned box (min xyz, max xyz) that the patches are sized to: the bodies' and the
// triangle-mesh obstacles' rest positions.
using Bounds = std::array<double, 6>;

// Planes first ("plane<i>", in the scene's order), then the triangle-mesh obstacles (their
// names). A plane's patch is the square of half-width D = the diagonal of `bounds`, centred on
// the projection of the box's centre onto the plane, corners counter-clockwise about the
// normal: it holds the box's shadow on the plane with a margin of at least D/2 on every side
// (a plane is infinite; ParaView needs a finite surface). Planes do not move.
std::vector<OutputObstacle> output_obstacles(const ContactParameters& contact, const Bounds& bounds);

// The displacement at time t of every moving triangle-mesh obstacle (motion other than
// fixed), in output_obstacles' order of those with `moving` set: 3 per vertex.
std::vector<std::vector<double>> obstacle_displacements(const ContactParameters& contact, double t);

}  // namespace dipc
