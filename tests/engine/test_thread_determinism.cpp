// Thread-count determinism: the engine sums every particle's forces in an order fixed by the
// neighbour list alone (simulation.hpp, header comment), so a run with 1 thread and a run with 2
// threads must give bitwise identical positions, velocities, angular velocities and forces (also
// the forces on the walls), and
// two runs with 2 threads must too. The scene has thousands of particles in a tall periodic-x
// column (many cell layers, so the three-colour layer loop really runs in parallel), with
// gravity, walls and Hertz-Mindlin friction (history), so every part of a step is exercised.
#include <catch2/catch.hpp>

#include <cstring>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "engine_helpers.hpp"

using namespace granule;

namespace {

constexpr double kColumnR = 1.0e-3;  // [m]

template <class D>
struct Snapshot {
  std::vector<typename D::Vec> x, v, f;
  std::vector<typename D::AngVec> omega, torque;
  std::vector<typename D::Vec> wall_f;  // the particles' force on each wall (Wall::force)
  std::vector<typename D::AngVec> wall_t;
  std::vector<std::uint64_t> id;
  std::size_t layers = 0;
  std::size_t builds = 0;
};

template <class T>
bool bitwise_equal(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

template <class D>
bool bitwise_equal(const Snapshot<D>& a, const Snapshot<D>& b) {
  return bitwise_equal(a.id, b.id) && bitwise_equal(a.x, b.x) && bitwise_equal(a.v, b.v) &&
         bitwise_equal(a.f, b.f) && bitwise_equal(a.omega, b.omega) && bitwise_equal(a.torque, b.torque) &&
         bitwise_equal(a.wall_f, b.wall_f) && bitwise_equal(a.wall_t, b.wall_t);
}

// A jittered lattice of spacing 2.3 mm (radii 0.8..1.2 mm): 26 x 82 disks or 7 x 45 x 7 spheres.
constexpr double kSpacing = 2.3e-3;  // [m]

template <class D>
typename D::IVec column_cells() {
  typename D::IVec c;
  if constexpr (D::dim == 2) {
    c << 26, 82;
  } else {
    c << 7, 45, 7;
  }
  return c;
}

template <class D>
Domain<D> column_domain() {
  using Vec = typename D::Vec;
  const Vec len = column_cells<D>().template cast<double>() * kSpacing;
  return test::box_domain<D>(len, false, 0);
}

template <class D>
std::vector<test::SphereSpec<D>> column_packing() {
  using Vec = typename D::Vec;
  std::mt19937_64 rng(77);
  const auto cells = column_cells<D>();
  std::vector<test::SphereSpec<D>> out;
  typename D::IVec c = D::IVec::Zero();
  while (c[D::dim - 1] < cells[D::dim - 1]) {
    Vec x = (c.template cast<double>().array() + 0.5).matrix() * kSpacing;
    for (int k = 0; k < D::dim; ++k) x[k] += test::uniform(rng, -0.02, 0.02) * kSpacing;
    out.push_back({x, test::uniform(rng, 0.8, 1.2) * kColumnR});
    for (int k = 0; k < D::dim; ++k) {
      if (++c[k] < cells[k] || k == D::dim - 1) break;
      c[k] = 0;
    }
  }
  return out;
}

template <class D, class Search>
Snapshot<D> run_column(int threads, std::size_t steps, bool perturb = false) {
  using Vec = typename D::Vec;
#ifdef _OPENMP
  omp_set_num_threads(threads);
#else
  (void)threads;
#endif
  const auto dom = column_domain<D>();
  SimulationConfig<D> cfg;
  cfg.domain = dom;
  cfg.dt = 1e-5;
  cfg.thickness = 1e-3;
  cfg.gravity = Vec::Zero();
  cfg.gravity[1] = -100.0;  // [m/s^2]
  Simulation<D, contact::HertzMindlin, Search> sim(cfg);
  const auto mat = sim.add_material(test::soft_material(0.5, 0.5));
  const auto wmat = sim.add_wall_material(test::soft_material(0.5, 0.5));
  for (int k = 1; k < D::dim; ++k) {
    sim.add_wall(geometry::PlaneShape<D>(dom.lo, Vec::Unit(k)), wmat);
    sim.add_wall(geometry::PlaneShape<D>(dom.hi, Vec(-Vec::Unit(k))), wmat);
  }
  std::mt19937_64 rng(3);
  const auto packing = column_packing<D>();
  for (const auto& s : packing) {
    Vec v;
    for (int k = 0; k < D::dim; ++k) v[k] = test::uniform(rng, -0.3, 0.3);  // [m/s]
    // Control: one position moved by 1e-9 r.
    Vec x = s.x;
    if (perturb && &s == &packing.front()) x[1] += 1e-9 * kColumnR;
    sim.add_particle(x, s.r, mat, v);
  }
  sim.run(steps);
  Snapshot<D> snap;
  const auto& p = sim.particles();
  const std::size_t n = p.owned();
  snap.x.assign(p.x.begin(), p.x.begin() + n);
  snap.v.assign(p.v.begin(), p.v.begin() + n);
  snap.f.assign(p.f.begin(), p.f.begin() + n);
  snap.omega.assign(p.omega.begin(), p.omega.begin() + n);
  snap.torque.assign(p.torque.begin(), p.torque.begin() + n);
  snap.id.assign(p.id.begin(), p.id.begin() + n);
  for (const auto& w : sim.walls()) {
    snap.wall_f.push_back(w.force);
    snap.wall_t.push_back(w.torque);
  }
  snap.layers = sim.neighbour_list().layers();
  snap.builds = sim.neighbour_list().builds;
  return snap;
}

template <class D, class Search>
void check_determinism() {
#ifdef _OPENMP
  const int saved = omp_get_max_threads();
  omp_set_num_threads(2);
  int team = 0;
#pragma omp parallel
  {
#pragma omp single
    team = omp_get_num_threads();
  }
  INFO("OpenMP team size with omp_set_num_threads(2): " << team);
  REQUIRE(team == 2);
#else
  WARN("compiled without OpenMP: the runs below are all serial");
#endif
  // LinkedCells rebuilds every step (the expensive part): fewer steps suffice to cover it.
  const std::size_t steps = Search::rebuild_every_step ? 50 : 100;
  const Snapshot<D> one = run_column<D, Search>(1, steps);
  const Snapshot<D> two = run_column<D, Search>(2, steps);
  const Snapshot<D> two_again = run_column<D, Search>(2, steps);
  const Snapshot<D> perturbed = run_column<D, Search>(2, steps, true);
#ifdef _OPENMP
  omp_set_num_threads(saved);
#endif
  INFO("dim " << D::dim << ", " << Search::name << ": " << one.x.size() << " particles, " << one.layers
              << " cell layers, " << one.builds << " builds");
  REQUIRE(one.x.size() >= 2100);
  // Below this size the engine runs its particle loops serially: the test would be vacuous.
  REQUIRE(one.x.size() >= Simulation<D, contact::HertzMindlin, Search>::kParallelMinParticles);
  CHECK(one.layers >= 12);
  double moved = 0.0;
  for (const auto& v : one.v) moved = std::max(moved, v.norm());
  CHECK(moved > 0.1);  // the particles really move
  CHECK(bitwise_equal(one, two));
  CHECK(bitwise_equal(two, two_again));
  CHECK_FALSE(bitwise_equal(two, perturbed));  // the comparison sees a 1e-9 r change of the input
}

}  // namespace

TEMPLATE_TEST_CASE("Results are bitwise identical for 1 and 2 threads (VerletList)", "[engine][threads]", Dim2,
                   Dim3) {
  check_determinism<TestType, neighbours::VerletList>();
}

TEMPLATE_TEST_CASE("Results are bitwise identical for 1 and 2 threads (LinkedCells)", "[engine][threads]", Dim2,
                   Dim3) {
  check_determinism<TestType, neighbours::LinkedCells>();
}
