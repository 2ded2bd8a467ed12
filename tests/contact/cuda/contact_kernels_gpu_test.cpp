// CUDA contact kernels (contact/cuda/contact_kernels.hpp) against the same point functions
// (contact/contact_pair_terms.hpp) evaluated on the host, on random pairs of every kind —
// vertex–triangle, edge–edge (skew and nearly parallel, i.e. mollified), vertex–plane — closer
// than d̂: energy, gradient and Hessian (raw and PSD-projected) to 1e-12 relative to the
// pair's largest entry, active flags and the minimum distance exactly, and the CCD time of
// impact bit for bit on 10⁴ random trajectories per kind, many of them colliding; the same for
// pairs with triangle-mesh obstacle vertices (positions from the obstacle arrays, only the body
// nodes' gradient and Hessian blocks, obstacles moving from start to end in the CCD). Skips
// where no GPU is present; runs on the lent GPU machine.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "contact/contact_pair_terms.hpp"
#include "contact/cuda/contact_kernels.hpp"
#include "contact/obstacle_nodes.hpp"
#include "device/device_runtime.hpp"

namespace dipc {
namespace {

using Vec3 = std::array<double, 3>;

constexpr double kDhat = 1e-2;  // activation distance (unsquared)
constexpr double kDhat2 = kDhat * kDhat;
constexpr double kKappa = 1e3;

Vec3 add(const Vec3& a, const Vec3& b, double s = 1.0) { return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]}; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 unit(const Vec3& a) {
  const double n = std::sqrt(dot(a, a));
  return {a[0] / n, a[1] / n, a[2] / n};
}

// A random pair list over its own nodes (each pair has fresh nodes unless stated), the planes,
// and the node positions.
class RandomPairs {
 public:
  explicit RandomPairs(unsigned seed) : rng_(seed) {
    for (int k = 0; k < 8; ++k) {
      const Vec3 o = vec(2.0), n = unit(vec(1.0));
      plane_points.insert(plane_points.end(), o.begin(), o.end());
      plane_normals.insert(plane_normals.end(), n.begin(), n.end());
    }
  }

  std::vector<double> x;
  device::ContactPairList pairs;
  std::vector<double> plane_points, plane_normals;

  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
  // Log-uniform in [a, b].
  double log_uniform(double a, double b) { return std::exp(uniform(std::log(a), std::log(b))); }
  Vec3 vec(double r) { return {uniform(-r, r), uniform(-r, r), uniform(-r, r)}; }
  // Distances from 1e-4 d̂ (stiff barrier) to 1.5 d̂ (some pairs inactive).
  double distance() { return log_uniform(1e-4 * kDhat, 1.5 * kDhat); }

  std::int32_t node(const Vec3& p) {
    x.insert(x.end(), p.begin(), p.end());
    return static_cast<std::int32_t>(x.size() / 3 - 1);
  }

  // A triangle of size 0.1–1 somewhere in [-3, 3]³ and a point at `gap` from its plane, above
  // a random point of the plane near the triangle (inside or beyond its edges; inside if
  // `interior`). Returns the unit normal pointing from the triangle to the point.
  Vec3 vertex_triangle(double gap, bool interior) {
    const Vec3 t0 = vec(3.0);
    Vec3 e1, e2, n;
    do {
      e1 = vec(1.0), e2 = vec(1.0), n = cross(e1, e2);
    } while (dot(n, n) < 0.01 * dot(e1, e1) * dot(e2, e2));
    const double u = interior ? uniform(0.1, 0.8) : uniform(-0.3, 1.0);
    const double v = interior ? uniform(0.05, 0.9 - u) : uniform(-0.3, 1.0 - std::max(u, 0.0));
    const Vec3 normal = unit(n);
    const Vec3 p = add(add(add(t0, e1, u), e2, v), normal, gap);
    const std::int32_t nodes[4] = {node(p), node(t0), node(add(t0, e1)), node(add(t0, e2))};
    pairs.add(PairKind::vertex_triangle, nodes, uniform(0.01, 1.0), 0.0, -1);
    return normal;
  }

