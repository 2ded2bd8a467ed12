// ContactForm: IPC's barrier potential B(x) = κ Σ_k w_k b(d_k(x)) over the contact pairs of the
// whole (distributed) surface — point–triangle, edge–edge (mollified near parallel edges),
// point–plane for half-space obstacles, and the point–triangle and edge–edge pairs between the
// bodies and triangle-mesh obstacles — with its CCD step bound (Li et al. 2020, §4). A thin
// Form over a ContactSet (contact_set.hpp), which holds which pairs this rank evaluates (owned
// and ghost surface, candidates, active set and pattern, weights, obstacles); the form holds
// the stiffness κ, evaluates the pairs (contact/contact_pair_terms.hpp on the host, the kernels
// of contact/cuda/contact_kernels.hpp on the device) and keeps their device lists.
//
// Matrix pattern. The Hessian's COO pattern holds the pairs active at the last update_pattern;
// with -dipc_pattern_remap candidates the matrix reserves the blocks of every candidate pair as well
// (reserved_blocks), so that a new active set within the candidates is mapped onto the matrix's
// entries and only one outside them makes a new matrix (a new matrix was 1.6 s at 64,000 hexes
// on 2 cores, 0.54 s per Newton iteration at 1M on one H200, and a new preconditioner setup
// each time; assembly/reserved_blocks.hpp). Vertex–plane pairs
// are exempt: every owned surface vertex is paired with every plane for the whole run, and all
// those pairs are in the pattern from the first matrix on, writing zeros while inactive. Their
// 3×3 blocks lie on their vertex's diagonal block, which the elastic pattern already holds, so
// the matrix's nonzeros are the same and only vertex–triangle and edge–edge contacts change the
// pattern. An inactive pair's barrier is exactly zero, so values are unchanged; the cost is
// evaluating surface vertices × planes pairs, a small part of the broad phase's work.
//
// Memory space. On the host (the default) every evaluation loops over the pairs on the CPU. On
// the device the broad phase runs there too (ContactSet), prepare_segment, which then receives
// device arrays, has the pair list described there from the candidates' indices
// (ContactSet::describe_on_device), and value, gradient, hessian and max_step run the CUDA
// kernels on device arrays; both spaces call the same point functions. update_extra_nodes
// receives host arrays in both spaces; update_pattern receives x on the host and, where the
// potential has it there, on the device, where the device form flags the active candidates
// (and uploads the pattern's pairs when they change). The queries min_distance, active_pairs
// and the set's count_intersections stay on the CPU.
// Both spaces search every pair's time of impact on [0, 1] and take the minimum, so the step
// bound is the same bit for bit on the host and the device, and does not depend on the order
// of the pairs (which differs between rank counts). Searching up to the running minimum
// instead would end some searches sooner, but the bound would then depend on that order.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "contact/cuda/contact_kernels.hpp"
#include "contact/distributed/contact_parameters.hpp"
#include "contact/distributed/contact_set.hpp"
#include "forms/form.hpp"
#include "partition/distributed_mesh.hpp"

namespace dipc {

struct ContactPairTerms;

class ContactForm : public Form {
 public:
  using PairInfo = ContactSet::PairInfo;
  // space: where value, gradient, hessian and max_step run (and where their arrays live).
  // MemorySpace::device throws device::DeviceError when no CUDA device is available.
  // nodal (optional): the caller's halo exchange of the mesh's nodes, for the set's rest areas.
  ContactForm(const DistributedMesh& mesh, ContactParameters parameters, MemorySpace space = MemorySpace::host,
              const GhostExchange* nodal = nullptr);
  // The set refers to parameters_ and stats_: the form stays where it was built.
  ContactForm(const ContactForm&) = delete;
  ContactForm& operator=(const ContactForm&) = delete;
  std::string name() const override { return "contact barrier"; }
  MemorySpace memory_space() const override { return space_; }
  bool value(const double* x, double* energy) override;
  bool gradient(const double* x, double* g) override;
  bool node_groups(std::vector<NodeGroup>* groups) const override;
  bool hessian(const double* x, double* values) override;
  double max_step(const double* x, const double* p) override;
  const std::vector<std::int64_t>* extra_nodes() const override { return &set_.extra_nodes(); }
  bool update_extra_nodes(const double* x, const double* p) override;
  void prepare_segment(const double* x, const double* p) override;
  void update_pattern(const double* x, const double* x_device) override;
  long pattern_version() const override { return set_.pattern_version(); }
  bool pattern_may_change() const override { return true; }
  void reserved_blocks(std::vector<std::array<std::int64_t, 2>>* blocks) const override {
    set_.reserved_blocks(blocks);
  }
  bool limits_step() const override { return true; }
  bool set_exact_hessian(bool exact) override {
    exact_hessian_ = exact;
    return true;
  }

