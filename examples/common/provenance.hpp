#pragma once
// Where a result of an example's study came from: the commit of the build, the date and the
// machine (CPU model, hardware threads and the OpenMP threads used). Every result file of a
// study carries it, so a table in a README can be traced to the run that made it.
#include <algorithm>
#include <ctime>
#include <fstream>
#include <string>
#include <thread>

#ifdef _OPENMP
#include <omp.h>
#endif

#if __has_include("granule_git_info.hpp")
#include "granule_git_info.hpp"  // generated at build time (cmake/git_info.cmake)
#endif
#ifndef GRANULE_GIT_COMMIT
#define GRANULE_GIT_COMMIT "unknown"
#endif

namespace granule::examples {

/// Where and from what a result came.
struct Provenance {
  std::string commit;   ///< git commit of the build ("-dirty" if the tree had changes)
  std::string date;     ///< UTC, ISO 8601
  std::string machine;  ///< CPU model, its hardware threads and the OpenMP threads used
};

inline Provenance provenance_now() {
  Provenance p;
  p.commit = GRANULE_GIT_COMMIT;
  char buf[32];
  const std::time_t t = std::time(nullptr);
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  p.date = buf;
  std::string model = "unknown CPU";
  std::ifstream cpu("/proc/cpuinfo");
  for (std::string line; std::getline(cpu, line);)
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  p.machine = model + " x" + std::to_string(std::max(1u, std::thread::hardware_concurrency()));
#ifdef _OPENMP
  const int threads = omp_get_max_threads();
#else
  const int threads = 1;
#endif
  p.machine += ", " + std::to_string(threads) + (threads == 1 ? " thread" : " threads");
  return p;
}

}  // namespace granule::examples