  // Edge a of length 0.1–1 and edge b at `gap` from it along their common normal, measured
  // between the points at random parameters of both (in [0.1, 0.9] if `interior`, so that the
  // segments' closest points are those), crossing at angle `angle` (0: parallel). Returns the
  // unit common normal pointing from a to b.
  Vec3 edge_edge(double gap, double angle, bool interior) {
    const Vec3 a0 = vec(3.0), da = unit(vec(1.0));
    const double la = uniform(0.1, 1.0), lb = uniform(0.1, 1.0);
    const Vec3 normal = unit(cross(da, vec(1.0)));
    const Vec3 w = cross(da, normal);  // da, normal, w orthonormal
    const Vec3 db = add(Vec3{da[0] * std::cos(angle), da[1] * std::cos(angle), da[2] * std::cos(angle)}, w,
                        std::sin(angle));
    const double sa = interior ? uniform(0.1, 0.9) : uniform(-0.2, 1.2);
    const double sb = interior ? uniform(0.1, 0.9) : uniform(-0.2, 1.2);
    const Vec3 pa = add(a0, da, sa * la);
    const Vec3 b0 = add(add(pa, normal, gap), db, -sb * lb);
    const std::int32_t nodes[4] = {node(a0), node(add(a0, da, la)), node(b0), node(add(b0, db, lb))};
    // Mollifier threshold ε_x = 1e-3 |ea|² |eb|² (rest = current, as ContactForm at rest).
    pairs.add(PairKind::edge_edge, nodes, uniform(0.01, 1.0), 1e-3 * la * la * lb * lb, -1);
    return normal;
  }

  // A vertex at `gap` in front of a random plane. Returns the plane's normal.
  Vec3 vertex_plane(double gap) {
    const int k = static_cast<int>(uniform(0, 8)) % 8;
    const Vec3 o{plane_points[3 * k], plane_points[3 * k + 1], plane_points[3 * k + 2]};
    const Vec3 n{plane_normals[3 * k], plane_normals[3 * k + 1], plane_normals[3 * k + 2]};
    const Vec3 t = vec(2.0);
    const Vec3 p = add(add(o, add(t, n, -dot(t, n))), n, gap);
    const std::int32_t nodes[4] = {node(p), -1, -1, -1};
    pairs.add(PairKind::vertex_plane, nodes, uniform(0.01, 1.0), 0.0, k);
    return n;
  }

  // Mixed kinds: skew and nearly parallel (mollified, some exactly parallel) edges.
  void mixed(int per_kind) {
    for (int i = 0; i < per_kind; ++i) {
      vertex_triangle(distance(), false);
      edge_edge(distance(), uniform(0.05, 1.5), false);
      edge_edge(distance(), i % 10 == 0 ? 0.0 : log_uniform(1e-6, 0.03), false);
      vertex_plane(distance());
    }
  }

  // Stacked positions of pair i and its plane (nullptr for other kinds).
  int gather(std::size_t i, double* X) const {
    const int count = pair_node_count(pairs.kind[i]);
    for (int k = 0; k < count; ++k)
      for (int c = 0; c < 3; ++c) X[3 * k + c] = x[3 * pairs.nodes[4 * i + k] + c];
    return count;
  }
  const double* plane_point(std::size_t i) const {
    return pairs.plane[i] >= 0 ? plane_points.data() + 3 * pairs.plane[i] : nullptr;
  }
  const double* plane_normal(std::size_t i) const {
    return pairs.plane[i] >= 0 ? plane_normals.data() + 3 * pairs.plane[i] : nullptr;
  }

