// VolumetricSplit: a form's stiff volumetric part, kept out of its Hessian for the mixed u-p
// linear solve (nonlinear/mixed_linear_solve.hpp). Only that solve needs it, so it is an
// interface of its own, reached through Form::volumetric_split(), rather than more of Form.
//
// Forms whose Hessian holds rank-one terms d_e b_e b_eᵀ with d_e ~ lambda / V_e (mean-dilatation
// elements, physics/hex8_mean_dilatation.hpp) may hand them over: after split_volumetric(),
// hessian() leaves them out (same pattern) and volumetric_part() holds b_e and d_e at the state
// of the last hessian().
#pragma once
#include <petscsys.h>

#include <cstdint>
#include <vector>

namespace dipc {

// The stiff volumetric part of a Hessian kept apart as rank-one terms d_e b_e b_eᵀ, one row per
// mean-dilatation element of this rank (hex8_mean_dilatation.hpp, mixed_linear_solve.hpp).
struct VolumetricPart {
  int rows = 0;
  std::vector<std::int32_t> local_dofs;  // 24 per row: 3 * local node + component
  std::vector<PetscInt> global_dofs;     // 24 per row
  std::vector<double> gradient;          // 24 per row: b_e = dv_e/dx at the last hessian()
  std::vector<double> curvature;         // per row: d_e = the form's scale times f''_e (>= 0)
  std::vector<double> weight;            // per row: V_e / (scale mu_e), the pressure mass over the shear modulus
};

class VolumetricSplit {
 public:
  // Largest lambda / mu among the elements whose terms can be split.
  virtual double split_stiffness_ratio() const = 0;
  // From now on hessian() leaves the volumetric terms out (same pattern); a second call changes nothing.
  virtual void split_volumetric() = 0;
  // The split terms at the state of the last hessian() (nullptr before split_volumetric()).
  virtual const VolumetricPart* volumetric_part() const = 0;

 protected:
  ~VolumetricSplit() = default;  // not owned through this interface: the form is
};

}  // namespace dipc
