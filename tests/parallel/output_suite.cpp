// Analysis and output of a distributed run (docs/mpi.md, "Analysis and output"), under mpiexec
// with 1, 2 and 4 ranks (tests/CMakeLists.txt), against the same scene in one process:
//
//   1. kinetic, gravitational and elastic energies and the contact count, reduced over the ranks
//      (a pair across two ranks counted once);
//   2. gathered_frame() on rank 0: every particle and contact once; the virial stress
//      (analysis::average_stress) and force-network statistics (mean normal force, strong-force
//      count) computed from it;
//   3. io::PieceVtkWriter: one .vtu piece per rank, a .pvtu naming every piece, a .pvd of the
//      .pvtu files; the pieces' particle counts add up to N, and (where python3 with vtk is
//      found) VTK's own parallel reader opens the .pvtu with N points;
//   4. a CSV time series of the reduced energies written by rank 0 alone.
//
// Equality: with one rank bitwise (the distributed engine is bitwise the one-process run);
// with 2 and 4 the states differ by about 1e-9 r after 200 steps (distributed_suite.cpp), so
// the energies and stresses are compared to 1e-6 relative and the contact counts exactly.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <fstream>
#include <sstream>
#include <string>

#include "granule/analysis/force_network.hpp"
#include "granule/analysis/stress.hpp"
#include "granule/granule.hpp"
#include "granule/io/csv.hpp"
#include "granule/io/vtk_pieces.hpp"
#include "granule/parallel/mpi_domains.hpp"
#include "parallel/common.hpp"

using namespace granule;
using Vec = Dim3::Vec;
using namespace granule::test_parallel;  // check, failures, Single, Distributed, ...