 private:
  std::mt19937_64 rng_;
};

// Device copies of a RandomPairs.
struct DeviceScene {
  device::DeviceContactPairs pairs;
  device::DeviceContactObstacles planes;
  device::Array<double> x{"test positions"};
  device::Reducer reducer;
  explicit DeviceScene(const RandomPairs& r) {
    pairs.upload(r.pairs);
    planes.upload_planes(r.plane_points, r.plane_normals);
    x.upload(r.x);
  }
};

device::BarrierConstants constants(bool project) {
  device::BarrierConstants c;
  c.dhat2 = kDhat2;
  c.kappa = kKappa;
  c.project = project;
  return c;
}

bool has_gpu() { return device::device_count() > 0; }

// Largest |a_k − b_k| over a block, relative to the block's largest |b_k| (absolute when that is 0).
double block_error(const double* a, const double* b, int n) {
  double err = 0, scale = 0;
  for (int k = 0; k < n; ++k) err = std::max(err, std::abs(a[k] - b[k])), scale = std::max(scale, std::abs(b[k]));
  return scale > 0 ? err / scale : err;
}

TEST(ContactKernelsGpu, EnergyGradientHessianAndActiveSetMatchHost) {
  if (!has_gpu()) GTEST_SKIP() << "no CUDA device";
  RandomPairs r(7);
  r.mixed(2500);
  const std::size_t n = r.pairs.size();
  DeviceScene d(r);
  ASSERT_EQ(d.pairs.count, n);

  for (bool project : {false, true}) {
    SCOPED_TRACE(project ? "projected Hessian" : "exact Hessian");
    const device::BarrierConstants c = constants(project);
    // Host: the point function pair by pair.
    long double energy = 0;
    std::vector<double> g(r.x.size(), 0.0), H(d.pairs.hessian_values, 0.0);
    std::vector<std::int32_t> active(n);
    std::size_t offset = 0;
    int active_count[3] = {0, 0, 0}, mollified = 0;
    for (std::size_t i = 0; i < n; ++i) {
      double X[12];
      const int count = r.gather(i, X);
      bool is_active;
      ContactPairTerms t;
      ASSERT_TRUE(contact_pair_terms(r.pairs.kind[i], X, r.plane_point(i), r.plane_normal(i), c.dhat2, c.kappa,
                                     r.pairs.weight[i], r.pairs.eps_x[i], true, true, c.project, &is_active, &t));
      active[i] = is_active ? 1 : 0;
      energy += t.energy;
      const int m = 3 * count;
      if (is_active) {
        ++active_count[static_cast<int>(r.pairs.kind[i])];
        for (int k = 0; k < m; ++k) g[3 * r.pairs.nodes[4 * i + k / 3] + k % 3] += t.g[k];
        for (int k = 0; k < m * m; ++k) H[offset + k] = t.H[k];
        if (r.pairs.kind[i] == PairKind::edge_edge &&
            contact::edge_edge_cross_squared_norm(X, X + 3, X + 6, X + 9) < r.pairs.eps_x[i])
          ++mollified;
      }
      offset += static_cast<std::size_t>(m) * m;
    }
    ASSERT_EQ(offset, d.pairs.hessian_values);
    for (int kind = 0; kind < 3; ++kind) EXPECT_GT(active_count[kind], 500) << "kind " << kind;
    EXPECT_GT(mollified, 500) << "too few mollified edge–edge pairs";

    double gpu_energy = 0;
    ASSERT_TRUE(device::contact_barrier_energy(d.pairs, d.planes, c, d.x.data(), d.reducer, &gpu_energy));
    EXPECT_NEAR(gpu_energy, static_cast<double>(energy), 1e-12 * static_cast<double>(energy));

    device::Array<double> dg("test gradient");
    dg.resize(r.x.size());
    dg.set_zero();
    ASSERT_TRUE(device::add_contact_barrier_gradient(d.pairs, d.planes, c, d.x.data(), dg.data(), d.reducer));
    const std::vector<double> gpu_g = dg.to_host();
    device::Array<double> dH("test Hessian");
    dH.resize(d.pairs.hessian_values);
    ASSERT_TRUE(device::contact_barrier_hessian(d.pairs, d.planes, c, d.x.data(), dH.data(), d.reducer));
    const std::vector<double> gpu_H = dH.to_host();
    device::Array<std::int32_t> dactive("test active flags");
    dactive.resize(n);
    ASSERT_TRUE(device::contact_active_flags(d.pairs, d.planes, c, d.x.data(), dactive.data(), d.reducer));
    EXPECT_EQ(dactive.to_host(), active);

    // Every pair has its own nodes, so gradient blocks and Hessian blocks compare pair by pair.
    double worst_g = 0, worst_H = 0;
    offset = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const int count = pair_node_count(r.pairs.kind[i]);
      const int m = 3 * count;
      for (int k = 0; k < count; ++k) {
        const std::size_t at = 3 * static_cast<std::size_t>(r.pairs.nodes[4 * i + k]);
        worst_g = std::max(worst_g, block_error(&gpu_g[at], &g[at], 3));
      }
      worst_H = std::max(worst_H, block_error(&gpu_H[offset], &H[offset], m * m));
      offset += static_cast<std::size_t>(m) * m;
    }
    EXPECT_LE(worst_g, 1e-12);
    EXPECT_LE(worst_H, 1e-12);
  }
}

