// Paper 002: a thin intruder pulled up at constant speed out of a 2D bed of disks. Writes the drag
// force and friction mobilisation against the intruder height, the drag's power spectrum and
// coarse-grained velocity maps (normalised by V) at a few heights. See README.md and scene.hpp.
//
//   intruder_pull_out_2d [--paper | --medium] [--width M] [--bed-height M] [--E PA] [--velocity M/S]
//                        [--fill-rate 1/S] [--fill-source-width M] [--fill-release-height M]
//                        [--fill-friction MU] [--seed N] [--out DIR]
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
                 "  --medium            paper cell and bed (W = 0.1 m, bed 0.15 m) with the quick E and V\n"
                 "  --sample-travel M   intruder travel per drag sample [m] (quick: 2e-4)\n"
                 "  --fill-rate N       disks released per second while filling [1/s]; 0: all at once\n"
                 "  --fill-source-width M   width of the release region, centred [m]; 0: whole cell\n"
                 "  --fill-release-height M height of the release region above the floor [m]; 0: 3 x bed\n"
                 "  --fill-friction MU  friction while filling (mu restored before settling); -1: mu\n"
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
    } else if (arg == "--medium") {
      const auto q = po::paper_params();
      p.cell_width = q.cell_width;
      p.bed_height = q.bed_height;
      p.fill_rate = q.fill_rate;
    } else if (arg == "--width") p.cell_width = std::stod(next());
    else if (arg == "--bed-height") p.bed_height = std::stod(next());
    else if (arg == "--E") p.youngs_modulus = std::stod(next());
    else if (arg == "--velocity") p.pull_velocity = std::stod(next());
    else if (arg == "--sample-travel") p.sample_travel = std::stod(next());
    else if (arg == "--fill-rate") p.fill_rate = std::stod(next());
    else if (arg == "--fill-source-width") p.fill_source_width = std::stod(next());
    else if (arg == "--fill-release-height") p.fill_release_height = std::stod(next());
    else if (arg == "--fill-friction") p.fill_friction = std::stod(next());
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
  const auto& pk = s.packing;
  std::printf("bed: mean surface %.1f mm (top of the 5 highest disks %.1f mm); packing fraction %.3f in the interior "
              "(%zu slabs %.3f-%.3f), %.3f over the whole bed; filled and settled in %.2f s simulated\n",
              pk.surface * 1e3, s.bed_height * 1e3, pk.interior, pk.slabs, pk.interior_min, pk.interior_max, pk.whole,
              s.fill_sim_time);
  {
    io::CsvWriter csv(out / "bed.csv", {{"disks", ""}, {"mean_surface", "m"}, {"top_surface", "m"},
                                        {"phi_interior", ""}, {"phi_interior_min", ""}, {"phi_interior_max", ""},
                                        {"phi_whole", ""}, {"fill_time", "s"}, {"settled", ""}},
                      {.flush_every_row = false});
    csv.write_row({double(s.particles), pk.surface, s.bed_height, pk.interior, pk.interior_min, pk.interior_max,
                   pk.whole, s.fill_sim_time, s.settled ? 1.0 : 0.0});
  }

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
