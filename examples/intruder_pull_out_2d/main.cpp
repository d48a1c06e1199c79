// Paper 002: a thin intruder pulled up at constant speed out of a 2D bed of disks. Writes the drag
// force and friction mobilisation against the intruder height, the drag's power spectrum and
// coarse-grained velocity maps (normalised by V) at a few heights. See README.md and scene.hpp.
//
//   intruder_pull_out_2d [--paper] [--width M] [--bed-height M] [--E PA] [--velocity M/S]
//                        [--seed N] [--out DIR]
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <granule/io/csv.hpp>
#include <granule/io/progress.hpp>

#include "scene.hpp"

using namespace granule;
namespace po = granule::examples::pull_out;

int main(int argc, char** argv) {
  po::PullParams p;
  std::filesystem::path out = "out/intruder_pull_out_2d";
  auto usage = [](std::FILE* f) {
    std::fprintf(f,
                 "usage: intruder_pull_out_2d [options]\n"
                 "  --paper             paper 002 values: W = 0.1 m, bed 0.15 m, E = 64 GPa, V = 1.2e-3 m/s\n"
                 "                      (very long: ~1e9 steps)\n"
                 "  --width M           cell width W [m] (quick: 0.04)\n"
                 "  --bed-height M      target bed height [m] (quick: 0.05)\n"
                 "  --E PA              Young's modulus, k_n = E d [Pa] (quick: 2e7)\n"
                 "  --velocity M/S      intruder speed V [m/s] (quick: 0.02)\n"
                 "  --sample-travel M   intruder travel per drag sample [m] (quick: 2e-4)\n"
                 "  --seed N            insertion seed (1)\n"
                 "  --out DIR           output directory (out/intruder_pull_out_2d)\n");
  };
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    auto next = [&]() -> std::string {
      if (a + 1 >= argc) { std::fprintf(stderr, "%s needs a value\n", arg.c_str()); std::exit(2); }
      return argv[++a];
    };
    if (arg == "--paper") {
      const auto keep_seed = p.seed;
      p = po::paper_params();
      p.seed = keep_seed;
    } else if (arg == "--width") p.cell_width = std::stod(next());
    else if (arg == "--bed-height") p.bed_height = std::stod(next());
    else if (arg == "--E") p.youngs_modulus = std::stod(next());
    else if (arg == "--velocity") p.pull_velocity = std::stod(next());
    else if (arg == "--sample-travel") p.sample_travel = std::stod(next());
    else if (arg == "--seed") p.seed = std::stoull(next());
    else if (arg == "--out") out = next();
    else if (arg == "--help") { usage(stdout); return 0; }
    else { usage(stderr); return 2; }
  }
  std::filesystem::create_directories(out);

  io::ProgressReporter fill_progress({.label = "fill"});
  auto s = po::build(p, [&](std::uint64_t n, double t) { fill_progress.update(n, t); });
  fill_progress.finish(s.sim->step_count(), s.sim->time());
  const double d = p.mean_diameter;
  std::fprintf(stderr, "bed: %zu disks, height %.4f m, settled %s, dt %.3g s, V/sqrt(g d) = %.3g\n", s.particles,
               s.bed_height, s.settled ? "yes" : "no", s.sim->dt(), p.pull_velocity / std::sqrt(9.81 * d));

  const double final_height = s.bed_height + d;
  const double travel = final_height - s.intruder_y0;
  std::vector<double> map_heights;
  for (double f : {0.1, 0.3, 0.5, 0.7}) map_heights.push_back(s.intruder_y0 + f * travel);
  io::ProgressReporter progress({.end_time = travel / p.pull_velocity, .label = "pull"});
  const auto r = po::pull(s, final_height, map_heights,
                          [&](double t) { progress.update(s.sim->step_count(), t); });
  progress.finish(s.sim->step_count(), travel / p.pull_velocity);

  {
    io::CsvWriter csv(out / "drag.csv", {{"time", "s"}, {"intruder_height", "m"}, {"drag_force", "N"},
                                         {"mu_star_bulk", ""}, {"mu_star_walls", ""}, {"intruder_contacts", ""}},
                      {.flush_every_row = false});
    for (const auto& x : r.samples)
      csv.write_row({x.time, x.height, x.drag, x.mu_star_bulk, x.mu_star_wall, double(x.contacts_intruder)});
  }
  {
    io::CsvWriter csv(out / "drag_spectrum.csv", {{"frequency", "Hz"}, {"wavelength", "m"}, {"psd", "N^2/Hz"}},
                      {.flush_every_row = false});
    for (std::size_t k = 1; k < r.spectrum.frequency.size(); ++k)
      csv.write_row({r.spectrum.frequency[k], p.pull_velocity / r.spectrum.frequency[k], r.spectrum.psd[k]});
  }
  for (const auto& m : r.maps) {
    char name[64];
    std::snprintf(name, sizeof name, "velocity_map_h%03.0fmm.csv", m.height * 1e3);
    io::CsvWriter csv(out / name, {{"x", "m"}, {"y", "m"}, {"vx_over_V", ""}, {"vy_over_V", ""},
                                   {"speed_over_V", ""}, {"packing_fraction", ""}},
                      {.flush_every_row = false});
    for (std::size_t i = 0; i < m.fields.size(); ++i) {
      const po::Vec x = m.fields.grid.node(i);
      const po::Vec v = m.fields.velocity[i] / p.pull_velocity;
      csv.write_row({x.x(), x.y(), v.x(), v.y(), v.norm(), m.fields.packing_fraction[i]});
    }
  }
  const double f_peak = r.spectrum.psd.size() >= 3 ? analysis::peak_frequency(r.spectrum) : 0.0;
  std::printf("%zu disks, bed height %.1f mm, pull %.1f -> %.1f mm at V = %.3g m/s\n", s.particles,
              s.bed_height * 1e3, s.intruder_y0 * 1e3, final_height * 1e3, p.pull_velocity);
  std::printf("drag: mean %.4g N, std %.4g N, max %.4g N; spectral peak %.3g Hz (wavelength %.3g mm)\n",
              r.mean_drag, r.std_drag, [&] { double m = 0; for (auto& x : r.samples) m = std::max(m, x.drag); return m; }(),
              f_peak, f_peak > 0 ? p.pull_velocity / f_peak * 1e3 : 0.0);
  std::printf("output in %s\n", out.string().c_str());
  return 0;
}
