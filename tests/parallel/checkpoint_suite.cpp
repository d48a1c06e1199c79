// Checkpoints of a distributed run (docs/mpi.md, "Checkpoints"), under mpiexec (tests/CMakeLists.txt):
//
//   save <dir>         a settled bed sheared along periodic x, split across the ranks (grid R x 1 x 1),
//                      run N steps in one process and distributed; both write a checkpoint at N
//                      (one_np<R>.ckpt from one process, dist_np<R>.ckpt from R ranks). Then, each
//                      run on K steps and compared with the one-process run continued:
//                        the uninterrupted distributed run;
//                        the distributed file restarted on the same R ranks;
//                        the one-process file restarted on R ranks;
//                        the distributed file restarted in one process (rank 0);
//                      a file read and written again at once (distributed, and in one process)
//                      is the same file, byte for byte;
//                      and the faults: a write that fails on rank 0 throws on every rank and leaves
//                      the previous file byte for byte; a corrupted file and a file of another
//                      scene (other time step) are refused on every rank with the reason named,
//                      leaving the simulation as it was.
//   load <file> <one>  a distributed file written with another rank count restarted on this one,
//                      against the one-process file <one> restarted in one process (which is
//                      bitwise the uninterrupted one-process run: tests/restart/test_checkpoint.cpp).
//
// Equality: to the tolerance of tests/parallel/distributed_suite.cpp (1e-7 r, 1e-6 m/s, 1e-3 1/s,
// 1e-7 relative floor force over the first 400 steps of a settled bed). Not bitwise, even on the
// rank count that wrote the file: the file holds no build positions and a one-process list, so a
// restart rebuilds its list at its first step (histories carried by key), where the
// uninterrupted run did not; the new list orders the force sums differently (last bits).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "granule/granule.hpp"
#include "granule/io/checkpoint.hpp"
#include "granule/parallel/mpi_domains.hpp"
#include "parallel/common.hpp"

using namespace granule;
using Vec = Dim3::Vec;
using namespace granule::test_parallel;  // check, failures, Single, Distributed, ...

