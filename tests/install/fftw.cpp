// Downstream use of granule::fftw: FFTW3 must be found and linked through the installed package.
// The DFT of a unit impulse is 1 at every frequency.
#include <fftw3.h>

#include <cmath>
#include <iostream>

int main() {
  const int n = 8;
  fftw_complex* in = fftw_alloc_complex(n);
  fftw_complex* out = fftw_alloc_complex(n);
  fftw_plan plan = fftw_plan_dft_1d(n, in, out, FFTW_FORWARD, FFTW_ESTIMATE);
  for (int k = 0; k < n; ++k) in[k][0] = in[k][1] = 0.0;
  in[0][0] = 1.0;
  fftw_execute(plan);
  int bad = 0;
  for (int k = 0; k < n; ++k) bad += std::abs(out[k][0] - 1.0) > 1e-14 || std::abs(out[k][1]) > 1e-14;
  fftw_destroy_plan(plan);
  fftw_free(in);
  fftw_free(out);
  if (bad != 0) return 1;
  std::cout << "OK\n";
  return 0;
}
