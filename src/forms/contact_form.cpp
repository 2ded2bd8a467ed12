// ContactForm (contact_form.hpp): κ and its bounds, the device pair lists, and the Form
// evaluations (value, gradient, Hessian, CCD step bound) on the host and the device over the
// pairs of its ContactSet; the active-pair queries for friction and the step reports.
#include "forms/contact_form.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "contact/contact_pair_terms.hpp"
#include "contact/geometry/barrier.hpp"
#include "logging/log_stages.hpp"
#include "threads/host_threads.hpp"

namespace dipc {

MemorySpace ContactForm::checked_space(MemorySpace space) {
  if (space == MemorySpace::device && device::device_count() == 0)
    throw device::DeviceError(device::built_with_cuda()
                                  ? "contact barrier on the device: no CUDA device is visible to this process"
                                  : "contact barrier on the device: dipc was built without CUDA "
                                    "(configure with -DDIPC_WITH_CUDA=ON)");
  return space;
}

ContactForm::ContactForm(const DistributedMesh& mesh, ContactParameters parameters, MemorySpace space,
                         const GhostExchange* nodal)
    : parameters_(std::move(parameters)),
      space_(checked_space(space)),
      set_(mesh, parameters_, space_, &stats_, nodal) {}

void ContactForm::set_kappa_bounds(double average_mass, double bbox_diagonal) {
  // IPC supplement (adaptive barrier stiffness): κ_min makes the barrier's stiffness at a
  // tiny distance d₀ = (1e-8 L)² comparable to the inertia of an average node,
  // κ_min = 1e11 · m̄ / (4 d₀ b''(d₀)), and κ_max = 100 κ_min. dipc's barrier is weighted by
  // rest vertex areas, so a node's barrier stiffness is κ Ā b'': the mass is taken per unit
  // area, m̄ / Ā (Ā the average vertex area), which keeps κ_min independent of the mesh size.
  const double average_area = set_.average_vertex_area();
  const double dhat2 = parameters_.dhat * parameters_.dhat;
  double d0 = 1e-8 * bbox_diagonal;
  d0 *= d0;
  if (d0 >= dhat2) d0 = 0.5 * dhat2;
  kappa_min_ = 1e11 * (average_mass / average_area) / (4.0 * d0 * contact::barrier_second_derivative(d0, dhat2));
  kappa_max_ = 100.0 * kappa_min_;
  min_distance_eps2_ = (1e-9 * bbox_diagonal) * (1e-9 * bbox_diagonal);
  if (parameters_.kappa_adaptive && parameters_.kappa < kappa_min_) parameters_.kappa = kappa_min_;
}

bool ContactForm::update_extra_nodes(const double* x, const double* p) {
  EventScope event(log_events().ghost_surfaces);
  return set_.exchange_ghosts(x, p);
}

void ContactForm::prepare_segment(const double* x, const double* p) {
  {
    EventScope event(log_events().broad_phase);
    set_.find_candidates(x, p);
  }
  if (space_ != MemorySpace::device) return;
  EventScope event(log_events().pair_lists);
  const double start = MPI_Wtime();
  set_.describe_on_device(&device_candidates_);
  stats_.transfer_seconds += MPI_Wtime() - start;
}

device::ContactPairList ContactForm::candidate_pair_list() const {
  device::ContactPairList list;
  list.resize(set_.candidate_starts()[kNumCandidateKinds]);
  set_.for_each_pair_slot(
      [&](CandidateKind kind, std::size_t i, std::size_t slot) { set_pair(&list, slot, set_.describe(kind, i)); });
  return list;
}

device::ContactPairList ContactForm::pattern_pair_list() const {
  const auto& pairs = set_.pattern_pairs();
  device::ContactPairList list;
  list.resize(pairs.size());
  parallel_for(pairs.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) set_pair(&list, k, set_.describe(pairs[k].kind, pairs[k].index));
  });
  return list;
}

bool ContactForm::node_groups(std::vector<NodeGroup>* groups) const {
  groups->resize(set_.num_pattern_groups());
  parallel_for(groups->size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      NodeGroup& g = (*groups)[k];
      g.count = set_.pattern_group(k, g.node.data());
    }
  });
  return true;
}

