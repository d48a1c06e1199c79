#pragma once
// Binary checkpoints for exact restarts.
//
// Layout: magic "GRANULE\x01CKPT", format version, byte-order mark, dimension, the contact
// model's signature, the neighbour policy and integrator names, a user section (e.g. the RNG
// state of an insertion), the scene's materials (format 5), the simulation's dynamic state, the
// payload length and an FNV-1a checksum of everything before it. Running 2N steps equals running
// N, writing, reading back and running N more, bitwise (tests/restart/test_checkpoint.cpp).
// Writes are atomic and durable: the file is written under a temporary name, flushed to disk,
// renamed over the target and the directory flushed (io/file.hpp), so a crash or a power loss
// mid-write never leaves a corrupt checkpoint, and a failed write leaves no temporary file.
// Truncated, foreign or mismatched files (other dimension, contact model, search, integrator,
// time step, counts of bodies, walls and materials, group modes, or other materials) are
// refused with IoError, and so is a state with an index out of range or a value that is not
// finite. A refused file leaves the simulation as it was: everything is checked before any of
// it is used (Simulation::load_state_format).
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "granule/core/error.hpp"
#include "granule/io/binary.hpp"
#include "granule/io/file.hpp"
#include "granule/materials/material.hpp"
#include "granule/materials/pair_material.hpp"

