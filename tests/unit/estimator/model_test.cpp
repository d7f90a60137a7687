// Identities of the model (MODEL.md), checked at random points: independent of any estimator.
#include "hrgbench/estimator/model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace hrgbench::estimator {
namespace {

class ModelTest : public ::testing::Test {
 protected:
  State RandomState() {
    return State::NullaryExpr([&] { return normal_(rng_); });
  }
  Delta RandomDelta() {
    return Delta::NullaryExpr([&] { return 1e-2 * normal_(rng_); });
  }
  std::mt19937_64 rng_{20261121};
  std::normal_distribution<double> normal_{0.0, 1.0};
};

TEST_F(ModelTest, FormsMatrixIsSymmetricInItsTwoArguments) {
  for (int i = 0; i < 100; ++i) {
    const State a = RandomState(), b = RandomState();
    EXPECT_LT((FormsMatrix(a) * b - FormsMatrix(b) * a).norm(), 1e-14);
  }
}

TEST_F(ModelTest, FormsSatisfyTheRankThreeIdentity) {
  for (int i = 0; i < 100; ++i) {
    const Forms z = QuadraticForms(RandomState());
    EXPECT_NEAR(z[kAc] * z[kAc] + z[kAs] * z[kAs], z[kS] * z[kS] - z[kK] * z[kK],
                1e-13 * z[kS] * z[kS]);
  }
}

// W is the symmetric bilinear form behind the quadratic forms: W(a)·b = (z(a+b) − z(a−b))/4
// (polarisation), which fails for any W that is not z's own.
TEST_F(ModelTest, FormsMatrixIsThePolarisationOfTheForms) {
  for (int i = 0; i < 100; ++i) {
    const State a = RandomState(), b = RandomState();
    const Forms polarised = (QuadraticForms(a + b) - QuadraticForms(a - b)) / 4.0;
    EXPECT_LT((FormsMatrix(a) * b - polarised).norm(), 1e-13);
  }
}

TEST_F(ModelTest, FormsEqualWTimesX) {
  for (int i = 0; i < 20; ++i) {
    const State x = RandomState();
    EXPECT_LT((QuadraticForms(x) - FormsMatrix(x) * x).norm(), 1e-14);
  }
}

// dz/dt = 2·W(x)·dx/dt = 2·W(x)·A·x must equal 2·M·z and 2·Mδ(Ω, z)·δ.
TEST_F(ModelTest, FormsDynamicsAgreesWithStateDynamics) {
  for (int i = 0; i < 100; ++i) {
    const State x = RandomState();
    const Delta d = RandomDelta();
    const double omega = normal_(rng_);
    const Forms z = QuadraticForms(x);
    const Forms from_state = 2.0 * FormsMatrix(x) * SystemMatrix(omega, d) * x;
    EXPECT_LT((2.0 * FormsDynamics(omega, d) * z - from_state).norm(), 1e-14);
    EXPECT_LT((2.0 * FormsRegressor(omega, z) * d - from_state).norm(), 1e-14);
  }
}

TEST_F(ModelTest, OrbitRoundTrip) {
  for (int i = 0; i < 200; ++i) {
    // Random orbit in the convention's range: a > |b|, θ ∈ (−π/2, π/2], φ ∈ (−π, π].
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Orbit o{1.0 + std::abs(u(rng_)), 0.0, 0.5 * std::numbers::pi * u(rng_),
            std::numbers::pi * u(rng_)};
    o.b = o.a * 0.9 * u(rng_);
    const Orbit back = StateToOrbit(OrbitToState(o));
    EXPECT_NEAR(back.a, o.a, 1e-12);
    EXPECT_NEAR(back.b, o.b, 1e-12);
    EXPECT_NEAR(back.theta_rad, o.theta_rad, 1e-10);
    EXPECT_NEAR(std::remainder(back.phi_rad - o.phi_rad, 2 * std::numbers::pi), 0.0, 1e-10);
    // And x → orbit → x for any x.
    const State x = RandomState();
    EXPECT_LT((OrbitToState(StateToOrbit(x)) - x).norm(), 1e-12);
  }
}

TEST_F(ModelTest, OrbitFormsMatchTheirDefinition) {
  const Orbit o{1.3, -0.4, 0.7, 0.2};
  const Forms z = QuadraticForms(OrbitToState(o));
  EXPECT_NEAR(z[kAc], (o.a * o.a - o.b * o.b) * std::cos(2 * o.theta_rad), 1e-14);
  EXPECT_NEAR(z[kAs], (o.a * o.a - o.b * o.b) * std::sin(2 * o.theta_rad), 1e-14);
  EXPECT_NEAR(z[kK], 2 * o.a * o.b, 1e-14);
  EXPECT_NEAR(z[kS], o.a * o.a + o.b * o.b, 1e-14);
}

// a = b: θ is undefined (MODEL.md); the convention puts θ = 0 and the angle into φ.
TEST_F(ModelTest, CircularOrbitKeepsTheState) {
  const State x = OrbitToState(Orbit{0.8, 0.8, 0.9, 0.3});
  const Orbit o = StateToOrbit(x);
  EXPECT_NEAR(o.a, 0.8, 1e-12);
  EXPECT_NEAR(o.b, 0.8, 1e-12);
  EXPECT_EQ(o.theta_rad, 0.0);
  EXPECT_LT((OrbitToState(o) - x).norm(), 1e-12);
}

TEST_F(ModelTest, UndistortExactInvertsTheDistortion) {
  for (int i = 0; i < 100; ++i) {
    const Xi xi = Xi::NullaryExpr([&] { return 0.05 * normal_(rng_); });
    const State x = RandomState();
    const Observation y = (Matrix4::Identity() + DistortionMatrix(xi)) * x;
    EXPECT_LT((UndistortExact(xi, y) - x).norm(), 1e-13);
  }
}

// z = N(ξ)·r + O(|ξ|²): halving ξ must cut the error of the first-order form by ~4.
TEST_F(ModelTest, FirstOrderDistortionIsSecondOrderAccurate) {
  const Xi xi_dir = (Xi() << 0.7, -0.3, 0.5, 0.4).finished();
  for (int i = 0; i < 20; ++i) {
    const Observation y = RandomState();
    double previous = 0.0;
    for (double scale : {4e-2, 2e-2, 1e-2}) {
      const Xi xi = scale * xi_dir;
      const Forms z = QuadraticForms(UndistortExact(xi, y));
      const Forms r = QuadraticForms(y);
      const Forms first = FirstOrderFormsDistortion(xi) * r;
      EXPECT_LT((first - (r + FirstOrderFormsSensitivity(r) * xi)).norm(), 1e-14);
      const double error = (first - z).norm();
      if (previous > 0.0) {
        EXPECT_GT(previous / error, 3.5);
        EXPECT_LT(previous / error, 4.5);
      }
      previous = error;
    }
  }
}

// The special-case regressor (ξ = (λ, φ, 0, 0), δ2 column corrected): its error against the exact
// dr/dt falls ~4× when ξ halves.
TEST_F(ModelTest, SpecialCaseRegressorIsFirstOrderInXi) {
  const Delta d = (Delta() << -1e-3, 0.3, 2e-4, -1e-4, 3e-4, 1e-4).finished();
  const double omega = 0.7;
  const State x = RandomState();
  double previous = 0.0;
  for (double scale : {2e-2, 1e-2, 5e-3}) {
    const Xi xi(scale, -0.6 * scale, 0.0, 0.0);
    const Matrix4 g = Matrix4::Identity() + DistortionMatrix(xi);
    const Observation y = g * x;
    const Forms dr_dt = 2.0 * FormsMatrix(y) * g * SystemMatrix(omega, d) * x;
    const Forms approx = 2.0 * FirstOrderFormsRegressor(omega, QuadraticForms(y), xi[0], xi[1]) * d;
    const double error = (approx - dr_dt).norm();
    if (previous > 0.0) {
      EXPECT_GT(previous / error, 3.5);
      EXPECT_LT(previous / error, 4.5);
    }
    previous = error;
  }
}

TEST_F(ModelTest, SystemMatrixMatchesTheEExpansion) {
  // A = δ1·I + 2Ωδ2·E34-1-2 + δ3·E12-3-4 + δ4·E3412 + δ5·E-214-3 + δ6·E-43-21 (MODEL.md notation).
  const auto e = [](std::array<int, 4> idx) {
    Matrix4 m = Matrix4::Zero();
    for (int row = 0; row < 4; ++row) m(row, std::abs(idx[row]) - 1) = idx[row] > 0 ? 1.0 : -1.0;
    return m;
  };
  const Delta d = RandomDelta();
  const double omega = 0.37;
  const Matrix4 expected = d[0] * Matrix4::Identity() + 2 * omega * d[1] * e({3, 4, -1, -2}) +
                           d[2] * e({1, 2, -3, -4}) + d[3] * e({3, 4, 1, 2}) +
                           d[4] * e({-2, 1, 4, -3}) + d[5] * e({-4, 3, -2, 1});
  EXPECT_LT((SystemMatrix(omega, d) - expected).norm(), 1e-16);
}

}  // namespace
}  // namespace hrgbench::estimator
