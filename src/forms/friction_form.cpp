#include "forms/friction_form.hpp"

#include <algorithm>
#include <cmath>

#include "contact/friction/friction_potential.hpp"
#include "contact/geometry/barrier.hpp"
#include "logging/log_stages.hpp"
#include "threads/host_threads.hpp"

namespace dipc {

void FrictionForm::update_lag(const double* x_lag, const double* x_start) {
  EventScope event(log_events().friction_lag);
  pairs_.clear();
  const double dhat2 = contact_.dhat() * contact_.dhat();
  std::vector<std::int64_t> pinned;
  for (const auto& active : contact_.active_pairs(x_lag)) {
    const auto& info = active.info;
    Pair p;
    p.count = info.count;
    double X[12];
    for (int k = 0; k < info.count; ++k) {
      p.global[k] = contact_.set().global_node(info.nodes[k]);
      if (!is_obstacle_node(p.global[k])) pinned.push_back(p.global[k]);
      const double* lagged = contact_.set().position(x_lag, info.nodes[k]);
      const double* started = contact_.set().step_start_position(x_start, info.nodes[k]);
      for (int c = 0; c < 3; ++c) {
        X[3 * k + c] = lagged[c];
        p.x_start[3 * k + c] = started[c];
      }
    }
    // Normal force λ = −κ w b'(d) 2√d at the lagged positions (IPC §5).
    const double d = ContactForm::squared_distance(info, X);
    const double lambda = contact::friction_normal_force(contact_.kappa() * info.weight,
                                                         contact::barrier_first_derivative(d, dhat2), d);
    if (info.kind == PairKind::vertex_triangle)
      p.pair = contact::point_triangle_lagged_friction(X, mu_, lambda, eps_u_);
    else if (info.kind == PairKind::edge_edge)
      p.pair = contact::edge_edge_lagged_friction(X, mu_, lambda, eps_u_);
    else
      p.plane = contact::point_plane_lagged_friction(info.plane->normal.data(), mu_, lambda, eps_u_);
    pairs_.push_back(p);
  }
  contact_.set().pin_nodes(std::move(pinned));
  reversing_.assign(pairs_.size(), 0);
  ++pattern_version_;
  if (on_device()) upload_pairs();
}

void FrictionForm::upload_pairs() {
  const std::size_t n = pairs_.size();
  std::vector<std::int32_t> count(n);
  std::vector<double> x_start(12 * n);
  std::vector<contact::LaggedPairFriction> pair(n);
  std::vector<contact::LaggedPointPlaneFriction> plane(n);
  std::vector<std::size_t> offset(n);
  std::size_t values = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const Pair& p = pairs_[k];
    count[k] = p.count;
    std::copy(p.x_start.begin(), p.x_start.end(), x_start.begin() + 12 * static_cast<std::ptrdiff_t>(k));
    pair[k] = p.pair, plane[k] = p.plane;
    offset[k] = values;  // the body nodes' block, as hessian() on the host
    int slots[4];
    const std::size_t b = 3 * static_cast<std::size_t>(body_slots(p.global.data(), p.count, slots));
    values += b * b;
  }
  device_.size = n;
  device_.count.upload(count), device_.x_start.upload(x_start);
  device_.pair.upload(pair), device_.plane.upload(plane), device_.hessian_offset.upload(offset);
  device_.reversing.resize(n);
  device_.reversing.set_zero();
  device_numbering_ = -1;  // the ids follow at the first evaluation
}

void FrictionForm::refresh_device_nodes() {
  const long numbering = contact_.set().numbering_version();
  if (numbering == device_numbering_) return;
  const std::size_t n = pairs_.size();
  std::vector<std::int32_t> nodes(4 * n, -1);  // slot-major, as the kernels read them
  parallel_for(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
      for (int s = 0; s < pairs_[k].count; ++s) nodes[s * n + k] = contact_.set().local_node(pairs_[k].global[s]);
  });
  device_.nodes.upload(nodes);
  device_numbering_ = numbering;
}

bool FrictionForm::gather(const Pair& p, const double* x, double* X, std::int32_t* local) const {
  for (int k = 0; k < p.count; ++k) {
    local[k] = contact_.set().local_node(p.global[k]);
    if (local[k] == -1) return false;
    const double* xk = contact_.set().position(x, local[k]);
    for (int c = 0; c < 3; ++c) X[3 * k + c] = xk[c];
  }
  return true;
}

void FrictionForm::slip(const Pair& p, const double* X, double u[2]) const {
  if (p.count == 1)
    contact::tangential_displacement(X, p.x_start.data(), p.plane, u);
  else
    contact::tangential_displacement(X, p.x_start.data(), p.pair, u);
}

