#pragma once
// Binary checkpoints for exact restarts.
//
// Layout: magic "GRANULE\x01CKPT", format version, byte-order mark, dimension, the contact
// model's signature, the neighbour policy and integrator names, a user section (e.g. the RNG
// state of an insertion), the simulation's dynamic state, the payload length and an FNV-1a
// checksum of everything before it. Running 2N steps equals running N, writing, reading back and
// running N more, bitwise (tests/io/test_checkpoint.cpp).
// Writes are atomic: the file is written under a temporary name and renamed over the target,
// so a crash mid-write never leaves a corrupt checkpoint. Truncated, foreign or mismatched files
// (other dimension, contact model, search or integrator) are refused with IoError.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "granule/core/error.hpp"
#include "granule/io/binary.hpp"

namespace granule::io {

inline constexpr char kCheckpointMagic[12] = {'G', 'R', 'A', 'N', 'U', 'L', 'E', '\x01', 'C', 'K', 'P', 'T'};
// 2: the neighbour list keeps history for touching pairs only (slots and per-layer pools).
// 3: the build positions are floats, followed by their rounding (neighbours/pair_list.hpp).
// 4: per wall, whether it is active and the force and torque of the particles on it. Version 3
//    files are still read (every wall active, wall readouts zero until the next step), so cached
//    beds stay usable.
inline constexpr std::uint32_t kCheckpointVersion = 4;

namespace detail {
inline std::uint64_t fnv1a(const std::uint8_t* p, std::size_t n) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

template <class Sim>
std::string scene_signature() {
  return std::string("dim=") + std::to_string(Sim::Dimension::dim) + ";" +
         Sim::ContactModelType::signature() + ";search=" + Sim::SearchPolicy::name +
         ";integrator=" + Sim::IntegratorPolicy::name;
}
}  // namespace detail

/// Writes sim's state to `path` atomically. `user` is stored verbatim (e.g. RNG state).
template <class Sim>
void write_checkpoint(Sim& sim, const std::string& path, const std::vector<std::uint64_t>& user = {}) {
  BinaryWriter w;
  for (char c : kCheckpointMagic) w.pod(c);
  w.pod(kCheckpointVersion);
  w.pod<std::uint32_t>(0x01020304u);  // byte-order mark
  w.pod<std::uint32_t>(Sim::Dimension::dim);
  w.str(detail::scene_signature<Sim>());
  w.vec(user);
  sim.save_state(w);
  const std::uint64_t len = w.bytes().size();
  const std::uint64_t sum = detail::fnv1a(w.bytes().data(), w.bytes().size());
  w.pod(len);
  w.pod(sum);

  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError("write_checkpoint: cannot open '" + tmp + "' for writing");
    out.write(reinterpret_cast<const char*>(w.bytes().data()), static_cast<std::streamsize>(w.bytes().size()));
    out.flush();
    if (!out) throw IoError("write_checkpoint: writing '" + tmp + "' failed (disk full?)");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw IoError("write_checkpoint: cannot rename '" + tmp + "' to '" + path + "': " + ec.message());
}

/// Restores sim (already set up with the same scene) from `path`; returns the user section.
template <class Sim>
std::vector<std::uint64_t> read_checkpoint(Sim& sim, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("read_checkpoint: cannot open '" + path + "'");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  BinaryReader r(bytes.data(), bytes.size(), path);
  if (bytes.size() < sizeof(kCheckpointMagic) + 16) r.fail("too short to be a granule checkpoint");
  for (char c : kCheckpointMagic)
    if (r.pod<char>() != c) r.fail("not a granule checkpoint (bad magic)");
  const auto version = r.pod<std::uint32_t>();
  if (version != kCheckpointVersion && version != 3)
    r.fail("format version " + std::to_string(version) + " is not supported (this build reads 3 and " +
           std::to_string(kCheckpointVersion) + ")");
  if (r.pod<std::uint32_t>() != 0x01020304u) r.fail("written on a machine with another byte order");
  // Integrity before anything else: length and checksum sit at the end.
  if (bytes.size() < 16) r.fail("truncated");
  const std::size_t body = bytes.size() - 16;
  std::uint64_t len = 0, sum = 0;
  std::memcpy(&len, bytes.data() + body, 8);
  std::memcpy(&sum, bytes.data() + body + 8, 8);
  if (len != body) r.fail("truncated or extended (length field " + std::to_string(len) + ", data " + std::to_string(body) + " bytes)");
  if (sum != detail::fnv1a(bytes.data(), body)) r.fail("checksum mismatch (corrupted file)");
  const auto dim = r.pod<std::uint32_t>();
  if (dim != static_cast<std::uint32_t>(Sim::Dimension::dim))
    r.fail("written by a " + std::to_string(dim) + "D simulation, this one is " + std::to_string(Sim::Dimension::dim) + "D");
  const std::string sig = r.str();
  const std::string want = detail::scene_signature<Sim>();
  if (sig != want) r.fail("written with '" + sig + "', this simulation is '" + want + "'");
  std::vector<std::uint64_t> user;
  r.vec(user);
  sim.load_state(r, /*wall_states=*/version >= 4);
  if (r.position() != body) r.fail("unexpected trailing data");
  return user;
}

}  // namespace granule::io