void ContactForm::update_pattern(const double* x, const double* x_device) {
  {
    EventScope event(log_events().active_set);
    if (space_ == MemorySpace::device && x_device) {
      // The flags of the device candidates (the set's candidates in its order), computed by the
      // same point function as terms() below, so the same set bit for bit.
      const std::array<std::size_t, kNumCandidateKinds + 1> first = set_.candidate_starts();
      const std::size_t n = first[kNumCandidateKinds];
      if (device_candidates_.count != n)
        throw std::logic_error("ContactForm::update_pattern: the device holds " +
                               std::to_string(device_candidates_.count) + " candidate pairs, the set " +
                               std::to_string(n) + " (prepare_segment must follow every broad phase)");
      device_active_.resize(n);
      device::contact_active_flags(device_candidates_, set_.device_obstacles(), barrier_constants(), x_device,
                                   device_active_.data(), reducer_);
      active_flags_.resize(n);
      device_active_.download(active_flags_.data());
      set_.update_pattern([&](CandidateKind kind, std::size_t i) {
        return active_flags_[first[static_cast<int>(kind)] + i] != 0;
      });
    } else {
      set_.update_pattern([&](CandidateKind kind, std::size_t i) {
        bool active;
        ContactPairTerms t;
        terms(set_.describe(kind, i), x, false, false, &active, &t);
        return active;
      });
    }
  }
  if (space_ != MemorySpace::device) return;
  EventScope event(log_events().pair_lists);
  // The pattern's device list also changes when exchanges renumber its nodes, so compare the
  // list itself, not only the key.
  const double start = MPI_Wtime();
  device::ContactPairList list = pattern_pair_list();
  if (list != uploaded_pattern_) {
    device_pattern_.upload(list);
    uploaded_pattern_ = std::move(list);
  }
  stats_.transfer_seconds += MPI_Wtime() - start;
}

bool ContactForm::terms(const PairInfo& info, const double* x, bool want_g, bool want_H, bool* active,
                        ContactPairTerms* t) const {
  double X[12];
  set_.gather(x, info, X);
  return contact_pair_terms(info.kind, X, info.plane_point(), info.plane_normal(), parameters_.dhat * parameters_.dhat,
                            parameters_.kappa, info.weight, info.eps_x, want_g, want_H,
                            parameters_.project_hessian && !exact_hessian_, active, t);
}

void ContactForm::set_pair(device::ContactPairList* list, std::size_t slot, const PairInfo& info) const {
  list->set(slot, info.kind, info.nodes.data(), info.weight, info.eps_x,
            info.plane ? static_cast<int>(info.plane - parameters_.planes.data()) : -1);
}

device::BarrierConstants ContactForm::barrier_constants() const {
  device::BarrierConstants c;
  c.dhat2 = parameters_.dhat * parameters_.dhat;
  c.kappa = parameters_.kappa;
  c.project = parameters_.project_hessian && !exact_hessian_;
  return c;
}

bool ContactForm::value(const double* x, double* energy) {
  const double start = MPI_Wtime();
  if (space_ == MemorySpace::device) {
    const bool ok = device::contact_barrier_energy(device_candidates_, set_.device_obstacles(), barrier_constants(), x,
                                                   reducer_, energy);
    stats_.barrier_seconds += MPI_Wtime() - start;
    return ok;
  }
  double e = 0;
  const bool ok = set_.for_each_pair([&](CandidateKind kind, std::size_t i) {
    bool active;
    ContactPairTerms t;
    if (!terms(set_.describe(kind, i), x, false, false, &active, &t)) return false;
    e += t.energy;
    return true;
  });
  *energy = e;
  stats_.barrier_seconds += MPI_Wtime() - start;
  return ok;
}

bool ContactForm::gradient(const double* x, double* g) {
  const double start = MPI_Wtime();
  if (space_ == MemorySpace::device) {
    const bool ok = device::add_contact_barrier_gradient(device_candidates_, set_.device_obstacles(),
                                                         barrier_constants(), x, g, reducer_);
    stats_.barrier_seconds += MPI_Wtime() - start;
    return ok;
  }
  const bool ok = set_.for_each_pair([&](CandidateKind kind, std::size_t i) {
    const PairInfo info = set_.describe(kind, i);
    bool active;
    ContactPairTerms t;
    if (!terms(info, x, true, false, &active, &t)) return false;
    if (!active) return true;
    for (int k = 0; k < info.count; ++k)
      if (!is_obstacle_node(info.nodes[k]))
        for (int c = 0; c < 3; ++c) g[3 * info.nodes[k] + c] += t.g[3 * k + c];
    return true;
  });
  stats_.barrier_seconds += MPI_Wtime() - start;
  return ok;
}

