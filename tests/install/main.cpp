// Downstream use of an installed granule: headers, Eigen and the error helpers, built optimised.
#include <granule/core/dimension.hpp>
#include <granule/core/error.hpp>

#include <iostream>

int main() {
#ifndef __OPTIMIZE__
  // The README's recipe (and this test) configure with -DCMAKE_BUILD_TYPE=Release.
  std::cout << "built without optimisation\n";
  return 3;
#endif
  const granule::Dim<3>::Vec x(1.0, 2.0, 3.0);
  if (x.sum() != 6.0) return 1;
  try {
    const double radius = -1.0;  // [m]
    granule::require(radius > 0.0, "consumer", "radius", radius, "(0, inf)");
    return 2;  // a negative radius must be rejected
  } catch (const granule::InvalidParameter& e) {
    std::cout << "rejected as expected: " << e.what() << '\n';
  }
  std::cout << "OK\n";
  return 0;
}