namespace output_suite {

// Compares a with b: bitwise when `exact`, else to `tol` relative to |b| (or to `scale`).
void same(const std::string& what, double a, double b, bool exact, double tol, double scale = 0.0) {
  const double rel = std::abs(a - b) / std::max({std::abs(b), scale, 1e-300});
  std::printf("  %-40s one process %.17g, distributed %.17g, rel %.3g\n", what.c_str(), b, a, rel);
  if (exact)
    check(a == b, what + ": not bitwise the one-process value", 0);
  else
    check(rel <= tol, what + ": differs by more than " + std::to_string(tol) + " relative", 0);
}

// The suite's entry, called by tests/parallel/mpi_suites_main.cpp: argv[0] is the suite's name,
// argv[1..] its arguments.
int run(parallel::MpiContext& mpi, int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "mpi_output";
  return mpi.run([&] {
    const test_parallel::SceneOptions o = test_parallel::sheared_slab();
    const auto config = test_parallel::scene_config(o);
    // The bed: poured and settled in one process (every rank the same), then sheared.
    std::vector<std::pair<Vec, double>> bed;
    {
      test_parallel::SceneOptions still = o;
      still.floor_speed = 0.0;
      Single s(test_parallel::scene_config(still));
      test_parallel::populate(s, still);
      s.run(12000);
      const auto g = s.gather();
      for (std::size_t i = 0; i < g.size(); ++i) bed.push_back({g.x[i], g.radius[i]});
    }
    auto build = [&](auto& sim) {
      test_parallel::populate(sim, o);
      sim.remove_particles([](std::size_t) { return true; });
      for (const auto& [x, r] : bed) sim.add_particle(x, r, 0);
    };
    Single one(config);
    build(one);
    Distributed many(config, parallel::MpiDomains(mpi, parallel::RankGrid{{mpi.size(), 1, 1}}));
    build(many);
    one.run(199);
    many.run(199);
    one.request_contacts();
    many.request_contacts();
    one.run(1);
    many.run(1);
    const bool exact = mpi.size() == 1;
    const double tol = 1e-6;

    // 1. Reduced observables (collective: every rank gets the total).
    const double ek = many.kinetic_energy(), eg = many.gravitational_energy(), ee = many.elastic_energy();
    const std::size_t nc = many.contact_count();
    const double ek1 = one.kinetic_energy(), eg1 = one.gravitational_energy(), ee1 = one.elastic_energy();
    const std::size_t nc1 = one.contact_count();
    std::vector<double> mine{ek, eg, ee, double(nc)}, root = mine;
    MPI_Bcast(root.data(), 4, MPI_DOUBLE, 0, mpi.comm());
    check(mine == root, "the reduced observables differ between ranks", mpi.rank());

    // 2. The gathered frame and the analyses on it.
    const auto fr = many.gathered_frame();
    const auto fr1 = one.gathered_frame();
    // 3. Pieces, .pvtu and .pvd (two frames).
    io::PieceVtkWriter<Dim3> out(dir + "/np" + std::to_string(mpi.size()), "particles");
    out.write(many);
    many.run(10);
    const auto last = out.write(many);
    // 4. CSV from rank 0: every rank computes the reduced values, rank 0 writes them.
    const std::string csv_path = dir + "/np" + std::to_string(mpi.size()) + "/energies.csv";
    {
      std::optional<io::CsvWriter> csv;
      if (mpi.root()) csv.emplace(csv_path, std::vector<io::CsvColumn>{{"time", "s"}, {"kinetic", "J"}, {"contacts", ""}});
      for (int k = 0; k < 3; ++k) {
        many.run(5);
        const double e = many.kinetic_energy();
        const double c = double(many.contact_count());
        if (csv) csv->write_row({many.time(), e, c});
      }
    }

    if (mpi.root()) {
      std::printf("%d ranks (%s):\n", mpi.size(), exact ? "bitwise" : "tolerance 1e-6 relative");
      same("kinetic energy [J]", ek, ek1, exact, tol);
      same("gravitational energy [J]", eg, eg1, exact, tol);
      same("elastic energy [J]", ee, ee1, exact, tol);
      std::printf("  contacts: one process %zu, distributed %zu\n", nc1, nc);
      check(nc == nc1, "contact count differs", 0);
      check(fr.size() == fr1.size() && fr.id == fr1.id, "gathered frame: not every particle once in id order", 0);
      std::printf("  frame contacts: one process %zu, distributed %zu\n", fr1.contacts.size(), fr.contacts.size());
      check(fr.contacts.size() == fr1.contacts.size() && fr.contacts.size() > 0, "gathered frame: contact count", 0);
      const double volume = (config.domain.hi - config.domain.lo).prod();
      const auto s = analysis::average_stress(fr, volume), s1 = analysis::average_stress(fr1, volume);
      const double scale = s1.total().norm();
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          same("virial stress (" + std::to_string(a) + "," + std::to_string(b) + ") [Pa]", s.total()(a, b),
               s1.total()(a, b), exact, tol, scale);
      same("pressure [Pa]", s.pressure(), s1.pressure(), exact, tol);
      same("mean normal force, pairs [N]", analysis::mean_normal_force(fr), analysis::mean_normal_force(fr1), exact, tol);
      same("mean normal force, walls [N]", analysis::mean_normal_force(fr, analysis::ContactKind::Wall),
           analysis::mean_normal_force(fr1, analysis::ContactKind::Wall), exact, tol);
      const std::size_t strong = analysis::count_strong_forces(fr, 2.0), strong1 = analysis::count_strong_forces(fr1, 2.0);
      std::printf("  contacts above 2x the mean normal force: one process %zu, distributed %zu\n", strong1, strong);
      check(strong == strong1, "strong-force count differs", 0);

      // The .pvtu names every rank's piece; the pieces hold N particles together.
      const std::string pvtu = file_contents(last);
      std::size_t pieces = 0, points = 0;
      for (std::size_t at = pvtu.find("<Piece Source=\""); at != std::string::npos;
           at = pvtu.find("<Piece Source=\"", at + 1)) {
        const std::size_t b = at + 15, e = pvtu.find('"', b);
        const std::string piece = pvtu.substr(b, e - b);
        const std::string vtu = file_contents(last.parent_path() / piece);
        const std::size_t k = vtu.find("NumberOfPoints=\"");
        check(k != std::string::npos, "piece " + piece + " missing or unreadable", 0);
        if (k != std::string::npos) points += std::stoul(vtu.substr(k + 16));
        ++pieces;
      }
      std::printf("  %s: %zu pieces, %zu particles\n", last.filename().string().c_str(), pieces, points);
      check(pieces == std::size_t(mpi.size()), "the .pvtu does not name one piece per rank", 0);
      check(points == bed.size(), "the pieces do not hold every particle once", 0);
      const std::string pvd = file_contents(out.pvd_path());
      check(pvd.find("particles_000000.pvtu") != std::string::npos && pvd.find("particles_000001.pvtu") != std::string::npos,
            "the .pvd does not list both frames", 0);
#ifdef GRANULE_PYTHON
      // VTK's parallel reader (what ParaView uses for .pvtu) gives every particle.
      const std::string cmd = std::string(GRANULE_PYTHON) +
                              " -c \"import sys, vtk; r = vtk.vtkXMLPUnstructuredGridReader(); r.SetFileName(sys.argv[1]); "
                              "r.Update(); o = r.GetOutput(); print('vtk reader:', o.GetNumberOfPoints(), 'points,', "
                              "o.GetPointData().GetNumberOfArrays(), 'arrays'); sys.exit(0 if o.GetNumberOfPoints() == " +
                              std::to_string(bed.size()) + " else 1)\" " + last.string();
      check(std::system(cmd.c_str()) == 0, "VTK's reader does not read the .pvtu with every particle", 0);
#endif
      const std::string csv_text = file_contents(csv_path);
      std::size_t lines = 0;
      for (char ch : csv_text) lines += ch == '\n';
      check(lines == 4, "the CSV has " + std::to_string(lines) + " lines, not a header and 3 rows", 0);
    }
    const int total = static_cast<int>(mpi.max(failures));
    if (mpi.root()) std::printf(total == 0 ? "output: OK (%d ranks)\n" : "output: FAILED (%d ranks)\n", mpi.size());
    return total == 0 ? 0 : 1;
  });
}

}  // namespace output_suite
