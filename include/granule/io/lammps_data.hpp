#pragma once
// LAMMPS data files for spheres: the hand-over format between granule and its peer codes.
//
// A settled bed made by granule is written once and read by LAMMPS and LIGGGHTS with
// `read_data`, so every code starts a benchmark from the same particles; the end states are
// read back for comparison. Format (LAMMPS manual, command `read_data`, atom_style sphere;
// LIGGGHTS 3.8 `read_data` with atom_style sphere/granular reads the same layout):
//
//   <title line>
//   <N> atoms
//   <T> atom types
//   <xlo> <xhi> xlo xhi        (likewise y and z)
//   Atoms # sphere
//   <id> <type> <diameter> <density> <x> <y> <z> [<ix> <iy> <iz>]
//   Velocities
//   <id> <vx> <vy> <vz> <wx> <wy> <wz>
//
// The mass of a sphere follows from m = rho * 4/3 pi r^3. Ids in the file are 1-based
// (LAMMPS rejects id 0): the writer stores frame.id + 1 and the reader returns id - 1, so a
// round trip keeps granule's ids. Numbers are written in the shortest form that reads back to
// the identical double (std::to_chars), so a round trip is exact. 3D only: LAMMPS and LIGGGHTS
// interpret `density` of 2D disks differently, and the peer benchmarks are 3D.
#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "granule/analysis/frame.hpp"
#include "granule/core/dimension.hpp"
#include "granule/core/error.hpp"
#include "granule/io/file.hpp"

namespace granule::io {

/// Contents of a LAMMPS sphere data file. `frame` holds x, v, omega, radius, mass, id (sorted by
/// id), box_lo and box_hi; a data file does not record periodicity, so frame.periodic is all
/// false. `type` and `density` are per particle, in the order of `frame`.
struct LammpsData {
  analysis::Frame<Dim3> frame;
  std::vector<std::uint32_t> type;  ///< LAMMPS atom type (1-based)
  std::vector<double> density;      ///< [kg/m^3]
};

namespace detail {

inline void append_number(std::string& out, double value) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, value);
  out.append(buf, res.ptr);
}

inline void append_number(std::string& out, std::uint64_t value) {
  char buf[24];
  const auto res = std::to_chars(buf, buf + sizeof buf, value);
  out.append(buf, res.ptr);
}

/// Splits a line into whitespace-separated tokens, dropping a trailing '#' comment.
inline std::vector<std::string_view> split_tokens(std::string_view line) {
  const auto hash = line.find('#');
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  std::vector<std::string_view> tokens;
  std::size_t pos = 0;
  while (pos < line.size()) {
    while (pos < line.size() && std::isspace(static_cast<unsigned char>(line[pos]))) ++pos;
    const std::size_t start = pos;
    while (pos < line.size() && !std::isspace(static_cast<unsigned char>(line[pos]))) ++pos;
    if (pos > start) tokens.push_back(line.substr(start, pos - start));
  }
  return tokens;
}

inline double parse_double(std::string_view token, const std::string& where) {
  double value = 0.0;
  const auto res = std::from_chars(token.data(), token.data() + token.size(), value);
  if (res.ec != std::errc() || res.ptr != token.data() + token.size()) {
    throw IoError(where + ": '" + std::string(token) + "' is not a number");
  }
  return value;
}

inline std::uint64_t parse_count(std::string_view token, const std::string& where) {
  std::uint64_t value = 0;
  const auto res = std::from_chars(token.data(), token.data() + token.size(), value);
  if (res.ec != std::errc() || res.ptr != token.data() + token.size()) {
    throw IoError(where + ": '" + std::string(token) + "' is not a non-negative integer");
  }
  return value;
}

/// A line that starts a section ("Atoms", "Velocities", ...) begins with a letter.
inline bool is_keyword_line(const std::vector<std::string_view>& tokens) {
  return !tokens.empty() && std::isalpha(static_cast<unsigned char>(tokens.front().front()));
}

}  // namespace detail