TEST(ContactKernelsGpu, SharedNodesAccumulateGradient) {
  if (!has_gpu()) GTEST_SKIP() << "no CUDA device";
  RandomPairs r(11);
  r.mixed(500);
  // Every pair a second time over the same nodes: the gradient kernel adds into shared nodes.
  const device::ContactPairList once = r.pairs;
  for (std::size_t i = 0; i < once.size(); ++i)
    r.pairs.add(once.kind[i], &once.nodes[4 * i], once.weight[i], once.eps_x[i], once.plane[i]);
  DeviceScene d(r);
  const device::BarrierConstants c = constants(true);
  std::vector<double> g(r.x.size(), 0.0);
  for (std::size_t i = 0; i < r.pairs.size(); ++i) {
    double X[12];
    const int count = r.gather(i, X);
    bool active;
    ContactPairTerms t;
    ASSERT_TRUE(contact_pair_terms(r.pairs.kind[i], X, r.plane_point(i), r.plane_normal(i), c.dhat2, c.kappa,
                                   r.pairs.weight[i], r.pairs.eps_x[i], true, false, c.project, &active, &t));
    if (active)
      for (int k = 0; k < 3 * count; ++k) g[3 * r.pairs.nodes[4 * i + k / 3] + k % 3] += t.g[k];
  }
  device::Array<double> dg("test gradient");
  dg.resize(r.x.size());
  dg.set_zero();
  ASSERT_TRUE(device::add_contact_barrier_gradient(d.pairs, d.planes, c, d.x.data(), dg.data(), d.reducer));
  const std::vector<double> gpu_g = dg.to_host();
  double worst = 0;
  for (std::size_t k = 0; k < g.size(); k += 3) worst = std::max(worst, block_error(&gpu_g[k], &g[k], 3));
  EXPECT_LE(worst, 1e-12);
}

TEST(ContactKernelsGpu, InadmissiblePairsFailAsOnHost) {
  if (!has_gpu()) GTEST_SKIP() << "no CUDA device";
  RandomPairs r(13);
  r.mixed(50);
  // A vertex on a triangle's corner (d = 0) and a vertex behind a plane.
  r.vertex_triangle(0.01 * kDhat, true);
  const std::size_t touching = r.pairs.size() - 1;
  r.x[3 * r.pairs.nodes[4 * touching]] = r.x[3 * r.pairs.nodes[4 * touching + 1]];
  r.x[3 * r.pairs.nodes[4 * touching] + 1] = r.x[3 * r.pairs.nodes[4 * touching + 1] + 1];
  r.x[3 * r.pairs.nodes[4 * touching] + 2] = r.x[3 * r.pairs.nodes[4 * touching + 1] + 2];
  r.vertex_plane(-0.1 * kDhat);
  DeviceScene d(r);
  const device::BarrierConstants c = constants(true);

  long double energy = 0;
  bool host_ok = true;
  for (std::size_t i = 0; i < r.pairs.size(); ++i) {
    double X[12];
    r.gather(i, X);
    bool active;
    ContactPairTerms t;
    if (contact_pair_terms(r.pairs.kind[i], X, r.plane_point(i), r.plane_normal(i), c.dhat2, c.kappa, r.pairs.weight[i],
                           r.pairs.eps_x[i], false, false, c.project, &active, &t))
      energy += t.energy;
    else
      host_ok = false;
  }
  ASSERT_FALSE(host_ok);
  double gpu_energy = 0;
  EXPECT_FALSE(device::contact_barrier_energy(d.pairs, d.planes, c, d.x.data(), d.reducer, &gpu_energy));
  EXPECT_NEAR(gpu_energy, static_cast<double>(energy), 1e-12 * static_cast<double>(energy));
  device::Array<double> dg("test gradient");
  dg.resize(r.x.size());
  dg.set_zero();
  EXPECT_FALSE(device::add_contact_barrier_gradient(d.pairs, d.planes, c, d.x.data(), dg.data(), d.reducer));
  device::Array<double> dH("test Hessian");
  dH.resize(d.pairs.hessian_values);
  EXPECT_FALSE(device::contact_barrier_hessian(d.pairs, d.planes, c, d.x.data(), dH.data(), d.reducer));
  const std::vector<double> H = dH.to_host();
  // The two inadmissible pairs are the last ones: their Hessian values are zeros.
  EXPECT_TRUE(std::all_of(H.end() - 144 - 9, H.end(), [](double v) { return v == 0.0; }));
  // A state where every pair is admissible clears the flag again.
  RandomPairs fine(13);
  fine.mixed(50);
  DeviceScene e(fine);
  EXPECT_TRUE(device::contact_barrier_energy(e.pairs, e.planes, c, e.x.data(), e.reducer, &gpu_energy));
}

