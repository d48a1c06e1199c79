// Downstream use of granule::mpi: the installed MPI headers of granule compile through the
// target, and the program runs as a single process (an MPI singleton) that owns the whole box.
#include <granule/parallel/decomposition.hpp>
#include <granule/parallel/mpi_context.hpp>

#include <iostream>

int main(int argc, char** argv) {
  granule::parallel::MpiContext mpi(argc, argv);
  return mpi.run([&] {
    granule::Domain<granule::Dim3> box;
    const auto grid = granule::parallel::choose_grid(box, mpi.size());
    const granule::parallel::Decomposition<granule::Dim3> dec(box, grid);
    if (mpi.size() != 1 || dec.owner(granule::Dim3::Vec(0.5, 0.5, 0.5)) != 0) return 1;
    if (mpi.sum(2.0) != 2.0) return 2;
    std::cout << "OK\n";
    return 0;
  });
}