namespace granule::io {

inline constexpr char kCheckpointMagic[12] = {'G', 'R', 'A', 'N', 'U', 'L', 'E', '\x01', 'C', 'K', 'P', 'T'};
// 2: the neighbour list keeps history for touching pairs only (slots and per-layer pools).
// 3: the build positions are floats, followed by their rounding (neighbours/pair_list.hpp).
// 4: per wall, whether it is active and the force and torque of the particles on it.
// 5: the materials (each one's parameters and the pair table, set_pair included) after the user
//    section, and the time origin (time and step of the last dt change) after the state, so
//    that time() = t0 + (steps since) x dt continues bitwise.
// Versions 3 and 4 are still read (3: every wall active, wall readouts zero until the next step;
// both: materials unchecked, time counted on from the stored time), so cached beds stay usable.
inline constexpr std::uint32_t kCheckpointVersion = 5;
inline constexpr std::uint32_t kOldestCheckpointVersion = 3;

/// Options of read_checkpoint.
struct CheckpointReadOptions {
  /// Load into a scene whose materials differ from the checkpoint's (e.g. a bed poured with
  /// one friction coefficient, then sheared with another). Their number must still agree; the
  /// particles keep the masses they were written with.
  bool allow_other_materials = false;
};

namespace detail {
inline std::uint64_t fnv1a(const std::uint8_t* p, std::size_t n) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

// The parameters a checkpoint records per material and per material pair, by name.
struct MaterialField {
  const char* name;
  double Material::*member;
};
inline constexpr MaterialField kMaterialFields[] = {
    {"youngs_modulus", &Material::youngs_modulus},
    {"poisson_ratio", &Material::poisson_ratio},
    {"density", &Material::density},
    {"restitution", &Material::restitution},
    {"friction", &Material::friction},
    {"rolling_friction", &Material::rolling_friction},
    {"rolling_damping", &Material::rolling_damping},
    {"cohesion_energy_density", &Material::cohesion_energy_density},
    {"surface_energy", &Material::surface_energy},
    {"normal_stiffness", &Material::normal_stiffness},
    {"reference_length", &Material::reference_length},
    {"tangential_stiffness_ratio", &Material::tangential_stiffness_ratio},
    {"rolling_stiffness_factor", &Material::rolling_stiffness_factor},
    {"rolling_stiffness", &Material::rolling_stiffness},
};
struct PairField {
  const char* name;
  double PairMaterial::*member;
};
inline constexpr PairField kPairFields[] = {
    {"E_eff", &PairMaterial::E_eff},
    {"G_eff", &PairMaterial::G_eff},
    {"restitution", &PairMaterial::restitution},
    {"mu_s", &PairMaterial::mu_s},
    {"mu_r", &PairMaterial::mu_r},
    {"rolling_damping", &PairMaterial::rolling_damping},
    {"k_c", &PairMaterial::k_c},
    {"surface_energy", &PairMaterial::surface_energy},
    {"k_n_linear", &PairMaterial::k_n_linear},
    {"kt_ratio", &PairMaterial::kt_ratio},
    {"rolling_stiffness_factor", &PairMaterial::rolling_stiffness_factor},
    {"k_roll", &PairMaterial::k_roll},
};

template <class Sim>
void write_materials(BinaryWriter& w, const Sim& sim) {
  const auto& table = sim.materials();
  const auto n = static_cast<std::uint32_t>(table.size());
  w.pod<std::uint64_t>(n);
  for (std::uint32_t a = 0; a < n; ++a) {
    w.str(table[a].name);
    w.pod<std::uint8_t>(sim.is_wall_material(a) ? 1 : 0);
    w.pod<std::uint8_t>(table[a].rigid ? 1 : 0);
    for (const auto& f : kMaterialFields) w.pod<double>(table[a].*f.member);
  }
  for (std::uint32_t a = 0; a < n; ++a)
    for (std::uint32_t b = 0; b < n; ++b)
      for (const auto& f : kPairFields) w.pod<double>(table.pair(a, b).*f.member);
}

// Reads the materials section and says how it differs from sim's materials ("" if it does not).
// The names are labels: they are reported, not compared.
template <class Sim>
std::string compare_materials(BinaryReader& r, const Sim& sim) {
  const auto& table = sim.materials();
  const auto n = r.pod<std::uint64_t>();
  // (Each pair costs 96 bytes: a crafted count cannot allocate more than the file holds.)
  if (n > 0 && (n > (std::uint64_t(1) << 20) || n * n * sizeof(double) * std::size(kPairFields) > r.size()))
    r.fail("the materials section announces " + std::to_string(n) + " materials");
  std::vector<std::string> diffs;
  const auto text = granule::detail::to_text<double>;
  const auto label = [&](std::uint64_t a, const std::string& name) {
    return "material " + std::to_string(a) + " ('" + name + "')";
  };
  struct Recorded {
    std::string name;
    bool wall, rigid;
    std::vector<double> values;
  };
  std::vector<Recorded> rec(static_cast<std::size_t>(n));
  for (auto& m : rec) {
    m.name = r.str();
    m.wall = r.pod<std::uint8_t>() != 0;
    m.rigid = r.pod<std::uint8_t>() != 0;
    for (std::size_t k = 0; k < std::size(kMaterialFields); ++k) m.values.push_back(r.pod<double>());
  }
  std::vector<double> pairs(static_cast<std::size_t>(n * n) * std::size(kPairFields));
  for (double& v : pairs) v = r.pod<double>();
  if (n != table.size())
    return "it has " + std::to_string(n) + " materials, the scene " + std::to_string(table.size());
  for (std::uint32_t a = 0; a < n; ++a) {
    const Recorded& m = rec[a];
    const Material& now = table[a];
    if (m.wall != sim.is_wall_material(a))
      diffs.push_back(label(a, now.name) + " is a " + (m.wall ? "wall" : "particle") + " material in the checkpoint, a " +
                      (m.wall ? "particle" : "wall") + " material in the scene");
    if (m.rigid != now.rigid)
      diffs.push_back(label(a, now.name) + " is " + (m.rigid ? "" : "not ") + "rigid in the checkpoint, " +
                      (now.rigid ? "" : "not ") + "rigid in the scene");
    for (std::size_t k = 0; k < std::size(kMaterialFields); ++k) {
      const double was = m.values[k], is = now.*kMaterialFields[k].member;
      if (std::memcmp(&was, &is, sizeof(double)) != 0)
        diffs.push_back(label(a, now.name) + ": " + kMaterialFields[k].name + " " + text(was) + " in the checkpoint, " +
                        text(is) + " in the scene");
    }
  }
  // The pair table follows from the materials unless set_pair changed it: report it only then.
  if (diffs.empty()) {
    std::size_t at = 0;
    for (std::uint32_t a = 0; a < n; ++a)
      for (std::uint32_t b = 0; b < n; ++b)
        for (const auto& f : kPairFields) {
          const double was = pairs[at++], is = table.pair(a, b).*f.member;
          if (a <= b && std::memcmp(&was, &is, sizeof(double)) != 0)
            diffs.push_back("pair (" + std::to_string(a) + ", " + std::to_string(b) + "): " + f.name + " " + text(was) +
                            " in the checkpoint, " + text(is) + " in the scene (set_pair)");
        }
  }
  std::string out;
  for (std::size_t k = 0; k < diffs.size(); ++k) out += (k ? "; " : "") + diffs[k];
  return out;
}

template <class Sim>
std::string scene_signature() {
  return std::string("dim=") + std::to_string(Sim::Dimension::dim) + ";" +
         Sim::ContactModelType::signature() + ";search=" + Sim::SearchPolicy::name +
         ";integrator=" + Sim::IntegratorPolicy::name;
}
}  // namespace detail

/// Writes sim's state and materials to `path` atomically and durably. `user` is stored
/// verbatim (e.g. RNG state). Throws IoError with the system's reason when the file cannot be
/// written; then no temporary file is left and an existing `path` is unchanged.
template <class Sim>
void write_checkpoint(Sim& sim, const std::string& path, const std::vector<std::uint64_t>& user = {}) {
  BinaryWriter w;
  for (char c : kCheckpointMagic) w.pod(c);
  w.pod(kCheckpointVersion);
  w.pod<std::uint32_t>(0x01020304u);  // byte-order mark
  w.pod<std::uint32_t>(Sim::Dimension::dim);
  w.str(detail::scene_signature<Sim>());
  w.vec(user);
  detail::write_materials(w, sim);
  static_assert(Sim::kStateFormat == kCheckpointVersion, "save_state's layout is this format's");
  if constexpr (!Sim::ParallelPolicy::distributed) {
    sim.save_state(w);
    const std::uint64_t len = w.bytes().size();
    const std::uint64_t sum = detail::fnv1a(w.bytes().data(), w.bytes().size());
    w.pod(len);
    w.pod(sum);
    write_file_atomically(path, w.bytes().data(), w.bytes().size(), "write_checkpoint", /*durable=*/true);
  } else {
    // Distributed (collective): the state is gathered to rank 0, which writes the one-process
    // format atomically as above; its outcome is broadcast, so every rank returns or every rank
    // throws (a failed write leaves the previous file as it was).
    const auto& E = sim.parallel_engine();
    std::exception_ptr mine;
    std::string error;
    try {
      sim.save_state(w);
      if (E.context().root()) {
        const std::uint64_t len = w.bytes().size();
        const std::uint64_t sum = detail::fnv1a(w.bytes().data(), w.bytes().size());
        w.pod(len);
        w.pod(sum);
        write_file_atomically(path, w.bytes().data(), w.bytes().size(), "write_checkpoint", /*durable=*/true);
      }
    } catch (const std::exception& e) {
      mine = std::current_exception();
      error = e.what();
    }
    E.broadcast(error);
    if (mine) std::rethrow_exception(mine);  // (an error thrown on every rank keeps its type)
    if (!error.empty()) throw IoError("rank 0 of " + std::to_string(E.ranks()) + ": " + error);
  }
}

/// Restores sim (already set up with the same scene) from `path`; returns the user section.
/// On any error (IoError) sim is left exactly as it was. A scene whose materials differ from the
/// checkpoint's is refused with the differences named, unless options.allow_other_materials.
template <class Sim>
std::vector<std::uint64_t> read_checkpoint_bytes(Sim& sim, const std::string& file, const std::string& path,
                                                 const CheckpointReadOptions& options);

/// Distributed (collective): rank 0 reads the file and every rank receives its bytes and checks
/// them all before taking anything over, so a refused file is refused on every rank with the
/// same message. The state is re-decomposed for this run's rank count at the next step.
template <class Sim>
std::vector<std::uint64_t> read_checkpoint(Sim& sim, const std::string& path,
                                           const CheckpointReadOptions& options = {}) {
  if constexpr (!Sim::ParallelPolicy::distributed) {
    return read_checkpoint_bytes(sim, read_file(path, "read_checkpoint"), path, options);
  } else {
    const auto& E = sim.parallel_engine();
    std::string file, error;
    if (E.context().root()) {
      try {
        file = read_file(path, "read_checkpoint");
      } catch (const std::exception& e) {
        error = e.what();
      }
    }
    E.broadcast(error);
    if (!error.empty()) throw IoError(error);
    E.broadcast(file);
    // The same bytes and the same scene on every rank: the checks agree. (Should they not,
    // no rank is left waiting: the outcome is agreed before anyone returns.)
    std::exception_ptr mine;
    std::vector<std::uint64_t> user;
    try {
      user = read_checkpoint_bytes(sim, file, path, options);
    } catch (...) {
      mine = std::current_exception();
    }
    const bool failed = E.any(mine != nullptr);
    if (mine) std::rethrow_exception(mine);
    if (failed) throw IoError("read_checkpoint: '" + path + "' was refused on another rank");
    return user;
  }
}

/// read_checkpoint on bytes already read from `path`.
template <class Sim>
std::vector<std::uint64_t> read_checkpoint_bytes(Sim& sim, const std::string& file, const std::string& path,
                                                 const CheckpointReadOptions& options) {
  const auto* data = reinterpret_cast<const std::uint8_t*>(file.data());
  BinaryReader whole(data, file.size(), path);
  if (file.size() < sizeof(kCheckpointMagic) + 16) whole.fail("too short to be a granule checkpoint");
  for (char c : kCheckpointMagic)
    if (whole.pod<char>() != c) whole.fail("not a granule checkpoint (bad magic)");
  const auto version = whole.pod<std::uint32_t>();
  if (version < kOldestCheckpointVersion || version > kCheckpointVersion)
    whole.fail("format version " + std::to_string(version) + " is not supported (this build reads " +
               std::to_string(kOldestCheckpointVersion) + " to " + std::to_string(kCheckpointVersion) + ")");
  if (whole.pod<std::uint32_t>() != 0x01020304u) whole.fail("written on a machine with another byte order");
  // Integrity before anything else: length and checksum sit at the end.
  const std::size_t body = file.size() - 16;
  std::uint64_t len = 0, sum = 0;
  std::memcpy(&len, data + body, 8);
  std::memcpy(&sum, data + body + 8, 8);
  if (len != body) whole.fail("truncated or extended (length field " + std::to_string(len) + ", data " + std::to_string(body) + " bytes)");
  if (sum != detail::fnv1a(data, body)) whole.fail("checksum mismatch (corrupted file)");
  // The payload alone from here: reading into the length and checksum is truncation.
  BinaryReader r(data, body, path);
  r.skip(whole.position());
  const auto dim = r.pod<std::uint32_t>();
  if (dim != static_cast<std::uint32_t>(Sim::Dimension::dim))
    r.fail("written by a " + std::to_string(dim) + "D simulation, this one is " + std::to_string(Sim::Dimension::dim) + "D");
  const std::string sig = r.str();
  const std::string want = detail::scene_signature<Sim>();
  if (sig != want) r.fail("written with '" + sig + "', this simulation is '" + want + "'");
  std::vector<std::uint64_t> user;
  r.vec(user);
  if (version >= 5) {
    const std::string diff = detail::compare_materials(r, sim);
    if (!diff.empty() && !options.allow_other_materials)
      r.fail("its materials differ from the scene's: " + diff +
             " (CheckpointReadOptions::allow_other_materials loads it anyway)");
  }
  sim.load_state_format(r, version, /*whole=*/true);
  return user;
}

}  // namespace granule::io