TEST(ContactKernelsGpu, MinimumSquaredDistanceMatchesHostExactly) {
  if (!has_gpu()) GTEST_SKIP() << "no CUDA device";
  RandomPairs r(17);
  r.mixed(2000);
  DeviceScene d(r);
  double host = INFINITY;
  for (std::size_t i = 0; i < r.pairs.size(); ++i) {
    double X[12];
    r.gather(i, X);
    host = std::min(host, contact_pair_squared_distance(r.pairs.kind[i], X, r.plane_point(i), r.plane_normal(i)));
  }
  EXPECT_EQ(device::contact_min_squared_distance(d.pairs, d.planes, d.x.data(), d.reducer), host);
  device::DeviceContactPairs none;
  EXPECT_EQ(device::contact_min_squared_distance(none, d.planes, d.x.data(), d.reducer), INFINITY);
}

// Random trajectories of one kind, cycling through three modes: (0) a random rigid
// translation plus random relative motion of about twice the start gap; (1) a certain
// collision: the vertex (kinds 0 and 2) or edge b (kind 1) is driven 1.5–4 gaps towards the
// other primitive's interior, which stays; (2) degenerate starts: a zero gap (t* = 0), no
// motion at all (t* = t_max), or random motion as in (0). Every seventh edge–edge pair is
// nearly parallel (1e-6 to 0.03 rad).
//
// must_report marks the collisions the CCD must report (t* < 1 for t_max = 1): all of mode
// (1), nearly parallel edges included.
struct Trajectories {
  RandomPairs r;
  std::vector<double> p;          // 3 per node
  std::vector<char> must_report;  // per pair

  Trajectories(PairKind kind, int count, unsigned seed) : r(seed) {
    for (int i = 0; i < count; ++i) {
      const int mode = i % 3;
      const bool collide = mode == 1, touching = mode == 2 && i % 10 == 2, still = mode == 2 && i % 10 == 5;
      const bool nearly_parallel = kind == PairKind::edge_edge && i % 7 == 0;
      const double gap = touching ? 0.0 : r.log_uniform(1e-4 * kDhat, 10 * kDhat);
      Vec3 towards;  // from the first primitive to the second
      if (kind == PairKind::vertex_triangle)
        towards = r.vertex_triangle(gap, collide);
      else if (kind == PairKind::edge_edge)
        towards = r.edge_edge(gap, nearly_parallel ? r.log_uniform(1e-6, 0.03) : r.uniform(0.05, 1.5), collide);
      else
        towards = r.vertex_plane(gap);
      const Vec3 common = r.vec(1.0);
      const double through = r.uniform(1.5, 4.0) * gap;
      const int nodes = pair_node_count(kind);
      for (int k = 0; k < nodes; ++k) {
        Vec3 step{0, 0, 0};
        const bool moving_primitive = kind == PairKind::edge_edge ? k >= 2 : k == 0;
        if (collide && moving_primitive)
          step = add(step, towards, -through);
        else if (!collide && !still)
          step = add(common, r.vec(2.0 * gap));
        p.insert(p.end(), step.begin(), step.end());
      }
      must_report.push_back(collide ? 1 : 0);
    }
  }
};

void expect_same_times_of_impact(PairKind kind) {
  constexpr int kCount = 12000;
  Trajectories t(kind, kCount, 100 + static_cast<int>(kind));
  ASSERT_EQ(t.r.pairs.size(), static_cast<std::size_t>(kCount));
  ASSERT_EQ(t.p.size(), t.r.x.size());
  DeviceScene d(t.r);
  device::Array<double> dp("test directions"), dtoi("test times of impact");
  dp.upload(t.p);
  dtoi.resize(kCount);
  for (double t_max : {1.0, 0.37}) {
    SCOPED_TRACE("t_max = " + std::to_string(t_max));
    device::contact_times_of_impact(d.pairs, d.planes, d.x.data(), dp.data(), t_max, dtoi.data());
    const std::vector<double> gpu = dtoi.to_host();
    int mismatches = 0, early = 0, zero = 0;
    double host_min = t_max;
    for (int i = 0; i < kCount; ++i) {
      double X0[12] = {}, X1[12] = {};
      const int count = t.r.gather(i, X0);
      for (int k = 0; k < count; ++k)
        for (int c = 0; c < 3; ++c) X1[3 * k + c] = X0[3 * k + c] + t.p[3 * t.r.pairs.nodes[4 * i + k] + c];
      const double host = contact_pair_time_of_impact(kind, X0, X1, t.r.plane_point(i), t.r.plane_normal(i), t_max);
      host_min = std::min(host_min, host);
      if (host < t_max) ++early;
      if (host == 0.0) ++zero;
      if (t.must_report[i] && t_max == 1.0) {
        EXPECT_LT(host, 1.0) << "pair " << i << " collides, CCD returned " << host;
      }
      if (gpu[i] != host && ++mismatches <= 5)
        ADD_FAILURE() << "pair " << i << ": GPU toi " << gpu[i] << " != CPU toi " << host;
    }
    EXPECT_EQ(mismatches, 0);
    if (t_max == 1.0) {
      EXPECT_GT(early, kCount / 3) << "too few trajectories come close";
    }
    EXPECT_GT(zero, 0) << "no pair starts within the CCD resolution";
    EXPECT_EQ(device::contact_min_time_of_impact(d.pairs, d.planes, d.x.data(), dp.data(), t_max, d.reducer), host_min);
  }
}

