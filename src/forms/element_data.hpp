// ElementData: this rank's element block in structure-of-arrays form (connectivity,
// reference coordinates, per-element material), owned storage behind the non-owning
// assembly::ElementBlock view that the element loops (and later the CUDA kernels) take.
#pragma once
#include <petscsys.h>

#include <cstdint>
#include <vector>

#include "assembly/element_loops.hpp"
#include "forms/form.hpp"
#include "forms/problem.hpp"
#include "partition/distributed_mesh.hpp"

namespace dipc {

struct ElementData {
  std::vector<std::int32_t> nodes;  // 8 per element
  std::vector<double> reference;    // 3 per local node
  std::vector<double> lambda, mu, rho;
  std::vector<VolumetricTerm> volumetric;  // per element
  std::vector<MaterialModel> model;        // per element; empty when all are neo-Hookean
  std::vector<std::int64_t> local_to_global;

  // skip_body[b] (optional): leave out the elements of body b (kinematic bodies, whose nodes are
  // all prescribed, contribute nothing to the elastic energy's minimisation). Throws for a body
  // whose material combines mean dilatation with a model other than neo-Hookean.
  ElementData(const DistributedMesh& mesh, const std::vector<BodyMaterial>& materials,
              const std::vector<char>& skip_body = {});
  ElementBlock block() const;
  // Reference coordinates of element e's nodes, X[3a + i].
  void gather_reference(int e, double X[24]) const;
  int num_elements() const { return static_cast<int>(lambda.size()); }
  // COO patterns (global dof ids) of the elastic Hessian (576 per element) and of the
  // consistent mass (192 per element), in the orders of element_loops.hpp; the host and the
  // device forms share them.
  void elastic_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) const;
  void consistent_mass_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) const;
  // The same patterns as node blocks (form.hpp), for Form::element_pattern.
  ElementPattern pattern(ElementLayout layout) const {
    return {num_elements(), nodes.data(), local_to_global.data(), layout};
  }
};

}  // namespace dipc
