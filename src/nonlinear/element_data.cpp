#include "nonlinear/element_data.hpp"

#include <stdexcept>
#include <string>

namespace dipc {

ElementData::ElementData(const DistributedMesh& mesh, const std::vector<BodyMaterial>& materials)
    : local_to_global(mesh.local_to_global) {
  const int ne = mesh.num_elements();
  nodes.reserve(8 * static_cast<std::size_t>(ne));
  for (const auto& e : mesh.elements) nodes.insert(nodes.end(), e.begin(), e.end());
  reference.reserve(3 * mesh.coordinates.size());
  for (const auto& X : mesh.coordinates) reference.insert(reference.end(), X.begin(), X.end());
  lambda.resize(ne), mu.resize(ne), rho.resize(ne);
  for (int e = 0; e < ne; ++e) {
    const int b = mesh.element_body[e];
    if (b < 0 || b >= static_cast<int>(materials.size()))
      throw std::runtime_error("element " + std::to_string(mesh.element_input_id[e]) +
                               " has body id " + std::to_string(b) + " without a material");
    lambda[e] = materials[b].lambda, mu[e] = materials[b].mu, rho[e] = materials[b].rho;
  }
}

void ElementData::gather_reference(int e, double X[24]) const {
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i) X[3 * a + i] = reference[3 * nodes[8 * static_cast<std::size_t>(e) + a] + i];
}

ElementBlock ElementData::block() const {
  ElementBlock b;
  b.num_elements = num_elements();
  b.nodes = nodes.data();
  b.reference = reference.data();
  b.lambda = lambda.data();
  b.mu = mu.data();
  return b;
}

}  // namespace dipc
