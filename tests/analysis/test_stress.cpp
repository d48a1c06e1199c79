// Tests of granule/analysis/stress.hpp. References: paper 001 eq. 8 (LIGGGHTS compute
// stress/atom) evaluated by hand; the mean stress of a loaded simple lattice, σ = −f/a² I (3D)
// and −f/(a t) I (2D), from the Love–Weber formula σ = (1/V) Σ_c b ⊗ F.
#include <catch2/catch.hpp>

#include <cmath>

#include "frame_builders.hpp"
#include "granule/analysis/coarse_graining.hpp"
#include "granule/analysis/stress.hpp"

using granule::Dim2;
using granule::Dim3;
using namespace granule::analysis;

namespace {

// Simple lattice of n^D touching particles (spacing a = 2r) in a periodic box, one contact per
// nearest-neighbour pair (across the periodic boundary too) carrying a normal force f.
template <class D>
Frame<D> loaded_periodic_lattice(int n, double a, double f_n) {
  using Vec = typename D::Vec;
  Frame<D> f = granule::test::lattice_frame<D>(n, a, 0.5 * a, 2500.0, Vec::Constant(0.5 * a));
  f.box_lo = Vec::Zero();
  f.box_hi = Vec::Constant(n * a);
  f.periodic.setConstant(true);
  const int total = static_cast<int>(f.size());
  for (int s = 0; s < total; ++s) {
    typename D::IVec k;
    int rest = s;
    for (int d = 0; d < D::dim; ++d) {
      k[d] = rest % n;
      rest /= n;
    }
    for (int d = 0; d < D::dim; ++d) {
      typename D::IVec kn = k;
      kn[d] = (k[d] + 1) % n;
      int j = 0;
      for (int e = D::dim - 1; e >= 0; --e) j = j * n + kn[e];
      ContactRecord<D> c;
      c.i = static_cast<std::uint32_t>(s);
      c.j = static_cast<std::uint32_t>(j);
      c.branch = Vec::Zero();
      c.branch[d] = a;  // periodic image resolved
      c.normal = -c.branch / a;
      c.fn = f_n;
      f.contacts.push_back(c);
    }
  }
  return f;
}

}  // namespace

TEST_CASE("virial of a static two-particle contact matches paper 001 eq. 8 by hand",
          "[analysis][stress]") {
  using D = Dim3;
  using Vec = D::Vec;
  const double r = 1e-3;
  Frame<D> f;
  granule::test::add_particle<D>(f, Vec(0.0, 0.0, 0.0), Vec::Zero(), r, 2500.0);
  granule::test::add_particle<D>(f, Vec(2.0 * r, 0.0, 0.0), Vec::Zero(), r, 2500.0);
  ContactRecord<D> c;
  c.i = 0;
  c.j = 1;
  c.branch = Vec(2.0 * r, 0.0, 0.0);
  c.normal = Vec(-1.0, 0.0, 0.0);
  c.fn = 10.0;
  c.ft = Vec(0.0, 3.0, 0.0);
  f.contacts.push_back(c);
  // Eq. 8 with r1 = x_i, r2 = x_j, F1 = (−10, 3, 0), F2 = −F1 (relative positions, as LAMMPS):
  //   r1 F1 + r2 F2 = (x_i − x_j) ⊗ F1 = (−2r, 0, 0) ⊗ (−10, 3, 0)
  //   S = −½ (…): S_xx = −½ (−2r)(−10) = −10 r, S_xy = −½ (−2r)(3) = 3 r, others 0.
  const auto s = particle_virial(f);
  for (int p = 0; p < 2; ++p) {
    D::Mat expected = D::Mat::Zero();
    expected(0, 0) = -10.0 * r;
    expected(0, 1) = 3.0 * r;
    CHECK((s.contact[p] - expected).norm() < 1e-15);
    CHECK(s.kinetic[p].norm() == 0.0);
  }
  // Compression gives a negative trace (tension-positive convention).
  CHECK(s.total(0).trace() < 0.0);
}

TEMPLATE_TEST_CASE("virial kinetic part is -m v v with an optional reference velocity",
                   "[analysis][stress]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  Frame<D> f;
  Vec v = Vec::Zero();
  v[0] = 2.0;
  v[1] = -1.0;
  granule::test::add_particle<D>(f, Vec::Zero(), v, 1e-3, 2000.0);
  const double m = f.mass[0];
  const auto s = particle_virial(f);
  CHECK((s.kinetic[0] + m * v * v.transpose()).norm() < 1e-15 * m * v.squaredNorm());
  const auto s2 = particle_virial(f, v);
  CHECK(s2.kinetic[0].norm() == 0.0);
}