void FrictionForm::prepare_segment(const double* x, const double* p) {
  if (!majorize_reversals_) return;
  EventScope event(log_events().friction);
  if (on_device()) {
    refresh_device_nodes();
    device::mark_friction_reversals(device_, device_obstacle_end(), x, p, eps_u_);
    return;
  }
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    double X[12], X1[12], u0[2], u1[2];
    std::int32_t local[4];
    reversing_[k] = 0;
    if (!gather(pairs_[k], x, X, local)) continue;
    // Obstacles stand still along a segment (they move between segments, ContactSet).
    for (int n = 0; n < pairs_[k].count; ++n)
      for (int c = 0; c < 3; ++c)
        X1[3 * n + c] = X[3 * n + c] + (is_obstacle_node(local[n]) ? 0.0 : p[3 * static_cast<std::size_t>(local[n]) + c]);
    slip(pairs_[k], X, u0);
    slip(pairs_[k], X1, u1);
    reversing_[k] = contact::slip_reverses(u0, u1, eps_u_) ? 1 : 0;
  }
}

std::size_t FrictionForm::num_reversing() const {
  std::size_t n = 0;
  if (on_device()) {
    for (const auto r : device_.reversing.to_host()) n += r != 0;
    return n;
  }
  for (const auto r : reversing_) n += r;
  return n;
}

bool FrictionForm::value(const double* x, double* energy) {
  EventScope event(log_events().friction);
  if (on_device()) {
    refresh_device_nodes();
    return device::friction_energy(device_, device_obstacle_end(), x, reducer_, energy);
  }
  double e = 0;
  for (const Pair& p : pairs_) {
    double X[12];
    std::int32_t local[4];
    if (!gather(p, x, X, local)) return false;
    e += p.count == 1 ? contact::friction_energy(X, p.x_start.data(), p.plane)
                      : contact::friction_energy(X, p.x_start.data(), p.pair);
  }
  *energy = e;
  return true;
}

bool FrictionForm::gradient(const double* x, double* g) {
  EventScope event(log_events().friction);
  if (on_device()) {
    refresh_device_nodes();
    return device::add_friction_gradient(device_, device_obstacle_end(), x, g, reducer_);
  }
  for (const Pair& p : pairs_) {
    double X[12], gp[12];
    std::int32_t local[4];
    if (!gather(p, x, X, local)) return false;
    if (p.count == 1)
      contact::friction_gradient(X, p.x_start.data(), p.plane, gp);
    else
      contact::friction_gradient(X, p.x_start.data(), p.pair, gp);
    for (int k = 0; k < p.count; ++k)
      if (!is_obstacle_node(local[k]))
        for (int c = 0; c < 3; ++c) g[3 * local[k] + c] += gp[3 * k + c];
  }
  return true;
}

bool FrictionForm::node_groups(std::vector<NodeGroup>* groups) const {
  groups->resize(pairs_.size());
  parallel_for(pairs_.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      const Pair& p = pairs_[k];
      int slots[4];
      NodeGroup& g = (*groups)[k];
      g.count = body_slots(p.global.data(), p.count, slots);  // obstacle nodes have no unknowns
      for (int a = 0; a < g.count; ++a) g.node[a] = p.global[slots[a]];
    }
  });
  return true;
}

bool FrictionForm::hessian(const double* x, double* values) {
  EventScope event(log_events().friction);
  if (on_device()) {
    refresh_device_nodes();
    const bool ok = device::friction_hessian_values(device_, device_obstacle_end(), x, values, reducer_);
    device_.reversing.set_zero();  // one Newton model only, as below
    return ok;
  }
  std::size_t offset = 0;
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const Pair& p = pairs_[k];
    double X[12];
    std::int32_t local[4];
    if (!gather(p, x, X, local)) return false;
    int slots[4];
    const int n = 3 * body_slots(p.global.data(), p.count, slots);
    const auto model = reversing_[k] ? contact::FrictionModel::majorizer : contact::FrictionModel::projected;
    if (p.count == 1) {
      contact::friction_hessian(X, p.x_start.data(), p.plane, model, values + offset);
    } else if (n == 3 * p.count) {
      contact::friction_hessian(X, p.x_start.data(), p.pair, model, values + offset);
    } else {  // a pair with an obstacle: the body nodes' block
      double H[144];
      contact::friction_hessian(X, p.x_start.data(), p.pair, model, H);
      body_block(H, p.count, slots, n / 3, values + offset);
    }
    offset += static_cast<std::size_t>(n) * n;
  }
  // One Newton model only: the next segment decides again.
  std::fill(reversing_.begin(), reversing_.end(), 0);
  return true;
}

}  // namespace dipc