  // The pairs: surface, candidates, active set, obstacles, node ids, diagnostics.
  ContactSet& set() { return set_; }
  const ContactSet& set() const { return set_; }

  double kappa() const { return parameters_.kappa; }
  void set_kappa(double kappa) { parameters_.kappa = kappa; }
  // Bounds of the adaptive stiffness (IPC supplement): κ_min from the average nodal mass,
  // κ_max = 100 κ_min. Collective.
  void set_kappa_bounds(double average_mass, double bbox_diagonal);
  double kappa_min() const { return kappa_min_; }
  double kappa_max() const { return kappa_max_; }
  // IPC's "tiny distance" threshold ε_d² = (1e-9 L)² of the stiffness update.
  double min_distance_threshold2() const { return min_distance_eps2_; }
  bool kappa_adaptive() const { return parameters_.kappa_adaptive; }
  // Smallest distance (unsquared) over this rank's candidate pairs at x (and ∞ without pairs).
  double min_distance(const double* x) const;
  const ContactStats& stats() const { return stats_; }
  void reset_stats() { stats_ = ContactStats{}; }
  double dhat() const { return parameters_.dhat; }
  const ContactParameters& parameters() const { return parameters_; }

  // Pairs active at x (d < d̂), for friction; `first_global` tells pairs apart across exchanges.
  struct ActivePair {
    PairInfo info;
    std::int64_t first_global;
  };
  std::vector<ActivePair> active_pairs(const double* x) const;
  // The pair lists the device kernels read, built on the host threads (each pair in its own
  // slot, so the same list for any number of threads): every candidate pair in the set's order,
  // and the active pairs of the Hessian's pattern in theirs.
  device::ContactPairList candidate_pair_list() const;
  device::ContactPairList pattern_pair_list() const;
  // Device space: the candidates' device list of the last prepare_segment, which the set
  // describes on the device (ContactSet::describe_on_device) as candidate_pair_list() uploaded.
  const device::DeviceContactPairs& device_candidates() const { return device_candidates_; }
  // This rank's active pairs at x per CandidateKind, indexed by its value (output: the per-step
  // contact counts).
  static constexpr int num_pair_kinds = kNumCandidateKinds;
  static const char* pair_kind_name(int kind);  // kind: a CandidateKind's value
  std::array<long, num_pair_kinds> active_pair_counts(const double* x) const;
  // Squared distance of a pair whose stacked node positions are X (3 per node of info.nodes).
  static double squared_distance(const PairInfo& info, const double* X);

 private:
  static MemorySpace checked_space(MemorySpace space);  // throws DeviceError without a device
  bool terms(const PairInfo& info, const double* x, bool want_g, bool want_H, bool* active, ContactPairTerms* t) const;
  void set_pair(device::ContactPairList* list, std::size_t slot, const PairInfo& info) const;
  device::BarrierConstants barrier_constants() const;

  ContactParameters parameters_;
  MemorySpace space_;
  ContactStats stats_;
  ContactSet set_;  // after parameters_ and stats_, which it refers to
  // Device space: the candidates and the pattern's pairs (and the host copy they were uploaded
  // from, to upload only changes), and the reducer that brings scalars back.
  device::DeviceContactPairs device_candidates_, device_pattern_;
  device::ContactPairList uploaded_pattern_;
  // update_pattern on the device: the candidates' active flags there and their host copy.
  device::Array<std::int32_t> device_active_{"contact active flags"};
  std::vector<std::int32_t> active_flags_;
  device::Reducer reducer_;
  double kappa_min_ = 0, kappa_max_ = 0;
  double min_distance_eps2_ = 0;
  bool exact_hessian_ = false;  // set_exact_hessian: pairs' Hessians unprojected for now
};

}  // namespace dipc