namespace checkpoint_suite {

constexpr std::uint64_t kSave = 100, kAfter = 300;  // steps before the checkpoint, after it

// On rank 0: `got` against the reference, to the stated tolerance.
void judge(const std::string& name, const GatheredParticles<Dim3>& got, const Vec& f_got,
           const GatheredParticles<Dim3>& ref, const Vec& f_ref, const Domain<Dim3>& dom) {
  const test_parallel::Difference d = test_parallel::compare_gathered(got, ref, f_got, f_ref, dom);
  std::printf("%s: max |dx|/r %.3g, |dv| %.3g m/s, |domega| %.3g 1/s, floor force rel %.3g\n", name.c_str(), d.dx,
              d.dv, d.dw, d.floor);
  check(d.same_ids, name + ": not every particle once in id order", 0);
  check(d.dx < 1e-7, name + ": positions differ by more than 1e-7 r", 0);
  check(d.dv < 1e-6, name + ": velocities differ by more than 1e-6 m/s", 0);
  check(d.dw < 1e-3, name + ": angular velocities differ by more than 1e-3 1/s", 0);
  check(d.floor < 1e-7, name + ": the floor force differs by more than 1e-7 relative", 0);
}

// The scene as a restart builds it: materials, walls and bodies; its particles are replaced by
// the checkpoint's.
template <class Sim>
void scene_only(Sim& sim, const test_parallel::SceneOptions& o) {
  test_parallel::populate(sim, o);
}

// `f` must throw IoError on every rank with a message containing `why`.
template <class F>
void expect_io_error(const parallel::MpiContext& mpi, const std::string& name, const std::string& why, F&& f) {
  std::string what = "(nothing thrown)";
  try {
    f();
  } catch (const IoError& e) {
    what = e.what();
  } catch (const std::exception& e) {
    what = std::string("(not an IoError) ") + e.what();
  }
  const bool ok = what.find(why) != std::string::npos && what.rfind("(not", 0) != 0;
  check(ok, name + ": expected an IoError naming \"" + why + "\", got \"" + what + "\"", mpi.rank());
  if (ok && mpi.root()) std::printf("%s: refused on every rank: %s\n", name.c_str(), what.c_str());
}

void save_mode(const parallel::MpiContext& mpi, const std::string& dir) {
  const auto o = test_parallel::sheared_slab();
  const auto config = test_parallel::scene_config(o);
  const auto bed = test_parallel::settled_bed(o, 12000);
  const std::string R = std::to_string(mpi.size());
  const std::string one_file = dir + "/one_np" + R + ".ckpt", dist_file = dir + "/dist_np" + R + ".ckpt";
  if (mpi.root()) std::filesystem::create_directories(dir);
  MPI_Barrier(mpi.comm());

  // The one-process run, its checkpoint (rank 0) and its state K steps on.
  Single one(config);
  test_parallel::populate_bed(one, o, bed);
  one.run(kSave);
  if (mpi.root()) io::write_checkpoint(one, one_file);
  one.run(kAfter);
  const auto ref = one.gather();
  const Vec f_ref = one.wall(0).force;
  MPI_Barrier(mpi.comm());

  // The distributed run, its checkpoint, and its state K steps on.
  const parallel::RankGrid grid{{mpi.size(), 1, 1}};
  Distributed many(config, parallel::MpiDomains(mpi, grid));
  test_parallel::populate_bed(many, o, bed);
  many.run(kSave);
  const auto at_save = many.gather();
  io::write_checkpoint(many, dist_file);
  const auto after_write = many.gather();
  if (mpi.root())
    check(at_save.x == after_write.x && at_save.v == after_write.v, "writing a checkpoint changed the run", 0);
  many.run(kAfter);
  const auto g_many = many.gather();
  if (mpi.root()) judge("uninterrupted, " + R + " ranks", g_many, many.wall(0).force, ref, f_ref, config.domain);

  // The distributed file on the same rank count.
  {
    Distributed again(config, parallel::MpiDomains(mpi, grid));
    scene_only(again, o);
    io::read_checkpoint(again, dist_file);
    check(again.step_count() == kSave, "restart: step count not restored", mpi.rank());
    // Written again at once, the state gives the same file, byte for byte.
    io::write_checkpoint(again, dir + "/again_np" + R + ".ckpt");
    if (mpi.root())
      check(file_contents(dir + "/again_np" + R + ".ckpt") == file_contents(dist_file),
            "restart: the file written again right after reading differs from the file read", 0);
    const auto loaded = again.gather();
    if (mpi.root()) {
      check(loaded.id == at_save.id && loaded.x == at_save.x && loaded.v == at_save.v && loaded.f == at_save.f &&
                loaded.omega == at_save.omega,
            "restart: the state read back is not the state written, bit for bit", 0);
    }
    again.run(kAfter);
    const auto g = again.gather();
    if (mpi.root()) {
      judge("distributed file restarted on " + R + " ranks, against one process", g, again.wall(0).force, ref, f_ref,
            config.domain);
      judge("distributed file restarted on " + R + " ranks, against the uninterrupted " + R + "-rank run", g,
            again.wall(0).force, g_many, many.wall(0).force, config.domain);
    }
  }
  // The one-process file on R ranks.
  {
    Distributed from_one(config, parallel::MpiDomains(mpi));
    scene_only(from_one, o);
    io::read_checkpoint(from_one, one_file);
    from_one.run(kAfter);
    const auto g = from_one.gather();
    if (mpi.root())
      judge("one-process file restarted on " + R + " ranks", g, from_one.wall(0).force, ref, f_ref, config.domain);
  }
  // The distributed file in one process.
  if (mpi.root()) {
    Single solo(config);
    scene_only(solo, o);
    io::read_checkpoint(solo, dist_file);
    check(solo.particles().owned() == bed.size(), "one process: not every particle read", 0);
    io::write_checkpoint(solo, dir + "/solo_np" + R + ".ckpt");
    check(file_contents(dir + "/solo_np" + R + ".ckpt") == file_contents(dist_file),
          "one process: the distributed file written again by one process differs", 0);
    solo.run(kAfter);
    judge("distributed file restarted in one process", solo.gather(), solo.wall(0).force, ref, f_ref, config.domain);
  }
  MPI_Barrier(mpi.comm());

  // Faults. A write that fails on rank 0 (its temporary name is taken by a directory): every
  // rank throws, the previous file is unchanged.
  const std::string before = mpi.root() ? file_contents(dist_file) : std::string();
  if (mpi.root()) std::filesystem::create_directory(dist_file + ".tmp");
  MPI_Barrier(mpi.comm());
  expect_io_error(mpi, "failed write", "write_checkpoint", [&] { io::write_checkpoint(many, dist_file); });
  if (mpi.root()) {
    check(file_contents(dist_file) == before, "failed write: the previous checkpoint changed", 0);
    std::filesystem::remove(dist_file + ".tmp");
  }
  // A corrupted copy and a file of another scene: refused on every rank, the simulation unchanged.
  const std::string bad_file = dir + "/corrupt_np" + R + ".ckpt", other_file = dir + "/other_np" + R + ".ckpt";
  if (mpi.root()) {
    std::string b = before;
    b[b.size() / 2] ^= 0x20;
    std::ofstream(bad_file, std::ios::binary) << b;
  }
  auto other_config = config;
  other_config.dt = 0.5 * config.dt;
  {
    Distributed other(other_config, parallel::MpiDomains(mpi, grid));
    test_parallel::populate_bed(other, o, bed);
    other.run(2);
    io::write_checkpoint(other, other_file);
  }
  const auto state_before = many.gather();
  expect_io_error(mpi, "corrupted file", "checksum mismatch", [&] { io::read_checkpoint(many, bad_file); });
  expect_io_error(mpi, "other scene", "time step", [&] { io::read_checkpoint(many, other_file); });
  expect_io_error(mpi, "missing file", "read_checkpoint", [&] { io::read_checkpoint(many, dir + "/none.ckpt"); });
  const auto state_after = many.gather();
  if (mpi.root())
    check(state_before.x == state_after.x && state_before.v == state_after.v, "a refused file changed the run", 0);
  many.run(10);  // still runs (every rank still in step)
}

void load_mode(const parallel::MpiContext& mpi, const std::string& file, const std::string& one_file) {
  const auto o = test_parallel::sheared_slab();
  const auto config = test_parallel::scene_config(o);
  Distributed sim(config, parallel::MpiDomains(mpi));
  scene_only(sim, o);
  io::read_checkpoint(sim, file);
  sim.run(kAfter);
  const auto g = sim.gather();
  const auto parts = sim.parallel_engine().decomposition->grid().parts;
  if (!mpi.root()) return;
  Single ref(config);
  scene_only(ref, o);
  io::read_checkpoint(ref, one_file);
  ref.run(kAfter);
  judge("'" + std::filesystem::path(file).filename().string() + "' restarted on " + std::to_string(mpi.size()) +
            " ranks (grid " + std::to_string(parts[0]) + "x" + std::to_string(parts[1]) + "x" +
            std::to_string(parts[2]) + ")",
        g, sim.wall(0).force, ref.gather(), ref.wall(0).force, config.domain);
}

// The suite's entry, called by tests/parallel/mpi_suites_main.cpp: argv[0] is the suite's name,
// argv[1..] its arguments.
int run(parallel::MpiContext& mpi, int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "save";
  return mpi.run([&] {
    if (mode == "save" && argc > 2) {
      save_mode(mpi, argv[2]);
    } else if (mode == "load" && argc > 3) {
      load_mode(mpi, argv[2], argv[3]);
    } else {
      if (mpi.root()) std::printf("usage: %s save <dir> | load <file> <one-process file>\n", argv[0]);
      return 2;
    }
    const int total = static_cast<int>(mpi.max(failures));
    if (mpi.root())
      std::printf(total == 0 ? "checkpoint %s: OK (%d ranks)\n" : "checkpoint %s: FAILED (%d ranks)\n", mode.c_str(),
                  mpi.size());
    return total == 0 ? 0 : 1;
  });
}

}  // namespace checkpoint_suite