/// Writes `frame` as a LAMMPS data file (atom_style sphere) with the box [box_lo, box_hi] [m]
/// and one `density` [kg/m^3] for all particles, all of atom type 1. In periodic directions
/// positions are wrapped into [lo, hi); in the others each centre must lie inside the box.
/// A Velocities section (v and omega; omega zero if frame.omega is empty) is written when
/// `with_velocities` is true and frame.v is filled; otherwise the codes start at rest.
/// Throws InvalidParameter for a bad box, density, radius or position, IoError if the file
/// cannot be written.
inline void write_lammps_data(const std::string& path, const analysis::Frame<Dim3>& frame,
                              const Dim3::Vec& box_lo,   // [m]
                              const Dim3::Vec& box_hi,   // [m]
                              double density,            // [kg/m^3]
                              const std::array<bool, 3>& periodic, bool with_velocities = true) {
  const std::string where = "write_lammps_data";
  const std::size_t n = frame.x.size();
  require_positive(density, where, "density");
  for (int k = 0; k < 3; ++k) {
    require_finite(box_lo[k], where, "box_lo[" + std::to_string(k) + "]");
    require(box_hi[k] > box_lo[k] && std::isfinite(box_hi[k]), where,
            "box_hi[" + std::to_string(k) + "]", box_hi[k],
            "(box_lo[" + std::to_string(k) + "], inf) = (" + granule::detail::to_text(box_lo[k]) +
                ", inf)");
  }
  require(frame.radius.size() == n, where, "frame.radius.size()",
          static_cast<double>(frame.radius.size()), "{frame.x.size()}");
  require(frame.id.empty() || frame.id.size() == n, where, "frame.id.size()",
          static_cast<double>(frame.id.size()), "{0, frame.x.size()}");
  const bool write_v = with_velocities && !frame.v.empty();
  if (write_v) {
    require(frame.v.size() == n, where, "frame.v.size()", static_cast<double>(frame.v.size()),
            "{0, frame.x.size()}");
    require(frame.omega.empty() || frame.omega.size() == n, where, "frame.omega.size()",
            static_cast<double>(frame.omega.size()), "{0, frame.x.size()}");
  }
  constexpr std::uint64_t kMaxId = 2147483647;  // LAMMPS default tagint is 32-bit signed

  std::string out;
  out.reserve(160 * n * (write_v ? 2 : 1) + 256);
  out += "LAMMPS data file written by granule (atom_style sphere)\n\n";
  detail::append_number(out, static_cast<std::uint64_t>(n));
  out += " atoms\n1 atom types\n\n";
  const char* axis_names[3] = {" xlo xhi\n", " ylo yhi\n", " zlo zhi\n"};
  for (int k = 0; k < 3; ++k) {
    detail::append_number(out, box_lo[k]);
    out += ' ';
    detail::append_number(out, box_hi[k]);
    out += axis_names[k];
  }
  out += "\nAtoms # sphere\n\n";
  std::vector<std::uint64_t> ids(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t id = frame.id.empty() ? i + 1 : frame.id[i] + 1;
    require(id >= 1 && id <= kMaxId, where, "frame.id[" + std::to_string(i) + "]",
            static_cast<double>(id - 1), "[0, 2147483646]");
    ids[i] = id;
    const double r = frame.radius[i];
    require_positive(r, where, "frame.radius[" + std::to_string(i) + "]");
    Dim3::Vec x = frame.x[i];
    for (int k = 0; k < 3; ++k) {
      require_finite(x[k], where, "frame.x[" + std::to_string(i) + "][" + std::to_string(k) + "]");
      if (periodic[static_cast<std::size_t>(k)]) {
        const double length = box_hi[k] - box_lo[k];
        x[k] -= std::floor((x[k] - box_lo[k]) / length) * length;
        if (x[k] >= box_hi[k]) x[k] = box_lo[k];  // rounding can land exactly on hi
      } else {
        require(x[k] >= box_lo[k] && x[k] <= box_hi[k], where,
                "frame.x[" + std::to_string(i) + "][" + std::to_string(k) + "]", x[k],
                "[" + granule::detail::to_text(box_lo[k]) + ", " +
                    granule::detail::to_text(box_hi[k]) + "] (non-periodic box)");
      }
    }
    detail::append_number(out, id);
    out += " 1 ";
    detail::append_number(out, 2.0 * r);
    out += ' ';
    detail::append_number(out, density);
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      detail::append_number(out, x[k]);
    }
    out += '\n';
  }
  {
    std::vector<std::uint64_t> sorted = ids;
    std::sort(sorted.begin(), sorted.end());
    const auto dup = std::adjacent_find(sorted.begin(), sorted.end());
    require(dup == sorted.end(), where, "frame.id (duplicate)",
            dup == sorted.end() ? 0.0 : static_cast<double>(*dup - 1), "distinct ids");
  }
  if (write_v) {
    out += "\nVelocities\n\n";
    for (std::size_t i = 0; i < n; ++i) {
      detail::append_number(out, ids[i]);
      const Dim3::AngVec w = frame.omega.empty() ? Dim3::AngVec::Zero() : frame.omega[i];
      for (int k = 0; k < 3; ++k) {
        out += ' ';
        detail::append_number(out, frame.v[i][k]);
      }
      for (int k = 0; k < 3; ++k) {
        out += ' ';
        detail::append_number(out, w[k]);
      }
      out += '\n';
    }
  }
  write_file_atomically(path, out.data(), out.size(), where, /*durable=*/false);
}

