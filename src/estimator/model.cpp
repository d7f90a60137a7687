#include "hrgbench/estimator/model.hpp"

#include <cmath>
#include <complex>

namespace hrgbench::estimator {

Matrix4 SystemMatrix(double omega_rad_s, const Delta& d) noexcept {
  const double w = 2.0 * omega_rad_s * d[kScaleFactor];
  const double d1 = d[kDamping], d3 = d[kDampingAnisotropyCos], d4 = d[kDampingAnisotropySin];
  const double d5 = d[kFrequencyAnisotropyCos], d6 = d[kFrequencyAnisotropySin];
  Matrix4 a;
  a << d1 + d3, -d5, w + d4, -d6,  //
      d5, d1 + d3, d6, w + d4,     //
      -w + d4, -d6, d1 - d3, d5,   //
      d6, -w + d4, -d5, d1 - d3;
  return a;
}

Matrix4 DistortionMatrix(const Xi& xi) noexcept {
  const double x1 = xi[0], x2 = xi[1], x3 = xi[2], x4 = xi[3];
  Matrix4 c;
  c << x1, x2, x4, x3,   //
      -x2, x1, -x3, x4,  //
      x4, x3, -x1, -x2,  //
      -x3, x4, x2, -x1;
  return c;
}

Matrix4 FormsMatrix(const State& x) noexcept {
  Matrix4 w;
  w << x[0], x[1], -x[2], -x[3],  //
      x[2], x[3], x[0], x[1],     //
      x[3], -x[2], -x[1], x[0],   //
      x[0], x[1], x[2], x[3];
  return w;
}

Forms QuadraticForms(const State& x) noexcept {
  const double s12 = x[0] * x[0] + x[1] * x[1];
  const double s34 = x[2] * x[2] + x[3] * x[3];
  return Forms(s12 - s34, 2.0 * (x[0] * x[2] + x[1] * x[3]), 2.0 * (x[0] * x[3] - x[1] * x[2]),
               s12 + s34);
}

Matrix4 FormsDynamics(double omega_rad_s, const Delta& d) noexcept {
  const double w = 2.0 * omega_rad_s * d[kScaleFactor];
  const double d1 = d[kDamping], d3 = d[kDampingAnisotropyCos], d4 = d[kDampingAnisotropySin];
  const double d5 = d[kFrequencyAnisotropyCos], d6 = d[kFrequencyAnisotropySin];
  Matrix4 m;
  m << d1, w, -d6, d3,  //
      -w, d1, d5, d4,   //
      d6, -d5, d1, 0,   //
      d3, d4, 0, d1;
  return m;
}

Matrix46 FormsRegressor(double omega_rad_s, const Forms& z) noexcept {
  const double ac = z[kAc], as = z[kAs], k = z[kK], s = z[kS];
  const double w = 2.0 * omega_rad_s;
  Matrix46 m;
  m << ac, w * as, s, 0, 0, -k,  //
      as, -w * ac, 0, s, k, 0,   //
      k, 0, 0, 0, -as, ac,       //
      s, 0, ac, as, 0, 0;
  return m;
}

Matrix4 FirstOrderFormsDistortion(const Xi& xi) noexcept {
  const double x1 = xi[0], x2 = xi[1], x3 = xi[2], x4 = xi[3];
  Matrix4 n;
  n << 1, 0, -2 * x3, -2 * x1,  //
      0, 1, 2 * x2, -2 * x4,    //
      2 * x3, -2 * x2, 1, 0,    //
      -2 * x1, -2 * x4, 0, 1;
  return n;
}

Matrix4 FirstOrderFormsSensitivity(const Forms& r) noexcept {
  const double ac = r[kAc], as = r[kAs], k = r[kK], s = r[kS];
  Matrix4 n;
  n << -2 * s, 0, -2 * k, 0,  //
      0, 2 * k, 0, -2 * s,    //
      0, -2 * as, 2 * ac, 0,  //
      -2 * ac, 0, 0, -2 * as;
  return n;
}

Matrix46 FirstOrderFormsRegressor(double omega_rad_s, const Forms& r, double lambda,
                                  double phi) noexcept {
  const double ac = r[kAc], as = r[kAs], k = r[kK], s = r[kS];
  const double w = omega_rad_s;
  Matrix46 m;
  m << ac, 2 * w * as + 4 * w * phi * k, s, 2 * lambda * as, 0, -k + 2 * phi * as,     //
      as, -2 * w * ac + 4 * w * lambda * s, 0, s - 2 * lambda * ac, k, -2 * phi * ac,  //
      k, -4 * w * phi * ac, 0, 2 * phi * s, -as, ac - 2 * lambda * s,                  //
      s, 4 * w * lambda * as, ac, as + 2 * phi * k, 0, -2 * lambda * k;
  return m;
}

State UndistortExact(const Xi& xi, const Observation& y) noexcept {
  // I + C on u = (x1 + i·x2, x3 + i·x4) is [[1 + p, q], [q, 1 − p]] with p = ξ1 − iξ2, q = ξ4 −
  // iξ3.
  using C = std::complex<double>;
  const C p(xi[0], -xi[1]);
  const C q(xi[3], -xi[2]);
  const C g11 = 1.0 + p, g12 = q, g21 = q, g22 = 1.0 - p;
  const C det = g11 * g22 - g12 * g21;
  const C v1(y[0], y[1]), v2(y[2], y[3]);
  const C u1 = (g22 * v1 - g12 * v2) / det;
  const C u2 = (-g21 * v1 + g11 * v2) / det;
  return State(u1.real(), u1.imag(), u2.real(), u2.imag());
}

State OrbitToState(const Orbit& o) noexcept {
  const double ct = std::cos(o.theta_rad), st = std::sin(o.theta_rad);
  const double cp = std::cos(o.phi_rad), sp = std::sin(o.phi_rad);
  return State(o.a * ct * cp + o.b * st * sp, o.a * ct * sp - o.b * st * cp,
               o.a * st * cp - o.b * ct * sp, o.a * st * sp + o.b * ct * cp);
}

Orbit StateToOrbit(const State& x) noexcept {
  // u = e^{iφ}·(a·(cosθ, sinθ) + i·b·(−sinθ, cosθ)) with u = (x1 + i·x2, x3 + i·x4); a, b and 2θ
  // follow from the forms, then φ from projecting u back on the orbit's shape.
  const Forms z = QuadraticForms(x);
  Orbit o;
  if (z[kS] <= 0.0) return o;
  const double plus = std::sqrt(std::max(0.0, z[kS] + z[kK]));
  const double minus = std::sqrt(std::max(0.0, z[kS] - z[kK]));
  o.a = 0.5 * (plus + minus);
  o.b = 0.5 * (plus - minus);
  // Circular orbit (Ac = As = 0): θ undefined, atan2(0, 0) = 0 by convention, φ absorbs the angle.
  o.theta_rad = 0.5 * std::atan2(z[kAs], z[kAc]);
  using C = std::complex<double>;
  const double ct = std::cos(o.theta_rad), st = std::sin(o.theta_rad);
  const C u1(x[0], x[1]), u2(x[2], x[3]);
  const C projection = C(o.a * ct, o.b * st) * u1 + C(o.a * st, -o.b * ct) * u2;
  o.phi_rad = std::arg(projection);
  return o;
}

}  // namespace hrgbench::estimator
