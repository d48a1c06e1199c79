#pragma once
// parallel::SingleProcess: the default fifth template parameter of Simulation -- one process,
// no MPI. Its Engine holds nothing, and every distributed step of the engine sits behind
// `if constexpr (Parallel::distributed)`, so a program that does not choose MPI compiles to the
// code it compiled to before the policy existed (docs/mpi.md, "The policy"). The distributed
// policy is parallel::MpiDomains (parallel/mpi_domains.hpp, needs MPI).

namespace granule::parallel {

struct SingleProcess {
  static constexpr bool distributed = false;
  static constexpr const char* name = "single";
  /// The per-simulation data of the policy: none.
  template <class D>
  struct Engine {
    Engine() = default;
    explicit Engine(const SingleProcess&) {}
    static constexpr int rank() { return 0; }
    static constexpr int ranks() { return 1; }
  };
};

}  // namespace granule::parallel
