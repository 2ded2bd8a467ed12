// Form: one term of the incremental potential E(x) (docs/design.md §3, "The Form contract").
//
// Forms see this rank's *local* nodal arrays (owned nodes then ghosts, 3 values per node,
// see partition/distributed_mesh.hpp); IncrementalPotential gathers x once per evaluation,
// sums the forms and scatters gradients back to the owners once. Each contribution must be
// counted exactly once over all ranks: element terms loop over this rank's elements (each
// element lives on one rank), nodal terms over owned nodes only.
//
// A form carries its own scale (h² for elastic and body terms in implicit Euler), so the
// potential is the plain sum of its forms.
//
// Memory spaces. A form evaluates either on the host or on the CUDA device (memory_space()).
// The evaluations — value, gradient, hessian, is_valid, max_step — receive x, p, g and the
// Hessian values in the form's own space; the potential copies a local array across at most
// once per evaluation, whatever the number of forms. prepare_segment also receives x and p in
// the form's space (the potential keeps the segment in every space its forms use), so a device
// form can search its segment on the device. The other hooks (begin_step, begin_iteration,
// update_extra_nodes, update_pattern), called once per step or Newton iteration, always receive
// host arrays.
#pragma once
#include <petscsys.h>

#include <cstdint>
#include <string>
#include <vector>

#include "assembly/hessian_pattern.hpp"
#include "device/memory_space.hpp"

namespace dipc {

class VolumetricSplit;  // volumetric_split.hpp

// The Hessian's pattern (coo_pattern, element_pattern, element_hessian, update_pattern,
// pattern_version, pattern_may_change) is the part of a form the matrix assembler sees
// (assembly/hessian_pattern.hpp).
class Form : public HessianPattern {
 public:
  virtual ~Form() = default;
  virtual std::string name() const = 0;
  virtual MemorySpace memory_space() const { return MemorySpace::host; }

  // This rank's contribution to E at x. Returns false if x is not admissible for this
  // form (an inverted element), in which case E(x) = +inf.
  virtual bool value(const double* x, double* energy) = 0;
  // Adds ∂E/∂x into g (3 per local node). Returns false as value().
  virtual bool gradient(const double* x, double* g) = 0;
  // Writes the Hessian values in coo_pattern() order (HessianPattern). Returns false as value().
  virtual bool hessian(const double* x, double* values) = 0;

  // Largest step fraction α ∈ (0, 1] along p that this form allows from x (CCD for
  // contact). 1 for forms without such a limit.
  virtual double max_step(const double* x, const double* p) { return 1.0; }
  // True for forms whose max_step can be below 1 (contact): without any, the potential skips
  // the bound and its reduction over the ranks.
  virtual bool limits_step() const { return false; }
  // False if x must be rejected outright (an inverted element at a corner or quadrature
  // point), whatever the energy says.
  virtual bool is_valid(const double* x) { return true; }
  // Forms over elements: the smallest volume ratio (det F at the corners and Gauss points,
  // hex8_min_volume_ratio) of their elements at x, in the form's space, into *ratio (+huge for
  // none). False for forms without elements. The step report's J_min, without a pass over the
  // mesh on the host in device runs.
  virtual bool min_volume_ratio(const double* x, double* ratio) { return false; }
  // Hooks: start of a time step (x̂ = predicted positions, local array) and of a Newton
  // iteration.
  virtual void begin_step(const double* x_hat) {}
  // The time step h changed (step recovery halves it, then lets it grow back): forms whose
  // definition holds h (h²Ψ, h²fᵀx, friction's ε_v·h) rescale. Never called in static solves,
  // whose potential has no h.
  virtual void set_time_step(double h) {}
  // Returns true if the form changed its own definition (e.g. the barrier stiffness), so that
  // the gradient at x must be evaluated again.
  virtual bool begin_iteration(const double* x) { return false; }
  // Forms that PSD-project their Hessian term by term (contact: each pair's barrier Hessian)
  // write the unprojected terms while `exact` is set, until it is cleared, and return true; the
  // others ignore it and return false. NewtonSolver sets it where the projection would slow
  // Newton down (newton_solver.hpp, -dipc_contact_exact_hessian); energy and gradient are the
  // same either way.
  virtual bool set_exact_hessian(bool exact) { return false; }

  // --- Forms that reach beyond the mesh's local nodes (contact across ranks) ---------------
  // Global ids of nodes this form needs in addition to the mesh's local nodes; the potential
  // appends them to the local arrays in this order (nullptr: none).
  virtual const std::vector<std::int64_t>* extra_nodes() const { return nullptr; }
  // Collective. Called before the potential is evaluated anywhere on the segment x + αp,
  // α ∈ [0, 1] (p = 0 at the start of a step), with arrays over the current local nodes. The
  // form decides which remote data it needs for that segment; returns true if extra_nodes()
  // changed, after which the potential re-gathers and calls prepare_segment again.
  virtual bool update_extra_nodes(const double* x, const double* p) { return false; }
  // Called once the arrays cover extra_nodes(), with x and p in the form's memory space: the
  // form finds what it will evaluate along the segment (contact: candidate pairs).
  virtual void prepare_segment(const double* x, const double* p) {}

  // --- A stiff volumetric part kept out of the Hessian (mixed_linear_solve.hpp) -------------
  // Forms whose Hessian holds mean-dilatation elements' rank-one volumetric terms and can hand
  // them over (volumetric_split.hpp); nullptr for the others.
  virtual VolumetricSplit* volumetric_split() { return nullptr; }
};

}  // namespace dipc
