// BodyForceForm: −scale · fᵀx for a constant acceleration field g (gravity): the nodal force
// f_i = m_i g uses the lumped (row-sum) mass, which integrates ρ g N_i exactly for constant g.
// Linear in x, so its Hessian is empty.
#pragma once
#include <array>
#include <memory>

#include "forms/device_form_parts.hpp"
#include "forms/form.hpp"

namespace dipc {

// scale · m_i g for the first num_owned_nodes nodes, 3 per node (shared by the device form).
std::vector<double> scaled_body_forces(const std::vector<double>& node_mass, int num_owned_nodes,
                                       const std::array<double, 3>& acceleration, double scale);

class BodyForceForm : public Form {
 public:
  // space: where value and gradient run (device: through a DeviceBodyForcePart).
  BodyForceForm(const std::vector<double>& node_mass, int num_owned_nodes, const std::array<double, 3>& acceleration,
                double scale, MemorySpace space = MemorySpace::host);
  std::string name() const override { return "body force"; }
  MemorySpace memory_space() const override { return device_ ? MemorySpace::device : MemorySpace::host; }
  bool value(const double* x, double* energy) override;
  bool gradient(const double* x, double* g) override;
  void coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) override;
  bool hessian(const double*, double*) override { return true; }
  void set_time_step(double h) override;

 private:
  std::vector<double> node_mass_;  // owned nodes
  std::array<double, 3> acceleration_;
  std::vector<double> force_;                    // scale · m_i g, owned nodes, 3 per node
  std::unique_ptr<DeviceBodyForcePart> device_;  // device space only
};

}  // namespace dipc
