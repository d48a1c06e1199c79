#pragma once
// Neighbour-search policies. All three produce the same half list (each touching pair once,
// stored in the row of one of its particles) consumed by one pair loop; they differ in how the
// list is built and when it is rebuilt.
//
//   BruteForce   O(N^2) candidate test every step, no spatial sort, serial pair loop: the
//                reference every other policy is tested against.
//   LinkedCells  cell binning (cell >= interaction range) every step, no skin.
//   VerletList   cell binning with a skin; rebuilt only when some particle (or wall) has moved
//                more than half the skin since the last build (Verlet 1967; Allen & Tildesley).
// The cell policies sort particles by cell on every build (memory locality) and split rows into
// layers of cells along the longest axis; the pair loop runs layers in three colours so that
// no two threads touch the same particle (see docs/architecture.md, "determinism").
namespace granule::neighbours {

struct BruteForce {
  static constexpr bool uses_cells = false;
  static constexpr bool rebuild_every_step = true;
  static constexpr const char* name = "BruteForce";
};

struct LinkedCells {
  static constexpr bool uses_cells = true;
  static constexpr bool rebuild_every_step = true;
  static constexpr const char* name = "LinkedCells";
};

struct VerletList {
  static constexpr bool uses_cells = true;
  static constexpr bool rebuild_every_step = false;
  static constexpr const char* name = "VerletList";
};

}  // namespace granule::neighbours
