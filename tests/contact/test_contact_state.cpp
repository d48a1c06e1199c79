// Per-contact history of the contact models: empty for stateless laws, one vector for the
// linear and the legacy (displacement-form) springs, one vector and the last stiffness for the
// Mindlin force form (plus one angular vector for EPSD rolling), and reverse() turning the
// history of pair (i, j) into that of (j, i).
#include <catch2/catch.hpp>

#include <type_traits>

#include "contact_test_support.hpp"

using namespace granule;
using namespace granule::contact_test;

// Reference: contact/model.hpp and STYLE.md item 6 (State empty when stateless: the neighbour list
// then stores no history at all).
TEMPLATE_TEST_CASE("Contact model State: empty when stateless, one vector per spring", "[contact][state]", Dim2,
                   Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  STATIC_REQUIRE(std::is_empty_v<contact::LinearFrictionless::State<D>>);
  STATIC_REQUIRE(std::is_empty_v<contact::HertzFrictionless::State<D>>);
  STATIC_REQUIRE(std::is_empty_v<
                 contact::ContactModel<contact::HertzNormal, contact::NoTangential, contact::ConstantTorqueRolling,
                                       contact::SjkrCohesion>::State<D>>);
  STATIC_REQUIRE(!contact::HertzFrictionless::has_state<D>);
  STATIC_REQUIRE(!contact::LinearFrictionless::has_state<D>);
  // Sizes padded to the vector's alignment (Eigen::Vector2d is 16-byte aligned).
  constexpr auto padded = [](std::size_t bytes) { return (bytes + alignof(Vec) - 1) / alignof(Vec) * alignof(Vec); };
  // Mindlin force form: spring force + k_t of the last step (2D: 16 + 8 -> 32; 3D: 24 + 8 = 32).
  STATIC_REQUIRE(sizeof(contact::HertzMindlin::State<D>) == sizeof(Vec));  // displacement (potential form)
  STATIC_REQUIRE(sizeof(contact::HertzMindlinIncremental::State<D>) == padded(sizeof(Vec) + sizeof(double)));
  STATIC_REQUIRE(sizeof(contact::HertzMindlinLegacy::State<D>) == sizeof(Vec));
  STATIC_REQUIRE(sizeof(contact::LinearSpringDashpot::State<D>) == sizeof(Vec));
  STATIC_REQUIRE(contact::HertzMindlin::has_state<D>);
  // Tangential state (the spring displacement) + rolling torque (2D: one scalar; 3D: its
  // tangent-plane vector and its twisting scalar), at most padded (3D: 24 + 24 + 8 = 56;
  // 2D: 16 + 8 = 24, padded to 32 bytes by the alignment of the 2-vector).
  constexpr std::size_t rolling = D::dim == 3 ? sizeof(Vec) + sizeof(double) : sizeof(double);
  constexpr std::size_t epsd_min = sizeof(Vec) + rolling;
  constexpr std::size_t epsd_max = padded(sizeof(contact::MindlinTangential::State<D>) + rolling);
  STATIC_REQUIRE(sizeof(contact::HertzMindlinEpsd::State<D>) >= epsd_min);
  STATIC_REQUIRE(sizeof(contact::HertzMindlinEpsd::State<D>) <= epsd_max);
  STATIC_REQUIRE(sizeof(contact::HertzMindlinEpsdSjkr::State<D>) == sizeof(contact::HertzMindlinEpsd::State<D>));
}

