// Test program for parallel/mpi_context.hpp, run by ctest under mpirun with 2 and 4 ranks
// (tests/CMakeLists.txt, only with GRANULE_MPI=ON). Not a Catch2 file: every rank runs every
// check, the failures are summed over the ranks and rank 0 reports; the exit code is 0 only if
// no rank failed.
//
//   mpi_context_main          reductions and collective errors; prints "mpi_context: OK"
//   mpi_context_main abort    rank 1 throws inside MpiContext::run while the other ranks wait
//                             in a barrier: the job must end (ctest's timeout catches a hang)
//                             and the output must hold rank 1's message (ctest's regex).
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "granule/parallel/mpi_context.hpp"

namespace {

int failures = 0;

void expect(bool ok, const granule::parallel::MpiContext& mpi, const std::string& what) {
  if (ok) return;
  ++failures;
  std::fprintf(stderr, "rank %d of %d: FAILED: %s\n", mpi.rank(), mpi.size(), what.c_str());
}

/// The error every rank must see from collective(f), as "<type>|<message>", or "none".
template <class F>
std::string collective_outcome(const granule::parallel::MpiContext& mpi, F&& f) {
  try {
    mpi.collective(std::forward<F>(f));
  } catch (const granule::InvalidParameter& e) {
    return std::string("InvalidParameter|") + e.what();
  } catch (const granule::InstabilityError& e) {
    return std::string("InstabilityError|") + e.what();
  } catch (const granule::IoError& e) {
    return std::string("IoError|") + e.what();
  } catch (const std::runtime_error& e) {
    return std::string("runtime_error|") + e.what();
  }
  return "none";
}

int checks(const granule::parallel::MpiContext& mpi) {
  const int r = mpi.rank(), n = mpi.size();
  const std::string of_n = " of " + std::to_string(n) + ": ";
  expect(n >= 2, mpi, "run with at least 2 ranks");
  expect(r >= 0 && r < n, mpi, "rank within [0, size)");

  // Reductions of small integers are exact in any order.
  expect(mpi.sum(1.0) == n, mpi, "sum of 1 over the ranks is the rank count");
  expect(mpi.sum(double(r)) == n * (n - 1) / 2.0, mpi, "sum of the ranks");
  expect(mpi.max(double(r)) == n - 1, mpi, "max of the ranks");
  expect(mpi.min(double(r) - 7.5) == -7.5, mpi, "min of rank - 7.5");
  std::vector<double> v{double(r), 1.0, double(r * r)};
  mpi.sum(v);
  double squares = 0.0;
  for (int k = 0; k < n; ++k) squares += double(k) * k;
  expect(v[0] == n * (n - 1) / 2.0 && v[1] == n && v[2] == squares, mpi, "element-wise sum");

  // The rank-order sum is bitwise the sequential sum ((x0 + x1) + x2) + ..., on every rank.
  auto value = [](int k) { return 0.1 * (k + 1) + 1e-17 * k; };
  double sequential = value(0);
  for (int k = 1; k < n; ++k) sequential += value(k);
  expect(mpi.sum_in_rank_order(value(r)) == sequential, mpi, "sum in rank order is the sequential sum");

  // No error anywhere: nothing is thrown.
  expect(collective_outcome(mpi, [] {}) == "none", mpi, "collective without an error");

  // The last rank fails: every rank throws its error, type and message.
  const std::string last = std::to_string(n - 1);
  expect(collective_outcome(mpi, [&] {
           if (r == n - 1) throw granule::InstabilityError("step 12: particle 7 ran away");
         }) == "InstabilityError|rank " + last + of_n + "step 12: particle 7 ran away",
         mpi, "an instability on the last rank reaches every rank");

  // Two ranks fail with different errors: the lowest failing rank's wins, everywhere.
  expect(collective_outcome(mpi, [&] {
           if (r == 1) throw granule::IoError("cannot write out/frame.vtu: disk full");
           if (r == n - 1 && n > 2) throw std::logic_error("later rank");
         }) == "IoError|rank 1" + of_n + "cannot write out/frame.vtu: disk full",
         mpi, "the lowest failing rank's error wins");
  expect(collective_outcome(mpi, [&] {
           if (r == 0) throw granule::InvalidParameter("Decomposition: ranks = 0 is outside the valid range [1, inf)");
         }) == "InvalidParameter|rank 0" + of_n + "Decomposition: ranks = 0 is outside the valid range [1, inf)",
         mpi, "an InvalidParameter keeps its type");
  expect(collective_outcome(mpi, [&] {
           if (r == n - 1) throw std::out_of_range("index 9");
         }) == "runtime_error|rank " + last + of_n + "index 9",
         mpi, "other exceptions arrive as std::runtime_error");

  // The communicator still works after the errors (no message left in flight).
  expect(mpi.sum(2.0) == 2.0 * n, mpi, "reductions after the errors");

  const double failed = mpi.sum(double(failures));
  if (mpi.root()) std::printf(failed == 0 ? "mpi_context: OK (%d ranks)\n" : "mpi_context: FAILED (%d ranks)\n", n);
  return failed == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  granule::parallel::MpiContext mpi(argc, argv);
  const bool abort_mode = argc > 1 && std::string(argv[1]) == "abort";
  return mpi.run([&] {
    if (!abort_mode) return checks(mpi);
    // Rank 1 fails while the others wait in a collective call that it never joins.
    if (mpi.rank() == 1) throw granule::IoError("deliberate failure on rank 1");
    mpi.barrier();
    std::printf("rank %d passed the barrier: the abort did not stop it\n", mpi.rank());
    return 1;
  });
}
