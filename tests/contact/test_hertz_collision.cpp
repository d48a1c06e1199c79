// Elastic Hertz impacts through the engine (HertzFrictionless, e = 1): contact duration and
// maximum overlap against the closed-form Hertz solution, for two equal particles and for a
// particle on a plane wall, in 2D (disks, same force law) and 3D.
#include <catch2/catch.hpp>

#include <cmath>

#include "contact_test_support.hpp"
#include "granule/materials/time_step.hpp"

using namespace granule;
using namespace granule::contact_test;

namespace {

Material elastic_material() {
  Material m;
  m.youngs_modulus = 1.0e7;  // [Pa]
  m.poisson_ratio = 0.3;     // [-]
  m.density = 2500.0;        // [kg/m^3]
  m.restitution = 1.0;
  return m;
}

}  // namespace

// Reference: Johnson (1985), Contact Mechanics, section 11.4 (Hertz impact of elastic bodies):
//   delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5),
//   t_c = 2.8683 (m*^2 / (E*^2 R* v))^(1/5)  (= 2 delta_max/v * 1.4716),
// which is paper 001 eq. A17, 2.94 (m*^2/((16/15)^2 E*^2 R* v))^(1/5), to 0.1 %.
// v is the relative approach speed. Pair: m* = m/2, R* = r/2; wall: m* = m, R* = r.
// E* = E / (2 (1 - nu^2)) for two equal materials (000 eq. B8).
// Tolerance 1 % on t_c and delta_max (the brief): the engine reaches ~1e-4 with 2000 steps per
// contact; a wrong prefactor of the Hertz force (e.g. 2 E* instead of 4/3 E*) shifts both by 15 %,
// a wrong R* (r instead of r/2) by 13 %, a wrong m* by 32 %.
TEMPLATE_TEST_CASE("Hertz elastic head-on impact: duration and maximum overlap (Johnson 1985)",
                   "[contact][hertz]", Dim2, Dim3) {
  using D = TestType;
  const Material mat = elastic_material();
  const double r = 2.0e-3;   // [m]
  const double t = 1.0e-3;   // 2D disk thickness [m]
  const double E_eff = mat.youngs_modulus / (2.0 * (1.0 - mat.poisson_ratio * mat.poisson_ratio));
  const double m = mass_of<D>(mat.density, r, t);
  for (const bool wall : {false, true}) {
    for (const double v : {0.2, 2.0}) {
      const double m_eff = wall ? m : 0.5 * m;
      const double r_eff = wall ? r : 0.5 * r;
      const double tc = hertz_duration_exact(m_eff, E_eff, r_eff, v);
      const double dm = hertz_max_overlap_exact(m_eff, E_eff, r_eff, v);
      const auto res = run_head_on<D, contact::HertzFrictionless>(mat, r, v, wall, tc, 2000, t);
      INFO("dim " << D::dim << (wall ? " wall" : " pair") << " v = " << v << ": t_c = " << res.duration
                  << " s (Hertz " << tc << "), delta_max = " << res.max_overlap << " m (Hertz " << dm << ")");
      CHECK(res.duration == Approx(tc).epsilon(0.01));
      CHECK(res.max_overlap == Approx(dm).epsilon(0.01));
      // Elastic law: the rebound speed equals the impact speed (energy conservation, Verlet).
      CHECK(res.restitution == Approx(1.0).epsilon(1e-4));
      // The engine's helper (001 eq. A17 form) agrees with the exact constant to 0.2 %.
      CHECK(hertz_collision_time(m_eff, E_eff, r_eff, v) == Approx(tc).epsilon(2e-3));
      CHECK(hertz_max_overlap(m_eff, E_eff, r_eff, v) == Approx(dm).epsilon(1e-12));
    }
  }
}