TEST(ContactKernelsGpu, VertexTriangleTimeOfImpactIsBitIdentical) {
  if (!has_gpu()) GTEST_SKIP() << "no CUDA device";
  expect_same_times_of_impact(PairKind::vertex_triangle);
}
TEST(ContactKernelsGpu, EdgeEdgeTimeOfImpactIsBitIdentical) {
  if (!has_gpu()) GTEST_SKIP() << "no CUDA device";
  expect_same_times_of_impact(PairKind::edge_edge);
}
TEST(ContactKernelsGpu, VertexPlaneTimeOfImpactIsBitIdentical) {
  if (!has_gpu()) GTEST_SKIP() << "no CUDA device";
  expect_same_times_of_impact(PairKind::vertex_plane);
}

// Pairs with triangle-mesh obstacles: random vertex–triangle and edge–edge pairs (as above)
// whose nodes in `slots` (a bit per slot) become obstacle vertices, named −2 − k, with their
// positions moved from x to the obstacle arrays: at the end of the segment the pair's own
// position, at its start that position moved by `start_shift` (evaluations must read the end).
// Plane arguments for pairs of the other kinds, which ignore them.
constexpr double kNoPlane[3] = {0, 0, 1};

struct ObstaclePairs {
  RandomPairs r;
  std::vector<double> start, end;         // obstacle vertex positions, 3 per vertex
  std::vector<int> slot_mask;             // per pair
  std::vector<std::int32_t> former_rows;  // the rows of x that obstacle vertices left

  explicit ObstaclePairs(unsigned seed) : r(seed) {}

  void make_obstacle(std::size_t i, int slots, const std::vector<double>* p, double start_shift) {
    for (int k = 0; k < 4; ++k) {
      if (!(slots & (1 << k))) continue;
      std::int32_t& node = r.pairs.nodes[4 * i + k];
      const auto vertex = static_cast<std::int32_t>(end.size() / 3);
      for (int c = 0; c < 3; ++c) {
        const double x = r.x[3 * node + c];
        // With p: the obstacle moves from x to x + p; without: it stands at x, start elsewhere.
        start.push_back(p ? x : x + start_shift);
        end.push_back(p ? x + (*p)[3 * node + c] : x);
        r.x[3 * node + c] = std::nan("");  // the body row of x is no longer this node's
      }
      former_rows.push_back(node);
      node = obstacle_node(vertex);
    }
    slot_mask.push_back(slots);
  }

  // The three kinds of body–obstacle pairs, `per_kind` each: body vertex–obstacle triangle,
  // body edge–obstacle edge (skew and nearly parallel), obstacle vertex–body triangle.
  void mixed(int per_kind) {
    for (int i = 0; i < per_kind; ++i) {
      r.vertex_triangle(r.distance(), false);
      make_obstacle(r.pairs.size() - 1, 0b1110, nullptr, 0.3);
      r.edge_edge(r.distance(), i % 2 ? r.uniform(0.05, 1.5) : r.log_uniform(1e-6, 0.03), false);
      make_obstacle(r.pairs.size() - 1, 0b1100, nullptr, 0.3);
      r.vertex_triangle(r.distance(), false);
      make_obstacle(r.pairs.size() - 1, 0b0001, nullptr, 0.3);
    }
  }

