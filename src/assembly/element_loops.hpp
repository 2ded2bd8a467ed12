// CPU loops over a block of hex8 elements: elastic energy, gradient, Hessian values in COO
// order, volume ratios and mass matrices. Each element's material (materials.hpp) and
// volumetric term select the element routine (hex8_elastic). They call the same point functions as the CUDA
// kernels (hex8_elasticity.hpp, hex8_mass.hpp) and know nothing of MPI or PETSc: the caller
// passes local node ids and, for COO patterns, the local-to-global node map.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "math/host_device.hpp"
#include "physics/hex8_mean_dilatation.hpp"
#include "physics/materials.hpp"

namespace dipc {

// Structure-of-arrays view of an element block; nothing owned.
struct ElementBlock {
  int num_elements = 0;
  const std::int32_t* nodes = nullptr;         // 8*num_elements local node ids, element-major
  const double* reference = nullptr;           // 3*num_local_nodes reference coordinates
  const double* lambda = nullptr;              // per element
  const double* mu = nullptr;                  // per element
  const VolumetricTerm* volumetric = nullptr;  // per element; nullptr: all at the Gauss points
  const MaterialModel* model = nullptr;        // per element; nullptr: all neo-Hookean
  DIPC_HD VolumetricTerm volumetric_term(std::int64_t e) const {
    return volumetric ? volumetric[e] : VolumetricTerm::gauss_points;
  }
  DIPC_HD MaterialModel material_model(std::int64_t e) const { return model ? model[e] : MaterialModel::neo_hookean; }
};

// Elements [first, first + count) of a block, as a block of their own (its node ids index the
// same local arrays).
inline ElementBlock element_range(const ElementBlock& block, int first, int count) {
  ElementBlock r = block;
  r.num_elements = count;
  r.nodes = block.nodes + 8 * static_cast<std::int64_t>(first);
  r.lambda = block.lambda + first;
  r.mu = block.mu + first;
  if (block.volumetric) r.volumetric = block.volumetric + first;
  if (block.model) r.model = block.model + first;
  return r;
}

// Thrown when a global dof id does not fit PETSc's 32-bit index (3*global_node + 2 > 2^31-1).
class DofIndexOverflow : public std::overflow_error {
 public:
  using std::overflow_error::overflow_error;
};

// Entries per element of the elastic COO pattern (a dense 24x24 block).
constexpr int kElasticCooPerElement = 576;

// Where Hessian entry H_(3a+k)(3b+l) (node a, component k; node b, component l) sits among an
// element's 576 COO values: column-block (k, l, b) major, row node a fastest. The CUDA kernel
// gives row node a to thread a, so for each (k, l, b) the element's 8 threads store 8
// consecutive doubles (two full 32-byte sectors) instead of 8 values 576 bytes apart; the
// row-major 24x24 order made the kernel bound by L2 write sectors (ncu, README "GPU").
DIPC_HD constexpr int elastic_coo_offset(int a, int k, int b, int l) { return 8 * (24 * k + 8 * l + b) + a; }
// Entries per element of the consistent mass COO pattern (8x8 node pairs x 3 components).
constexpr int kMassCooPerElement = 192;

// How an element form lays out its Hessian values, 8x8 node blocks per element: the potential
// sums them into the matrix through a map over node blocks (nonlinear/node_block_reduction.hpp)
// and computes where entry (a, i; b, j) of an element lies instead of storing it per entry.
enum class ElementLayout : std::uint8_t {
  elastic,          // 576 values per element at elastic_coo_offset: every block a dense 3x3
  consistent_mass,  // 192 values per element, 3(8a + b) + i: M_ab on the block's diagonal only
};
DIPC_HD constexpr int element_values(ElementLayout layout) {
  return layout == ElementLayout::elastic ? kElasticCooPerElement : kMassCooPerElement;
}
// Which of a node block's 9 entries (bit 3i + j) the layout writes.
DIPC_HD constexpr unsigned element_block_mask(ElementLayout layout) {
  return layout == ElementLayout::elastic ? 0x1FFu : 0x111u;
}
// Offset of entry (node a, component i; node b, component j) among an element's values, or -1
// where the layout has none (the mass's off-diagonal components).
DIPC_HD constexpr int element_value_offset(ElementLayout layout, int a, int i, int b, int j) {
  return layout == ElementLayout::elastic ? elastic_coo_offset(a, i, b, j) : (i == j ? 3 * (8 * a + b) + i : -1);
}

// x holds 3 current coordinates per local node. Functions returning bool return false as
// soon as an element has det F <= 0 at a quadrature point; their outputs are then partial
// and must be discarded.

// Sum of the element energies.
bool elastic_energy(const ElementBlock& block, const double* x, double* energy);
// Adds the element gradients into g (3 per local node).
bool elastic_gradient(const ElementBlock& block, const double* x, double* g);
// Writes 576 PSD-projected Hessian values per element (element-major, each element's in the
// order of elastic_coo_offset) into coo_values, in the order of elastic_coo_pattern.
bool elastic_hessian(const ElementBlock& block, const double* x, double* coo_values);
// All three in one pass (one geometry evaluation per quadrature point): energy is
// overwritten with the sum, g added into, coo_values written as above.
bool elastic_energy_gradient_hessian(const ElementBlock& block, const double* x, double* energy, double* g,
                                     double* coo_values);

// As elastic_hessian, but the rank-one volumetric term f''_e b_e b_e^T of every mean-dilatation
// element is left out of its 576 values and returned instead: b_e = dv_e/dx (24 per element, in
// the element's dof order 3a + i) into volume_gradients[24e ...] and f''_e (>= 0, projected)
// into volume_curvatures[e]; zero for elements with the volumetric term at the Gauss points,
// whose values are complete. For the mixed u-p linear solve (nonlinear/mixed_linear_solve.hpp).
bool elastic_hessian_split(const ElementBlock& block, const double* x, double* coo_values, double* volume_gradients,
                           double* volume_curvatures);
// Reference volume of every element (sum of the 2x2x2-point weights times |J0|).
void reference_volumes(const ElementBlock& block, double* volumes);

// Resizes rows/cols to 576*num_elements and fills them with the global dof ids of the
// entries written by elastic_hessian: entry 576e + elastic_coo_offset(a, i, b, j) is
// (3*l2g[node_a]+i, 3*l2g[node_b]+j). Throws DofIndexOverflow if an id exceeds int32.
void elastic_coo_pattern(const ElementBlock& block, const std::int64_t* local_to_global,
                         std::vector<std::int32_t>* rows, std::vector<std::int32_t>* cols);

// Minimum volume ratio (hex8_min_volume_ratio) over all elements; per element too when
// per_element != nullptr. Returns +huge for an empty block.
double min_volume_ratio(const ElementBlock& block, const double* x, double* per_element);

// Adds the row-sum lumped masses into node_mass (one per local node); rho per element.
void lumped_mass(const ElementBlock& block, const double* rho, double* node_mass);
// Writes 192 values per element in the order of consistent_mass_coo_pattern: entry
// 192e + 3(8a + b) + c holds M_ab (the scalar consistent mass, hex8_consistent_mass) for the
// dof pair (3*l2g[node_a]+c, 3*l2g[node_b]+c), i.e. the 8x8 block expanded to M (x) I_3.
void consistent_mass_values(const ElementBlock& block, const double* rho, double* coo_values);
// Resizes rows/cols to 192*num_elements and fills them in the order above. Throws
// DofIndexOverflow if an id exceeds int32.
void consistent_mass_coo_pattern(const ElementBlock& block, const std::int64_t* local_to_global,
                                 std::vector<std::int32_t>* rows, std::vector<std::int32_t>* cols);

}  // namespace dipc
