#include "forms/element_data.hpp"

#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace dipc {

ElementData::ElementData(const DistributedMesh& mesh, const std::vector<BodyMaterial>& materials,
                         const std::vector<char>& skip_body)
    : local_to_global(mesh.local_to_global) {
  reference.reserve(3 * mesh.coordinates.size());
  for (const auto& X : mesh.coordinates) reference.insert(reference.end(), X.begin(), X.end());
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const int b = mesh.element_body[e];
    if (b < 0 || b >= static_cast<int>(materials.size()))
      throw std::runtime_error("element " + std::to_string(mesh.element_input_id[e]) + " has body id " +
                               std::to_string(b) + " without a material");
    if (b < static_cast<int>(skip_body.size()) && skip_body[b]) continue;
    if (materials[b].volumetric == VolumetricTerm::mean_dilatation && materials[b].model != MaterialModel::neo_hookean)
      throw std::runtime_error("body " + std::to_string(b) + ": the mean-dilatation element is neo-Hookean only, not " +
                               std::string(material_model_name(materials[b].model)));
    nodes.insert(nodes.end(), mesh.elements[e].begin(), mesh.elements[e].end());
    lambda.push_back(materials[b].lambda), mu.push_back(materials[b].mu), rho.push_back(materials[b].rho);
    volumetric.push_back(materials[b].volumetric);
    model.push_back(materials[b].model);
  }
  // All neo-Hookean: no per-element material, so that the element loops and kernels run
  // their variant without per-element dispatch (block().model null).
  bool all_neo_hookean = true;
  for (MaterialModel m : model) all_neo_hookean = all_neo_hookean && m == MaterialModel::neo_hookean;
  if (all_neo_hookean) model.clear();
}

void ElementData::gather_reference(int e, double X[24]) const {
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i) X[3 * a + i] = reference[3 * nodes[8 * static_cast<std::size_t>(e) + a] + i];
}

namespace {
void to_petsc(std::vector<std::int32_t>&& r, std::vector<std::int32_t>&& c, std::vector<PetscInt>* rows,
              std::vector<PetscInt>* cols) {
  if constexpr (std::is_same_v<PetscInt, std::int32_t>) {
    *rows = std::move(r), *cols = std::move(c);  // no copy of the (large) element patterns
  } else {
    rows->assign(r.begin(), r.end());
    cols->assign(c.begin(), c.end());
  }
}
}  // namespace

void ElementData::elastic_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) const {
  std::vector<std::int32_t> r, c;
  elastic_coo_pattern(block(), local_to_global.data(), &r, &c);
  to_petsc(std::move(r), std::move(c), rows, cols);
}

void ElementData::consistent_mass_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) const {
  std::vector<std::int32_t> r, c;
  consistent_mass_coo_pattern(block(), local_to_global.data(), &r, &c);
  to_petsc(std::move(r), std::move(c), rows, cols);
}

ElementBlock ElementData::block() const {
  ElementBlock b;
  b.num_elements = num_elements();
  b.nodes = nodes.data();
  b.reference = reference.data();
  b.lambda = lambda.data();
  b.mu = mu.data();
  b.volumetric = volumetric.data();
  b.model = model.empty() ? nullptr : model.data();
  return b;
}

}  // namespace dipc