  // Stacked positions of pair i at the end (obstacle vertices at `end`).
  void gather(std::size_t i, double* X) const {
    for (int k = 0; k < 4; ++k) {
      const std::int32_t node = r.pairs.nodes[4 * i + k];
      const double* xk = is_obstacle_node(node) ? &end[3 * obstacle_vertex(node)] : &r.x[3 * node];
      for (int c = 0; c < 3; ++c) X[3 * k + c] = xk[c];
    }
  }
};

TEST(ContactKernelsGpu, ObstaclePairsMatchHostOnTheirBodyNodes) {
  if (!has_gpu()) GTEST_SKIP() << "no CUDA device";
  ObstaclePairs o(23);
  o.mixed(1500);
  const std::size_t n = o.r.pairs.size();
  DeviceScene d(o.r);
  d.planes.upload_vertices(o.start, o.end);
  // The COO layout: each pair's body nodes' block only (9, 36 or 81 values).
  std::size_t values = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const int b = 4 - __builtin_popcount(o.slot_mask[i]);
    values += 9 * b * b;
  }
  ASSERT_EQ(d.pairs.hessian_values, values);

  for (bool project : {false, true}) {
    SCOPED_TRACE(project ? "projected Hessian" : "exact Hessian");
    const device::BarrierConstants c = constants(project);
    long double energy = 0;
    std::vector<double> g(o.r.x.size(), 0.0), H(values, 0.0);
    std::vector<std::int32_t> active(n);
    std::size_t offset = 0;
    int active_count[3] = {0, 0, 0};
    double min_d2 = INFINITY;
    for (std::size_t i = 0; i < n; ++i) {
      double X[12];
      o.gather(i, X);
      const PairKind kind = o.r.pairs.kind[i];
      min_d2 = std::min(min_d2, contact_pair_squared_distance(kind, X, kNoPlane, kNoPlane));
      bool is_active;
      ContactPairTerms t;
      ASSERT_TRUE(contact_pair_terms(kind, X, kNoPlane, kNoPlane, c.dhat2, c.kappa, o.r.pairs.weight[i],
                                     o.r.pairs.eps_x[i], true, true, c.project, &is_active, &t));
      active[i] = is_active ? 1 : 0;
      energy += t.energy;
      int slots[4];
      const int b = body_slots(&o.r.pairs.nodes[4 * i], 4, slots);
      if (is_active) {
        ++active_count[i % 3];
        for (int a = 0; a < b; ++a)
          for (int k = 0; k < 3; ++k) g[3 * o.r.pairs.nodes[4 * i + slots[a]] + k] += t.g[3 * slots[a] + k];
        body_block(t.H, 4, slots, b, &H[offset]);
      }
      offset += 9 * static_cast<std::size_t>(b) * b;
    }
    for (int kind = 0; kind < 3; ++kind) EXPECT_GT(active_count[kind], 100) << "obstacle pair kind " << kind;

    double gpu_energy = 0;
    ASSERT_TRUE(device::contact_barrier_energy(d.pairs, d.planes, c, d.x.data(), d.reducer, &gpu_energy));
    EXPECT_NEAR(gpu_energy, static_cast<double>(energy), 1e-12 * static_cast<double>(energy));
    EXPECT_EQ(device::contact_min_squared_distance(d.pairs, d.planes, d.x.data(), d.reducer), min_d2);

    // The gradient array has rows for the body nodes only; obstacle rows must stay untouched.
    device::Array<double> dg("test gradient");
    dg.resize(o.r.x.size());
    dg.set_zero();
    ASSERT_TRUE(device::add_contact_barrier_gradient(d.pairs, d.planes, c, d.x.data(), dg.data(), d.reducer));
    const std::vector<double> gpu_g = dg.to_host();
    device::Array<double> dH("test Hessian");
    dH.resize(values);
    ASSERT_TRUE(device::contact_barrier_hessian(d.pairs, d.planes, c, d.x.data(), dH.data(), d.reducer));
    const std::vector<double> gpu_H = dH.to_host();
    device::Array<std::int32_t> dactive("test active flags");
    dactive.resize(n);
    ASSERT_TRUE(device::contact_active_flags(d.pairs, d.planes, c, d.x.data(), dactive.data(), d.reducer));
    EXPECT_EQ(dactive.to_host(), active);

    double worst_g = 0, worst_H = 0;
    for (std::size_t k = 0; k < g.size(); k += 3) worst_g = std::max(worst_g, block_error(&gpu_g[k], &g[k], 3));
    offset = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const int m = 3 * (4 - __builtin_popcount(o.slot_mask[i]));
      worst_H = std::max(worst_H, block_error(&gpu_H[offset], &H[offset], m * m));
      offset += static_cast<std::size_t>(m) * m;
    }
    EXPECT_LE(worst_g, 1e-12);
    EXPECT_LE(worst_H, 1e-12);
  }
}