TEMPLATE_TEST_CASE("bulk stress of a loaded periodic lattice is -f/a^2 (3D), -f/(a t) (2D)",
                   "[analysis][stress]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  using Mat = typename D::Mat;
  const double a = 2e-3;
  const double fn = 7.0;
  const int n = 4;
  Frame<D> f = loaded_periodic_lattice<D>(n, a, fn);
  // Each particle has 2 contacts per axis, each sharing ½ b ⊗ F = ½ (−f a) e e: S = −f a I per
  // particle, V = a^D per particle (× t in 2D).
  const double per_volume = std::pow(a, D::dim) * (D::dim == 2 ? f.thickness : 1.0);
  const Mat expected = -fn * a / per_volume * Mat::Identity();
  const auto all = average_stress(f, std::pow(n * a, D::dim) * (D::dim == 2 ? f.thickness : 1.0));
  CHECK((all.contact - expected).norm() < 1e-12 * expected.norm());
  CHECK(all.kinetic.norm() == 0.0);
  CHECK(all.pressure() == Approx(fn * a / per_volume).epsilon(1e-12));
  // A region holding 2^D particles with volume (2a)^D gives the same mean stress.
  const auto part = average_stress(f, Vec::Zero(), Vec::Constant(2.0 * a));
  CHECK(part.particles == static_cast<std::size_t>(std::pow(2, D::dim)));
  CHECK((part.contact - expected).norm() < 1e-12 * expected.norm());
  CHECK_THROWS_AS(average_stress(f, Vec::Zero(), Vec::Zero()), granule::InvalidParameter);
  CHECK_THROWS_AS(average_stress(f, -1.0), granule::InvalidParameter);
}

TEMPLATE_TEST_CASE("summed virial equals the integral of the coarse-grained contact stress",
                   "[analysis][stress]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  using Mat = typename D::Mat;
  // Σ_i S^c_i = Σ_c b_c ⊗ F_c = ∫ σ^c dV (coarse_graining.hpp): the same contact virial with the
  // same index order and sign, including a wall contact (branch to the contact point).
  const double r = 0.5e-3;
  Frame<D> f;
  granule::test::add_particle<D>(f, Vec::Constant(3e-3), Vec::Zero(), r, 2500.0);
  Vec xj = Vec::Constant(3e-3);
  xj[0] += 1.9 * r;
  granule::test::add_particle<D>(f, xj, Vec::Zero(), r, 2500.0);
  ContactRecord<D> c;
  c.i = 0;
  c.j = 1;
  c.branch = xj - f.x[0];
  c.normal = -c.branch.normalized();
  c.fn = 3.0;
  c.ft = Vec::Zero();
  c.ft[1] = 0.8;
  f.contacts.push_back(c);
  ContactRecord<D> w;
  w.i = 1;
  w.branch = Vec::Zero();
  w.branch[1] = -r;
  w.normal = -w.branch / r;
  w.fn = 2.0;
  w.ft = Vec::Zero();
  w.ft[0] = -0.5;
  f.contacts.push_back(w);
  const auto s = particle_virial(f);
  const Mat summed = s.contact[0] + s.contact[1];
  const GaussianCgKernel<D> kernel(0.5e-3, 4e-3);
  const auto grid = RegularGrid<D>::covering(f, 0.25e-3, kernel.cutoff() + 0.5e-3);
  const auto cg = coarse_grain_direct(f, grid, kernel);
  Mat integral = Mat::Zero();
  for (std::size_t k = 0; k < grid.size(); ++k)
    integral += cg.contact_stress[k] * grid.cell_volume() * (D::dim == 2 ? f.thickness : 1.0);
  // c = 8w, h = w/2: node sum = integral to ~1e-14 (see test_coarse_graining.cpp).
  CHECK((integral - summed).norm() < 1e-10 * summed.norm());
  // Without walls the wall term disappears from particle 1 only.
  const auto nw = particle_virial(f, Vec::Zero(), false);
  CHECK((nw.contact[1] - 0.5 * c.branch * (c.fn * c.normal + c.ft).transpose()).norm() < 1e-15);
}
