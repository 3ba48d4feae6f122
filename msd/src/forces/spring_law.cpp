#include "msd/forces/spring_law.hpp"

#include <cmath>
#include <sstream>

namespace msd {

const char* to_string(EdgeClass c) {
  switch (c) {
    case EdgeClass::axis: return "axis";
    case EdgeClass::face_diagonal: return "face_diagonal";
    case EdgeClass::other: return "other";
  }
  return "other";
}

EdgeClass classify_edge(const Vec3& d) {
  const double tol = 1e-6 * d.norm();
  int nonzero = 0;
  double first = 0.0;
  bool equal = true;
  for (int c = 0; c < 3; ++c) {
    const double a = std::abs(d[c]);
    if (a <= tol) continue;
    if (nonzero++ == 0)
      first = a;
    else if (std::abs(a - first) > tol)
      equal = false;
  }
  if (nonzero == 1) return EdgeClass::axis;
  if (nonzero == 2 && equal) return EdgeClass::face_diagonal;
  return EdgeClass::other;
}

void check_spring_law(const SpringLaw& law, const std::string& where) {
  const auto fail = [&](const char* field, const char* rule, double v) {
    std::ostringstream s;
    s << where << "." << field << " must be " << rule << " (got " << v << ")";
    throw Error(s.str());
  };
  if (!(std::isfinite(law.stiffness) && law.stiffness > 0.0)) fail("stiffness", "positive and finite", law.stiffness);
  // A negative exponent lets phi' change sign: a spring that softens to zero
  // stiffness and then pushes the wrong way.
  if (!(std::isfinite(law.tension_exponent) && law.tension_exponent >= 0.0))
    fail("tension_exponent", ">= 0 (a negative one makes the law non-monotonic)", law.tension_exponent);
  if (!(std::isfinite(law.compression_exponent) && law.compression_exponent >= 0.0))
    fail("compression_exponent", ">= 0 (a negative one makes the law non-monotonic)", law.compression_exponent);
  if (law.tension_exponent + law.compression_exponent == 0.0)
    fail("tension_exponent", "positive when compression_exponent is 0 (the law would have no stiffness)",
         law.tension_exponent);
}

double spring_law_tension(double m, double n, double stretch) {
  return (std::pow(stretch, m) - std::pow(stretch, -n)) / (m + n);
}

double spring_law_slope(double m, double n, double stretch) {
  return (m * std::pow(stretch, m - 1.0) + n * std::pow(stretch, -n - 1.0)) / (m + n);
}

namespace {
// P_p(lambda) = (lambda^p - 1) / p, ln lambda at p = 0.
double power_integral(double p, double stretch) {
  return p == 0.0 ? std::log(stretch) : (std::pow(stretch, p) - 1.0) / p;
}
}  // namespace

double spring_law_energy(double m, double n, double stretch) {
  return (power_integral(m + 1.0, stretch) - power_integral(1.0 - n, stretch)) / (m + n);
}

Mat3 spring_law_jacobian(const Vec3& l, double rest, double ks, double m, double n) {
  const double length = l.norm();
  const Vec3 u = l / length;
  const double lambda = length / rest;
  const double across = rest * spring_law_tension(m, n, lambda) / length;
  const Mat3 uu = u * u.transpose();
  return ks * (spring_law_slope(m, n, lambda) * uu + across * (Mat3::Identity() - uu));
}

}  // namespace msd