// Reference: history hooks (MercuryDPM reverseHistory; contact/tangential/history.hpp): the
// tangential spring force and the rolling spring torque of (j, i) are minus those of (i, j); the
// stiffness the force form remembers is the same from both sides.
// Checked on the state, and physically: with the reversed history the swapped pair receives
// exactly the opposite force and swapped torques (Newton's third law), to round-off.
TEMPLATE_TEST_CASE("Contact model reverse(): history of (j, i) gives the opposite force", "[contact][state]", Dim2,
                   Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  using AngVec = typename D::AngVec;
  using Model = contact::HertzMindlinEpsd;
  Material mat;
  mat.youngs_modulus = 1.0e7;
  mat.poisson_ratio = 0.3;
  mat.density = 2500.0;
  mat.restitution = 0.7;
  mat.friction = 5.0;  // no sliding: the spring history is exercised
  mat.rolling_friction = 0.5;
  mat.rolling_damping = 0.2;
  const auto prm = Model::make(mix(mat, mat));
  const double ri = 2.0e-3, rj = 1.0e-3, mi = 8.0e-5, mj = 1.0e-5, dt = 1.0e-6;
  Vec xi = Vec::Zero();
  xi[0] = 2.9e-3;
  xi[D::dim - 1] = 0.3e-3;
  const Vec xj = Vec::Zero();
  Vec vi = Vec::Zero(), vj = Vec::Zero();
  vi[D::dim - 1] = 0.05;
  vj[0] = -0.01;
  AngVec wi, wj;
  if constexpr (D::dim == 2) {
    wi = 3.0;
    wj = -1.0;
  } else {
    wi = Eigen::Vector3d(1.0, -2.0, 3.0);
    wj = Eigen::Vector3d(0.5, 0.0, -1.0);
  }
  const auto gij = make_pair_geometry<D>(xi, xj, ri, rj, mi, mj, vi, vj, wi, wj, dt);
  const auto gji = make_pair_geometry<D>(xj, xi, rj, ri, mj, mi, vj, vi, wj, wi, dt);
  typename Model::template State<D> sij{};
  for (int k = 0; k < 10; ++k) Model::evaluate(prm, gij, sij);
  REQUIRE(sij.tangential.xi.norm() > 0.0);
  REQUIRE(contact::EpsdRolling::squared_norm<D>(sij.rolling) > 0.0);
  if constexpr (D::dim == 3) REQUIRE(sij.rolling.m_twist != 0.0);
  auto sji = sij;
  Model::reverse(sji);
  CHECK((sji.tangential.xi + sij.tangential.xi).norm() == 0.0);
  // Seen from j: the rolling part of M_k changes sign, the twisting part (M_k . n) does not.
  CHECK(D::norm(sji.rolling.m_roll + sij.rolling.m_roll) == 0.0);
  if constexpr (D::dim == 3) CHECK(sji.rolling.m_twist == sij.rolling.m_twist);
  const auto fij = Model::evaluate(prm, gij, sij);
  const auto fji = Model::evaluate(prm, gji, sji);
  const double scale = fij.force.norm();
  CHECK((fji.force + fij.force).norm() <= 1e-12 * scale);
  CHECK(D::norm(fji.torque_i - fij.torque_j) <= 1e-12 * D::norm(fij.torque_j));
  CHECK(D::norm(fji.torque_j - fij.torque_i) <= 1e-12 * D::norm(fij.torque_i));
  // Without reversing, the swapped pair would get a wrong tangential force.
  auto wrong = sij;
  const auto fbad = Model::evaluate(prm, gji, wrong);
  CHECK((fbad.force + fij.force).norm() > 1e-3 * scale);
}

// Reference: io/checkpoint.hpp refuses a file whose model signature differs. Checkpoints written
// before the Mindlin spring kept its force as history (it stored the displacement xi [m], now the
// force F_s [N] and k_t,old), before the implicit relaxation of Truncation::Total and before the
// twist rotation must not load into the changed laws; the LIGGGHTS 3.8 law did not change and its
// old checkpoints still load.
TEST_CASE("Contact model signatures: changed laws are renamed, the unchanged legacy law is not", "[contact][state]") {
  CHECK(contact::HertzMindlin::signature() != "ContactModel<HertzNormal,SpringTangential<Mindlin,Total,KeepLength>,NoRolling,NoCohesion>");
  CHECK(contact::LinearSpringDashpot::signature() != "ContactModel<LinearNormal,SpringTangential<Linear,Total,KeepLength>,NoRolling,NoCohesion>");
  CHECK(contact::LinearCoulombRolling::signature() != "ContactModel<LinearNormal,IncrementalCoulombTangential,EpsdRolling,NoCohesion>");
  CHECK(contact::HertzMindlinLegacy::signature() == "ContactModel<HertzNormal,SpringTangential<Mindlin,SpringOnly,KeepLength>,NoRolling,NoCohesion>");
  CHECK(contact::HertzMindlin::signature() != contact::HertzMindlinLegacy::signature());
}
