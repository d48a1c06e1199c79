// Re-writes a LAMMPS/LIGGGHTS sphere data file with granule's writer, at rest (no Velocities).
// Used to turn the stand-in beds settled by LIGGGHTS into the hand-over format that granule's
// settled beds will have, so that the peer inputs are tested on exactly that format.
// Usage: rewrite_data IN OUT PERIODIC_XYZ   (PERIODIC_XYZ e.g. 100 = periodic in x only)
#include <array>
#include <cstdio>
#include <exception>
#include <string>

#include "granule/io/lammps_data.hpp"

int main(int argc, char** argv) {
  if (argc != 4 || std::string(argv[3]).size() != 3) {
    std::fprintf(stderr, "usage: %s IN OUT PERIODIC_XYZ (e.g. 100)\n", argv[0]);
    return 2;
  }
  try {
    const auto data = granule::io::read_lammps_data(argv[1]);
    const std::string flags = argv[3];
    const std::array<bool, 3> periodic = {flags[0] == '1', flags[1] == '1', flags[2] == '1'};
    // One density for all particles (the reference scenes are monodisperse, one material).
    const double density = data.density.empty() ? 1.0 : data.density.front();
    granule::io::write_lammps_data(argv[2], data.frame, data.frame.box_lo, data.frame.box_hi,
                                   density, periodic, /*with_velocities=*/false);
    std::printf("%zu particles written to %s\n", data.frame.size(), argv[2]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rewrite_data: %s\n", e.what());
    return 1;
  }
  return 0;
}