// The CCD of pairs with obstacles: body nodes move along p, obstacle vertices from their start
// to their end positions (the trajectories of Trajectories, with the obstacle nodes' motion
// moved into the obstacle arrays), bit for bit as on the host.
TEST(ContactKernelsGpu, ObstaclePairTimesOfImpactAreBitIdentical) {
  if (!has_gpu()) GTEST_SKIP() << "no CUDA device";
  for (PairKind kind : {PairKind::vertex_triangle, PairKind::edge_edge}) {
    SCOPED_TRACE("kind " + std::to_string(static_cast<int>(kind)));
    constexpr int kCount = 9000;
    Trajectories t(kind, kCount, 300 + static_cast<int>(kind));
    ObstaclePairs o(0);
    o.r = t.r;
    // Vertex–triangle: the triangle (2 of 3 pairs) or the vertex (1 of 3) is the obstacle;
    // edge–edge: edge b, the one mode (1) drives into edge a.
    for (int i = 0; i < kCount; ++i)
      o.make_obstacle(i, kind == PairKind::edge_edge ? 0b1100 : (i % 3 == 2 ? 0b0001 : 0b1110), &t.p, 0.0);
    for (std::int32_t row : o.former_rows)
      for (int c = 0; c < 3; ++c) t.p[3 * row + c] = std::nan("");  // obstacles do not move along p
    DeviceScene d(o.r);
    d.planes.upload_vertices(o.start, o.end);
    device::Array<double> dp("test directions"), dtoi("test times of impact");
    dp.upload(t.p);
    dtoi.resize(kCount);
    device::contact_times_of_impact(d.pairs, d.planes, d.x.data(), dp.data(), 1.0, dtoi.data());
    const std::vector<double> gpu = dtoi.to_host();
    int mismatches = 0, early = 0;
    double host_min = 1.0;
    for (int i = 0; i < kCount; ++i) {
      double X0[12], X1[12];
      for (int k = 0; k < 4; ++k) {
        const std::int32_t node = o.r.pairs.nodes[4 * i + k];
        for (int c = 0; c < 3; ++c) {
          if (is_obstacle_node(node)) {
            X0[3 * k + c] = o.start[3 * obstacle_vertex(node) + c];
            X1[3 * k + c] = o.end[3 * obstacle_vertex(node) + c];
          } else {
            X0[3 * k + c] = o.r.x[3 * node + c];
            X1[3 * k + c] = X0[3 * k + c] + t.p[3 * node + c];
          }
        }
      }
      const double host = contact_pair_time_of_impact(kind, X0, X1, kNoPlane, kNoPlane, 1.0);
      host_min = std::min(host_min, host);
      if (host < 1.0) ++early;
      if (t.must_report[i]) {
        EXPECT_LT(host, 1.0) << "pair " << i << " collides, CCD returned " << host;
      }
      if (gpu[i] != host && ++mismatches <= 5)
        ADD_FAILURE() << "pair " << i << ": GPU toi " << gpu[i] << " != CPU toi " << host;
    }
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(early, kCount / 3) << "too few trajectories come close";
    EXPECT_EQ(device::contact_min_time_of_impact(d.pairs, d.planes, d.x.data(), dp.data(), 1.0, d.reducer), host_min);
  }
}

TEST(ContactKernelsGpu, EmptyListsNeedNoLaunch) {
  if (!has_gpu()) GTEST_SKIP() << "no CUDA device";
  device::DeviceContactPairs none;
  device::DeviceContactObstacles planes;
  device::Reducer reducer;
  double e = 1;
  EXPECT_TRUE(device::contact_barrier_energy(none, planes, constants(true), nullptr, reducer, &e));
  EXPECT_EQ(e, 0.0);
  EXPECT_TRUE(device::add_contact_barrier_gradient(none, planes, constants(true), nullptr, nullptr, reducer));
  EXPECT_TRUE(device::contact_barrier_hessian(none, planes, constants(true), nullptr, nullptr, reducer));
  EXPECT_EQ(device::contact_min_time_of_impact(none, planes, nullptr, nullptr, 0.5, reducer), 0.5);
}

}  // namespace
}  // namespace dipc