/// Same, with the box and periodicity taken from frame.box_lo, frame.box_hi, frame.periodic.
inline void write_lammps_data(const std::string& path, const analysis::Frame<Dim3>& frame,
                              double density,  // [kg/m^3]
                              bool with_velocities = true) {
  const std::array<bool, 3> periodic = {frame.periodic[0], frame.periodic[1], frame.periodic[2]};
  write_lammps_data(path, frame, frame.box_lo, frame.box_hi, density, periodic, with_velocities);
}

/// Reads a LAMMPS data file of atom_style sphere (as written by write_lammps_data, LAMMPS or
/// LIGGGHTS `write_data`). Positions are taken as written (image flags are ignored), particles
/// are sorted by id, velocities are zero when the file has no Velocities section. Other
/// sections are skipped. Throws IoError for a missing file, a triclinic box, an Atoms section
/// of another atom style, or counts that do not match the header.
inline LammpsData read_lammps_data(const std::string& path) {
  const std::string where = "read_lammps_data('" + path + "')";
  std::istringstream file(read_file(path, where));

  struct Row {
    std::uint64_t id;
    std::uint32_t type;
    double diameter, density;
    Dim3::Vec x, v;
    Dim3::AngVec w;
    bool has_v;
  };
  std::vector<Row> rows;
  std::uint64_t n_atoms = 0;
  bool have_atoms_count = false;
  std::array<bool, 3> have_axis = {false, false, false};
  Dim3::Vec lo = Dim3::Vec::Zero(), hi = Dim3::Vec::Zero();

  std::string line;
  std::getline(file, line);  // title line, always skipped
  std::size_t line_no = 1;
  enum class Section { Header, Atoms, Velocities, Other } section = Section::Header;
  std::uint64_t velocity_rows = 0;
  auto build_index = [&]() {
    std::sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.id < b.id; });
    for (std::size_t i = 1; i < rows.size(); ++i) {
      if (rows[i].id == rows[i - 1].id) {
        throw IoError(where + ": atom id " + std::to_string(rows[i].id) + " appears twice");
      }
    }
  };
  auto find_row = [&](std::uint64_t id) -> Row& {
    const auto it = std::lower_bound(rows.begin(), rows.end(), id,
                                     [](const Row& r, std::uint64_t key) { return r.id < key; });
    if (it == rows.end() || it->id != id) {
      throw IoError(where + ": velocity given for unknown atom id " + std::to_string(id));
    }
    return *it;
  };

  while (std::getline(file, line)) {
    ++line_no;
    const auto tokens = detail::split_tokens(line);
    if (tokens.empty()) continue;
    const std::string at = where + " line " + std::to_string(line_no);
    if (detail::is_keyword_line(tokens)) {
      const std::string_view key = tokens.front();
      if (section == Section::Atoms) build_index();
      if (key == "Atoms") {
        const auto hash = line.find('#');
        if (hash != std::string::npos) {
          const auto style = detail::split_tokens(std::string_view(line).substr(hash + 1));
          if (!style.empty() && style.front() != "sphere" && style.front() != "granular") {
            throw IoError(at + ": Atoms section of style '" + std::string(style.front()) +
                          "', expected sphere");
          }
        }
        if (!rows.empty()) throw IoError(at + ": second Atoms section");
        section = Section::Atoms;
      } else if (key == "Velocities") {
        if (rows.empty()) throw IoError(at + ": Velocities before Atoms");
        section = Section::Velocities;
      } else {
        section = Section::Other;
      }
      continue;
    }
    switch (section) {
      case Section::Header: {
        if (tokens.size() == 2 && tokens[1] == "atoms") {
          n_atoms = detail::parse_count(tokens[0], at);
          have_atoms_count = true;
        } else if (tokens.size() == 4 && (tokens[2] == "xlo" || tokens[2] == "ylo" ||
                                          tokens[2] == "zlo")) {
          const int k = tokens[2][0] - 'x';
          lo[k] = detail::parse_double(tokens[0], at);
          hi[k] = detail::parse_double(tokens[1], at);
          have_axis[static_cast<std::size_t>(k)] = true;
        } else if (tokens.size() == 6 && tokens[3] == "xy") {
          const double xy = detail::parse_double(tokens[0], at);
          const double xz = detail::parse_double(tokens[1], at);
          const double yz = detail::parse_double(tokens[2], at);
          if (xy != 0.0 || xz != 0.0 || yz != 0.0) throw IoError(at + ": triclinic box");
        }
        break;  // other header lines (bonds, extra counts) do not matter for spheres
      }
      case Section::Atoms: {
        if (tokens.size() != 7 && tokens.size() != 10) {
          throw IoError(at + ": expected 7 or 10 columns (id type diameter density x y z "
                             "[ix iy iz]), found " + std::to_string(tokens.size()));
        }
        Row r{};
        r.id = detail::parse_count(tokens[0], at);
        if (r.id == 0) throw IoError(at + ": atom id 0");
        const std::uint64_t type = detail::parse_count(tokens[1], at);
        if (type == 0 || type > 0xffffffffu) throw IoError(at + ": bad atom type");
        r.type = static_cast<std::uint32_t>(type);
        r.diameter = detail::parse_double(tokens[2], at);
        r.density = detail::parse_double(tokens[3], at);
        if (!(r.diameter > 0.0) || !(r.density > 0.0)) {
          throw IoError(at + ": diameter and density must be positive");
        }
        for (int k = 0; k < 3; ++k) r.x[k] = detail::parse_double(tokens[4 + k], at);
        r.v.setZero();
        r.w.setZero();
        r.has_v = false;
        rows.push_back(r);
        break;
      }
      case Section::Velocities: {
        if (tokens.size() != 7) {
          throw IoError(at + ": expected 7 columns (id vx vy vz wx wy wz), found " +
                        std::to_string(tokens.size()));
        }
        Row& r = find_row(detail::parse_count(tokens[0], at));
        for (int k = 0; k < 3; ++k) {
          r.v[k] = detail::parse_double(tokens[1 + k], at);
          r.w[k] = detail::parse_double(tokens[4 + k], at);
        }
        r.has_v = true;
        ++velocity_rows;
        break;
      }
      case Section::Other:
        break;
    }
  }
  if (section == Section::Atoms) build_index();
  if (!have_atoms_count) throw IoError(where + ": header has no 'N atoms' line");
  for (int k = 0; k < 3; ++k) {
    if (!have_axis[static_cast<std::size_t>(k)]) {
      throw IoError(where + ": header has no '" + std::string(1, static_cast<char>('x' + k)) +
                    "lo " + std::string(1, static_cast<char>('x' + k)) + "hi' line");
    }
  }
  if (rows.size() != n_atoms) {
    throw IoError(where + ": header announces " + std::to_string(n_atoms) +
                  " atoms, Atoms section has " + std::to_string(rows.size()));
  }
  if (velocity_rows != 0 && velocity_rows != n_atoms) {
    throw IoError(where + ": Velocities section has " + std::to_string(velocity_rows) +
                  " rows for " + std::to_string(n_atoms) + " atoms");
  }

  LammpsData data;
  auto& f = data.frame;
  f.box_lo = lo;
  f.box_hi = hi;
  const std::size_t n = rows.size();
  f.x.resize(n);
  f.v.resize(n);
  f.omega.resize(n);
  f.radius.resize(n);
  f.mass.resize(n);
  f.id.resize(n);
  f.group.assign(n, 0);
  data.type.resize(n);
  data.density.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Row& r = rows[i];
    f.x[i] = r.x;
    f.v[i] = r.v;
    f.omega[i] = r.w;
    f.radius[i] = 0.5 * r.diameter;
    f.mass[i] = r.density * Dim3::volume(f.radius[i], 1.0);
    f.id[i] = r.id - 1;
    data.type[i] = r.type;
    data.density[i] = r.density;
  }
  return data;
}

}  // namespace granule::io
