#pragma once
// MpiContext: MPI set-up and tear-down for a granule program, the reductions the distributed
// policy needs, and the propagation of errors so that an error on one rank stops every rank
// with that rank's message and no rank hangs (docs/mpi.md, "Errors"). Needs <mpi.h>: link
// granule::mpi (CMake, -DGRANULE_MPI=ON).
//
//   int main(int argc, char** argv) {
//     granule::parallel::MpiContext mpi(argc, argv);
//     return mpi.run([&] { ...; return 0; });   // an escaping exception aborts every rank
//   }
//
// Two levels of error handling:
//  * collective(f): f is local work (no MPI call inside). Every rank calls collective() at the
//    same point; if f threw on any rank, every rank throws the same granule error type
//    (InvalidParameter, InstabilityError, IoError, else std::runtime_error) with the message
//    "rank r of n: <what>" of the lowest failing rank. The engine's own checks (instability,
//    a refused checkpoint) are raised this way, so all ranks can carry on or stop together.
//  * run(f): around the whole program. An exception that escapes f on one rank (when the
//    others may be waiting in a collective call and would never return) is printed by that rank
//    to stderr as "granule: rank r of n: <what>" and ends the job with MPI_Abort.
// An exception that unwinds through the context's destructor also aborts (finalising would
// wait for the other ranks). MPI is initialised with MPI_THREAD_FUNNELED: OpenMP threads run
// inside each rank, and only the thread that set MPI up calls it, outside parallel regions.
// The C API only: the MPI-2 C++ bindings are deprecated and warn under -Wextra.
#ifndef OMPI_SKIP_MPICXX
#define OMPI_SKIP_MPICXX 1
#endif
#ifndef MPICH_SKIP_MPICXX
#define MPICH_SKIP_MPICXX 1
#endif
#include <mpi.h>

#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "granule/core/error.hpp"

namespace granule::parallel {

class MpiContext {
 public:
  /// Initialises MPI unless the program already did (then it is left to the program to
  /// finalise), on the communicator `comm`.
  MpiContext(int& argc, char**& argv, MPI_Comm comm = MPI_COMM_WORLD) : comm_(comm) {
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) {
      int provided = 0;
      MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
      owns_ = true;
      if (provided < MPI_THREAD_FUNNELED) {
        std::fprintf(stderr, "granule: the MPI library does not support MPI_THREAD_FUNNELED\n");
        MPI_Abort(comm_, 1);
      }
    }
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
  }

  MpiContext(const MpiContext&) = delete;
  MpiContext& operator=(const MpiContext&) = delete;

  ~MpiContext() {
    if (!owns_) return;
    int finalised = 0;
    MPI_Finalized(&finalised);
    if (finalised) return;
    if (std::uncaught_exceptions() > 0) {
      std::fprintf(stderr, "granule: rank %d of %d: an exception left the MPI context; aborting\n",
                   rank_, size_);
      std::fflush(stderr);
      MPI_Abort(comm_, 1);
    }
    MPI_Finalize();
  }

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }
  MPI_Comm comm() const { return comm_; }

  void barrier() const { MPI_Barrier(comm_); }

  /// Sum, maximum and minimum over the ranks (MPI_Allreduce: the order of the sum is the
  /// library's, so it may differ in the last bit between rank counts or runs).
  double sum(double x) const { return allreduce(x, MPI_SUM); }
  double max(double x) const { return allreduce(x, MPI_MAX); }
  double min(double x) const { return allreduce(x, MPI_MIN); }
  /// Element-wise sum of equal-length arrays, in place.
  void sum(std::vector<double>& x) const {
    MPI_Allreduce(MPI_IN_PLACE, x.data(), static_cast<int>(x.size()), MPI_DOUBLE, MPI_SUM, comm_);
  }

  /// The sum of one value per rank added in rank order, ((x_0 + x_1) + x_2) + ..., the same
  /// bits on every rank and in every run with this rank count (body forces, docs/mpi.md).
  double sum_in_rank_order(double x) const {
    std::vector<double> all(root() ? static_cast<std::size_t>(size_) : 0);
    MPI_Gather(&x, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, comm_);
    double s = 0.0;
    if (root()) {
      s = all[0];
      for (std::size_t r = 1; r < all.size(); ++r) s += all[r];
    }
    MPI_Bcast(&s, 1, MPI_DOUBLE, 0, comm_);
    return s;
  }

  /// Runs local work f on every rank; if it threw on any rank, every rank throws the lowest
  /// failing rank's error (same type, message "rank r of n: <what>"). f must not call MPI.
  template <class F>
  void collective(F&& f) const {
    Kind kind = Kind::None;
    std::string what;
    try {
      std::forward<F>(f)();
    } catch (const InvalidParameter& e) {
      kind = Kind::Invalid;
      what = e.what();
    } catch (const InstabilityError& e) {
      kind = Kind::Instability;
      what = e.what();
    } catch (const IoError& e) {
      kind = Kind::Io;
      what = e.what();
    } catch (const std::exception& e) {
      kind = Kind::Other;
      what = e.what();
    } catch (...) {
      kind = Kind::Other;
      what = "an exception that is not a std::exception";
    }
    raise_first_error(kind, what);
  }

  /// Runs the program's body; an exception escaping it on any rank is printed by that rank and
  /// ends every rank (MPI_Abort), so none waits forever in a collective call.
  template <class F>
  int run(F&& f) const {
    try {
      return std::forward<F>(f)();
    } catch (const std::exception& e) {
      abort_with(e.what());
    } catch (...) {
      abort_with("an exception that is not a std::exception");
    }
    return 1;  // not reached: MPI_Abort does not return
  }

  /// Prints "granule: rank r of n: <message>" to stderr and aborts every rank.
  [[noreturn]] void abort_with(const std::string& message) const {
    std::fprintf(stderr, "granule: rank %d of %d: %s\n", rank_, size_, message.c_str());
    std::fflush(stderr);
    MPI_Abort(comm_, 1);
    std::terminate();  // MPI_Abort should not return; never continue if it does
  }

 private:
  enum class Kind : int { None = 0, Invalid = 1, Instability = 2, Io = 3, Other = 4 };

  double allreduce(double x, MPI_Op op) const {
    double r = 0.0;
    MPI_Allreduce(&x, &r, 1, MPI_DOUBLE, op, comm_);
    return r;
  }

  /// Collective: the lowest rank with an error broadcasts its kind and message, and every rank
  /// throws them.
  void raise_first_error(Kind kind, const std::string& what) const {
    const int mine = kind == Kind::None ? size_ : rank_;
    int first = size_;
    MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm_);
    if (first == size_) return;
    int head[2] = {static_cast<int>(kind), static_cast<int>(what.size())};
    MPI_Bcast(head, 2, MPI_INT, first, comm_);
    std::string text(static_cast<std::size_t>(head[1]), '\0');
    if (rank_ == first) text = what;
    MPI_Bcast(text.data(), head[1], MPI_CHAR, first, comm_);
    const std::string message =
        "rank " + std::to_string(first) + " of " + std::to_string(size_) + ": " + text;
    switch (static_cast<Kind>(head[0])) {
      case Kind::Invalid: throw InvalidParameter(message);
      case Kind::Instability: throw InstabilityError(message);
      case Kind::Io: throw IoError(message);
      default: throw std::runtime_error(message);
    }
  }

  MPI_Comm comm_;
  int rank_ = 0;
  int size_ = 1;
  bool owns_ = false;
};

}  // namespace granule::parallel
