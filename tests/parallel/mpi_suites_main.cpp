// The distributed test suites in one program, run under mpiexec by ctest (tests/CMakeLists.txt,
// label mpi): `granule_mpi_suites <suite> [arguments]` with the suite
//
//   distributed  the distributed engine against one process (distributed_suite.cpp)
//   checkpoint   checkpoints written and restarted across rank counts (checkpoint_suite.cpp)
//   output       reductions, gathered frames, VTK pieces and CSV (output_suite.cpp)
//   rebalance    the runtime load balance (rebalance_suite.cpp)
//
// One program, compiled as one translation unit (a unity build), because every suite compares
// the same two engines (parallel/common.hpp: Single, Distributed): their templates are then
// instantiated and optimised once instead of four times (README, "Development": build times).
#include <cstdio>
#include <cstring>

#include "granule/parallel/mpi_context.hpp"

namespace distributed_suite {
int run(granule::parallel::MpiContext& mpi, int argc, char** argv);
}
namespace checkpoint_suite {
int run(granule::parallel::MpiContext& mpi, int argc, char** argv);
}
namespace output_suite {
int run(granule::parallel::MpiContext& mpi, int argc, char** argv);
}
namespace rebalance_suite {
int run(granule::parallel::MpiContext& mpi, int argc, char** argv);
}

int main(int argc, char** argv) {
  granule::parallel::MpiContext mpi(argc, argv);
  const char* suite = argc > 1 ? argv[1] : "";
  // Each suite sees its own name as argv[0] and its arguments from argv[1] on.
  if (std::strcmp(suite, "distributed") == 0) return distributed_suite::run(mpi, argc - 1, argv + 1);
  if (std::strcmp(suite, "checkpoint") == 0) return checkpoint_suite::run(mpi, argc - 1, argv + 1);
  if (std::strcmp(suite, "output") == 0) return output_suite::run(mpi, argc - 1, argv + 1);
  if (std::strcmp(suite, "rebalance") == 0) return rebalance_suite::run(mpi, argc - 1, argv + 1);
  if (mpi.root())
    std::printf("usage: %s distributed|checkpoint|output|rebalance [arguments]\n",
                argc > 0 ? argv[0] : "granule_mpi_suites");
  return 2;
}
