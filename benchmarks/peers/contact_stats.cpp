// Contact statistics of a sphere packing read from a LAMMPS data file: the number of touching
// particle pairs (overlap delta = r_i + r_j - |x_i - x_j| > 0) and their mean overlap.
// The same tool is applied to the end state of every code (granule, LIGGGHTS, LAMMPS), so the
// numbers compare like with like; wall contacts are not counted. Cell binning with cells of
// at least the largest contact distance, minimum image in periodic directions.
// Usage: contact_stats DATAFILE PERIODIC_XYZ   (e.g. 100 = periodic in x only)
// Output: one line "particles=N contacts=C mean_overlap=M max_overlap=X" (overlaps in m).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "granule/io/lammps_data.hpp"

int main(int argc, char** argv) {
  if (argc != 3 || std::string(argv[2]).size() != 3) {
    std::fprintf(stderr, "usage: %s DATAFILE PERIODIC_XYZ (e.g. 100)\n", argv[0]);
    return 2;
  }
  try {
    const auto data = granule::io::read_lammps_data(argv[1]);
    const auto& f = data.frame;
    const std::string flags = argv[2];
    const std::size_t n = f.size();
    double r_max = 0.0;
    for (double r : f.radius) r_max = std::max(r_max, r);
    const double reach = 2.0 * r_max;  // [m] largest possible contact distance
    std::array<int, 3> cells{};
    std::array<double, 3> length{}, cell_size{};
    std::array<bool, 3> periodic{};
    for (int k = 0; k < 3; ++k) {
      periodic[k] = flags[static_cast<std::size_t>(k)] == '1';
      length[k] = f.box_hi[k] - f.box_lo[k];
      cells[k] = std::max(1, static_cast<int>(std::floor(length[k] / reach)));
      // fewer than 3 cells in a periodic direction would visit a neighbour twice
      if (periodic[k] && cells[k] < 3) cells[k] = 1;
      cell_size[k] = length[k] / cells[k];
    }
    auto cell_of = [&](const granule::Dim3::Vec& x, int k) {
      const int c = static_cast<int>(std::floor((x[k] - f.box_lo[k]) / cell_size[k]));
      return std::clamp(c, 0, cells[k] - 1);
    };
    const std::size_t n_cells = static_cast<std::size_t>(cells[0]) * cells[1] * cells[2];
    std::vector<std::size_t> start(n_cells + 1, 0), order(n), cell_index(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& x = f.x[i];
      cell_index[i] = (static_cast<std::size_t>(cell_of(x, 2)) * cells[1] + cell_of(x, 1)) *
                          cells[0] + cell_of(x, 0);
      ++start[cell_index[i] + 1];
    }
    for (std::size_t c = 0; c < n_cells; ++c) start[c + 1] += start[c];
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) order[fill[cell_index[i]]++] = i;

    std::size_t contacts = 0;
    double sum = 0.0, max_overlap = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const auto& xi = f.x[i];
      const int ci[3] = {cell_of(xi, 0), cell_of(xi, 1), cell_of(xi, 2)};
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int d[3] = {dx, dy, dz};
            int c[3];
            bool skip = false;
            for (int k = 0; k < 3; ++k) {
              c[k] = ci[k] + d[k];
              if (cells[k] == 1) {
                if (d[k] != 0) skip = true;  // a single cell holds every neighbour
              } else if (c[k] < 0 || c[k] >= cells[k]) {
                if (periodic[k]) c[k] = (c[k] + cells[k]) % cells[k];
                else skip = true;
              }
            }
            if (skip) continue;
            const std::size_t cell =
                (static_cast<std::size_t>(c[2]) * cells[1] + c[1]) * cells[0] + c[0];
            for (std::size_t s = start[cell]; s < start[cell + 1]; ++s) {
              const std::size_t j = order[s];
              if (j <= i) continue;
              granule::Dim3::Vec dxv = f.x[j] - xi;
              for (int k = 0; k < 3; ++k)
                if (periodic[k]) dxv[k] -= length[k] * std::round(dxv[k] / length[k]);
              const double overlap = f.radius[i] + f.radius[j] - dxv.norm();
              if (overlap > 0.0) {
                ++contacts;
                sum += overlap;
                max_overlap = std::max(max_overlap, overlap);
              }
            }
          }
    }
    std::printf("particles=%zu contacts=%zu mean_overlap=%.6e max_overlap=%.6e\n", n, contacts,
                contacts ? sum / static_cast<double>(contacts) : 0.0, max_overlap);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "contact_stats: %s\n", e.what());
    return 1;
  }
  return 0;
}