bool ContactForm::hessian(const double* x, double* values) {
  const double start = MPI_Wtime();
  if (space_ == MemorySpace::device) {
    const bool ok = device::contact_barrier_hessian(device_pattern_, set_.device_obstacles(), barrier_constants(), x,
                                                    values, reducer_);
    stats_.barrier_seconds += MPI_Wtime() - start;
    return ok;
  }
  std::size_t offset = 0;
  bool ok = true;
  for (const auto& pe : set_.pattern_pairs()) {
    const PairInfo info = set_.describe(pe.kind, pe.index);
    int slots[4];
    const int n = 3 * body_slots(info.nodes.data(), info.count, slots);
    bool active;
    ContactPairTerms t;
    ok = terms(info, x, true, true, &active, &t) && ok;
    if (active)
      body_block(t.H, info.count, slots, n / 3, values + offset);
    else
      std::fill(values + offset, values + offset + n * n, 0.0);
    offset += static_cast<std::size_t>(n) * n;
  }
  stats_.barrier_seconds += MPI_Wtime() - start;
  return ok;
}

double ContactForm::max_step(const double* x, const double* p) {
  EventScope event(log_events().ccd);
  const double start = MPI_Wtime();
  double t = 1.0;
  if (space_ == MemorySpace::device) {
    t = device::contact_min_time_of_impact(device_candidates_, set_.device_obstacles(), x, p, 1.0, reducer_);
  } else {
    // Every pair on [0, 1], as on the device (see the header).
    set_.for_each_pair([&](CandidateKind kind, std::size_t i) {
      const PairInfo info = set_.describe(kind, i);
      double X0[12], X1[12];
      set_.gather_segment(x, p, info, X0, X1);
      t = std::min(t, contact_pair_time_of_impact(info.kind, X0, X1, info.plane_point(), info.plane_normal(), 1.0));
      return true;
    });
  }
  stats_.ccd_seconds += MPI_Wtime() - start;
  // IPC starts the line search at a fraction of the time of impact, so that the new state
  // keeps a positive distance even before the barrier pushes back.
  return t < 1.0 ? parameters_.ccd_fraction * t : 1.0;
}

double ContactForm::squared_distance(const PairInfo& info, const double* X) {
  return contact_pair_squared_distance(info.kind, X, info.plane_point(), info.plane_normal());
}

double ContactForm::min_distance(const double* x) const {
  // On the host threads (each chunk its own minimum), as the per-step reports ask for it.
  std::vector<double> chunk_min(static_cast<std::size_t>(host_threads()), std::numeric_limits<double>::infinity());
  set_.for_each_pair_chunk([&](CandidateKind kind, std::size_t begin, std::size_t end, int chunk) {
    double& d2 = chunk_min[static_cast<std::size_t>(chunk)];
    for (std::size_t i = begin; i < end; ++i) {
      const PairInfo info = set_.describe(kind, i);
      double X[12];
      set_.gather(x, info, X);
      d2 = std::min(d2, squared_distance(info, X));
    }
  });
  return std::sqrt(*std::min_element(chunk_min.begin(), chunk_min.end()));
}

std::vector<ContactForm::ActivePair> ContactForm::active_pairs(const double* x) const {
  return set_.collect_pairs<ActivePair>([&](CandidateKind kind, std::size_t i, std::vector<ActivePair>& out) {
    const PairInfo info = set_.describe(kind, i);
    bool active;
    ContactPairTerms t;
    terms(info, x, false, false, &active, &t);
    if (active) out.push_back({info, set_.global_node(info.nodes[0])});
  });
}

const char* ContactForm::pair_kind_name(int kind) {
  static const char* const names[num_pair_kinds] = {"point_triangle",     "edge_edge",
                                                    "point_plane",        "point_obstacle_triangle",
                                                    "edge_obstacle_edge", "obstacle_point_triangle"};
  return kind >= 0 && kind < num_pair_kinds ? names[kind] : "unknown";
}

std::array<long, ContactForm::num_pair_kinds> ContactForm::active_pair_counts(const double* x) const {
  std::vector<std::array<long, num_pair_kinds>> chunk_counts(static_cast<std::size_t>(host_threads()));
  set_.for_each_pair_chunk([&](CandidateKind kind, std::size_t begin, std::size_t end, int chunk) {
    long& count = chunk_counts[static_cast<std::size_t>(chunk)][static_cast<int>(kind)];
    for (std::size_t i = begin; i < end; ++i) {
      bool active;
      ContactPairTerms t;
      terms(set_.describe(kind, i), x, false, false, &active, &t);
      count += active;
    }
  });
  std::array<long, num_pair_kinds> counts{};
  for (const auto& c : chunk_counts)
    for (int k = 0; k < num_pair_kinds; ++k) counts[k] += c[k];
  return counts;
}

}  // namespace dipc
