// Downstream use of granule::mpi: the program sees <mpi.h> through the target, and runs as a
// single process (an MPI singleton) that owns the whole box.
#include <mpi.h>

#include <granule/parallel/decomposition.hpp>

#include <iostream>

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int ranks = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  granule::Domain<granule::Dim3> box;
  const auto grid = granule::parallel::choose_grid(box, ranks);
  const granule::parallel::Decomposition<granule::Dim3> dec(box, grid);
  const int owner = dec.owner(granule::Dim3::Vec(0.5, 0.5, 0.5));
  MPI_Finalize();
  if (ranks != 1 || owner != 0) return 1;
  std::cout << "OK\n";
  return 0;
}
