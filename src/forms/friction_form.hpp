// FrictionForm: lazily lagged IPC friction (Li et al. 2020, §5). At each lag update the
// active contact pairs are frozen with their tangent bases, closest-point weights and normal
// force magnitudes λ_k (from the barrier at the lagged positions); within the lag iteration
//   D(x) = Σ_k μ λ_k f0(‖u_k‖),  u_k = P_kᵀ Γ_k (x − x_n),
// smoothed below the sliding displacement ε_u = ε_v·h, is an ordinary smooth potential that
// Newton minimises together with the others. Built only when μ > 0.
//
// A pair whose slip the last Newton step reversed (friction_potential.hpp: slip_reverses, seen
// in prepare_segment on the line search's segment x -> x + p) gets, in the next Hessian only,
// the isotropic majorizer of its energy in place of its own Hessian: the exact model has no
// curvature along a sliding pair's slip and sends a pair that should stop across the apex,
// which makes the line search cut everyone's step (-dipc_friction_majorize_reversals, on by
// default; docs/performance.md, "Newton iterations on heavy contact steps"). Newton's criterion
// and the energy are unchanged: only the model that chooses the direction differs.
//
// Memory space: the contact form's. On the device the pairs of a lag iteration are uploaded at
// update_lag (cuda/friction_kernels.hpp), with their ext-local node ids again whenever the
// contact set renumbers its extra nodes, and value, gradient, hessian and the reversal test of
// prepare_segment run the kernels, which call the point functions the host loops call.
//
// Pairs are kept by global node ids and evaluated on the rank that evaluates the contact pair,
// so every pair counts once; their nodes stay among the contact form's extra nodes while the
// lag lasts. Obstacle vertices (contact_obstacles.hpp) keep their obstacle ids: their positions
// come from the contact form (at the step's start for x_start), and only the body nodes get
// gradient and Hessian entries, so a moving obstacle drags what rests on it.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "contact/cuda/friction_kernels.hpp"
#include "contact/friction/lagged_friction.hpp"
#include "forms/contact_form.hpp"

namespace dipc {

class FrictionForm : public Form {
 public:
  // μ the friction coefficient; smoothing below ε_u = ε_v · h (h the time step);
  // majorize_reversals: the Hessian of a pair whose slip the last step reversed is its majorizer's.
  FrictionForm(ContactForm& contact, double mu, double eps_v, double h, bool majorize_reversals)
      : contact_(contact), mu_(mu), eps_v_(eps_v), eps_u_(eps_v * h), majorize_reversals_(majorize_reversals) {}
  std::string name() const override { return "friction (lagged)"; }
  MemorySpace memory_space() const override { return contact_.memory_space(); }
  bool value(const double* x, double* energy) override;
  bool gradient(const double* x, double* g) override;
  bool node_groups(std::vector<NodeGroup>* groups) const override;
  bool hessian(const double* x, double* values) override;
  // Marks the pairs whose slip the segment x -> x + p reverses (for the next hessian()).
  void prepare_segment(const double* x, const double* p) override;
  long pattern_version() const override { return pattern_version_; }
  bool pattern_may_change() const override { return true; }
  // Takes effect at the next update_lag (the start of every step).
  void set_time_step(double h) override { eps_u_ = eps_v_ * h; }

  // Freezes the friction pairs at x_lag (the active contact pairs there); x_start holds the
  // positions at the start of the step. Both are local arrays of the potential.
  void update_lag(const double* x_lag, const double* x_start);
  std::size_t num_pairs() const { return pairs_.size(); }
  // Pairs whose next Hessian is their majorizer's (tests).
  std::size_t num_reversing() const;

 private:
  struct Pair {
    int count = 0;                         // 4 (point–triangle, edge–edge) or 1 (point–plane)
    std::array<std::int64_t, 4> global{};  // global node ids
    std::array<double, 12> x_start{};      // their positions at the start of the step
    contact::LaggedPairFriction pair{};
    contact::LaggedPointPlaneFriction plane{};
  };
  bool gather(const Pair& p, const double* x, double* X, std::int32_t* local) const;
  bool on_device() const { return contact_.memory_space() == MemorySpace::device; }
  // Device space: the pairs to the device (update_lag), and their ext-local ids again where the
  // contact set renumbered its nodes since.
  void upload_pairs();
  void refresh_device_nodes();
  const double* device_obstacle_end() const { return contact_.set().device_obstacles().vertex_end.data(); }
  // u of pair p at the gathered positions X.
  void slip(const Pair& p, const double* X, double u[2]) const;

  ContactForm& contact_;
  double mu_, eps_v_, eps_u_;
  bool majorize_reversals_;
  std::vector<Pair> pairs_;
  std::vector<std::uint8_t> reversing_;  // per pair: majorizer in the next Hessian
  long pattern_version_ = 0;
  device::DeviceFrictionPairs device_;
  long device_numbering_ = -1;  // the contact set's numbering_version() of device_.nodes
  device::Reducer reducer_;
};

}  // namespace dipc
