#pragma once
// VTK XML writers without the VTK library: UnstructuredGrid files (.vtu) and ParaView data
// collections (.pvd), following "VTK File Formats" (VTK User's Guide, Kitware, 11th ed., ch. 19,
// XML formats): <VTKFile type="UnstructuredGrid" version="1.0" header_type="UInt64">, one
// <Piece> with <PointData>, <CellData>, <Points> and <Cells> (connectivity, end offsets, types).
//
// Encodings: Ascii (values as text, shortest round-trip decimal form, so doubles read back
// bit-exact) and Binary (all arrays in one <AppendedData encoding="raw"> block, each preceded
// by its byte count as UInt64; byte order of this machine, declared in the header).
// 2D vectors are padded with z = 0 so that ParaView and OVITO read them as 3-vectors; 2D
// angular velocities (scalars about z) are written as (0, 0, omega).
//
// Files are written to "<file>.tmp" and renamed, and the .pvd is rewritten the same way after
// each frame, so every file on disk is complete even if a run stops mid-write.
//
// Writers: VtkWriter<D> (particles as VTK_VERTEX cells with their fields), ContactVtkWriter<D>
// (contact network as VTK_LINE cells with force data), SurfaceVtkWriter (wall surfaces from
// geometry::DisplayMesh as VTK_TRIANGLE / VTK_LINE cells). Each numbers its frames
// <name>_000000.vtu, <name>_000001.vtu, ... in its directory and keeps <name>.pvd up to date.
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <system_error>
#include <type_traits>
#include <variant>
#include <vector>

#include "granule/analysis/frame.hpp"
#include "granule/boundaries/geometry/display_mesh.hpp"
#include "granule/core/error.hpp"
#include "granule/io/file.hpp"

namespace granule::io {

/// How array values are stored in a .vtu file.
enum class VtkEncoding {
  Ascii,   ///< text, one tuple per line
  Binary,  ///< raw appended data with UInt64 block headers
};

/// VTK cell type ids (vtkCellType.h).
inline constexpr std::uint8_t kVtkVertex = 1;
inline constexpr std::uint8_t kVtkLine = 3;
inline constexpr std::uint8_t kVtkTriangle = 5;

/// One named data array: `components` values per tuple, tuples stored contiguously.
struct VtkArray {
  using Values = std::variant<std::vector<double>, std::vector<std::int64_t>, std::vector<std::uint32_t>,
                              std::vector<std::uint8_t>>;
  std::string name;
  int components = 1;
  Values values;

  std::size_t value_count() const {
    return std::visit([](const auto& v) { return v.size(); }, values);
  }
};

/// An unstructured grid as VTK stores it.
struct VtkGrid {
  std::vector<double> points;              ///< x, y, z of each point [m]
  std::vector<std::int64_t> connectivity;  ///< point indices of all cells, concatenated
  std::vector<std::int64_t> offsets;       ///< end of each cell in connectivity
  std::vector<std::uint8_t> types;         ///< VTK cell type of each cell
  std::vector<VtkArray> point_data;
  std::vector<VtkArray> cell_data;
  std::optional<double> time;              ///< written as field data "TimeValue" [s]

  std::size_t point_count() const { return points.size() / 3; }
  std::size_t cell_count() const { return types.size(); }

  /// Appends a point given in 2D (z = 0) or 3D; returns its index.
  template <class V>
  std::int64_t add_point(const V& p) {
    points.push_back(p[0]);
    points.push_back(p.size() > 1 ? p[1] : 0.0);
    points.push_back(p.size() > 2 ? p[2] : 0.0);
    return static_cast<std::int64_t>(point_count() - 1);
  }
  /// Appends a cell of `type` over the given point indices.
  void add_cell(std::uint8_t type, std::initializer_list<std::int64_t> ids) {
    connectivity.insert(connectivity.end(), ids.begin(), ids.end());
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    types.push_back(type);
  }

  /// Throws InvalidParameter when array sizes disagree with the point and cell counts.
  void validate() const {
    const std::string where = "io::VtkGrid";
    require(points.size() % 3 == 0, where, "points.size() % 3", static_cast<double>(points.size() % 3), "0");
    require(offsets.size() == types.size(), where, "offsets.size()", static_cast<double>(offsets.size()),
            "equal to types.size() = " + std::to_string(types.size()));
    std::int64_t prev = 0;
    for (std::int64_t o : offsets) {
      require(o >= prev && o <= static_cast<std::int64_t>(connectivity.size()), where, "cell offset",
              static_cast<double>(o), "non-decreasing, <= connectivity.size()");
      prev = o;
    }
    require(offsets.empty() || offsets.back() == static_cast<std::int64_t>(connectivity.size()), where,
            "last offset", offsets.empty() ? 0.0 : static_cast<double>(offsets.back()),
            "connectivity.size() = " + std::to_string(connectivity.size()));
    for (std::int64_t id : connectivity) {
      require(id >= 0 && id < static_cast<std::int64_t>(point_count()), where, "connectivity entry",
              static_cast<double>(id), "[0, " + std::to_string(point_count()) + ")");
    }
    auto check = [&](const std::vector<VtkArray>& arrays, std::size_t tuples, const char* kind) {
      for (std::size_t a = 0; a < arrays.size(); ++a) {
        const VtkArray& arr = arrays[a];
        require(!arr.name.empty(), where, std::string(kind) + " array name length", 0.0, "[1, inf)");
        require(arr.components >= 1, where, kind + std::string(" '") + arr.name + "' components", arr.components,
                "[1, inf)");
        require(arr.value_count() == tuples * static_cast<std::size_t>(arr.components), where,
                kind + std::string(" '") + arr.name + "' value count", static_cast<double>(arr.value_count()),
                std::to_string(tuples) + " tuples x " + std::to_string(arr.components) + " components");
        for (std::size_t b = 0; b < a; ++b) {
          if (arrays[b].name == arr.name) {
            throw InvalidParameter(where + ": two " + kind + " arrays are named '" + arr.name + "'");
          }
        }
      }
    };
    check(point_data, point_count(), "point data");
    check(cell_data, cell_count(), "cell data");
  }
};

namespace detail {

template <class T>
constexpr const char* vtk_type_name() {
  if constexpr (std::is_same_v<T, double>) return "Float64";
  if constexpr (std::is_same_v<T, std::int64_t>) return "Int64";
  if constexpr (std::is_same_v<T, std::uint32_t>) return "UInt32";
  if constexpr (std::is_same_v<T, std::uint8_t>) return "UInt8";
}

inline std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

/// Shortest decimal text that reads back to exactly the same value.
template <class T>
void append_number(std::string& out, T v) {
  char buf[40];
  const auto res = std::to_chars(buf, buf + sizeof(buf), std::is_same_v<T, std::uint8_t> ? unsigned(v) : v);
  out.append(buf, res.ptr);
}

inline std::string number_text(double v) {
  std::string s;
  append_number(s, v);
  return s;
}

/// Writes `content` to `path` through a temporary file and a rename (io/file.hpp; frames are
/// not flushed to disk one by one).
inline void write_atomically(const std::filesystem::path& path, const std::string& content) {
  write_file_atomically(path, content.data(), content.size(), "io", /*durable=*/false);
}

class VtuComposer {
 public:
  explicit VtuComposer(VtkEncoding enc) : enc_(enc) {}

  template <class T>
  void array(const std::string& name, int components, const std::vector<T>& values, int indent) {
    xml_.append(static_cast<std::size_t>(indent), ' ');
    xml_ += "<DataArray type=\"";
    xml_ += vtk_type_name<T>();
    xml_ += "\" Name=\"" + xml_escape(name) + "\" NumberOfComponents=\"" + std::to_string(components) + "\"";
    if (enc_ == VtkEncoding::Ascii) {
      xml_ += " format=\"ascii\">\n";
      for (std::size_t k = 0; k < values.size(); ++k) {
        if (k % static_cast<std::size_t>(components) == 0) xml_.append(static_cast<std::size_t>(indent + 2), ' ');
        append_number(xml_, values[k]);
        xml_ += (k + 1) % static_cast<std::size_t>(components) == 0 ? '\n' : ' ';
      }
      xml_.append(static_cast<std::size_t>(indent), ' ');
      xml_ += "</DataArray>\n";
    } else {
      xml_ += " format=\"appended\" offset=\"" + std::to_string(appended_.size()) + "\"/>\n";
      const std::uint64_t bytes = values.size() * sizeof(T);
      const auto* b = reinterpret_cast<const char*>(&bytes);
      appended_.append(b, sizeof(bytes));
      if (!values.empty()) appended_.append(reinterpret_cast<const char*>(values.data()), bytes);
    }
  }

  void array(const VtkArray& a, int indent) {
    std::visit([&](const auto& v) { array(a.name, a.components, v, indent); }, a.values);
  }

  void raw(const std::string& s) { xml_ += s; }

  std::string finish() {
    xml_ += "  </UnstructuredGrid>\n";
    if (enc_ == VtkEncoding::Binary) {
      xml_ += "  <AppendedData encoding=\"raw\">\n   _";
      xml_ += appended_;
      xml_ += "\n  </AppendedData>\n";
    }
    xml_ += "</VTKFile>\n";
    return std::move(xml_);
  }

 private:
  VtkEncoding enc_;
  std::string xml_;
  std::string appended_;
};

}  // namespace detail

/// Writes one .vtu file (atomically). Throws InvalidParameter for an inconsistent grid and
/// IoError when the file cannot be written.
inline void write_vtu(const std::filesystem::path& path, const VtkGrid& grid, VtkEncoding encoding = VtkEncoding::Binary) {
  grid.validate();
  detail::VtuComposer c(encoding);
  c.raw("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"");
  c.raw(std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian");
  c.raw("\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n");
  if (grid.time) {
    c.raw("    <FieldData>\n");
    c.raw("      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">");
    c.raw(detail::number_text(*grid.time));
    c.raw("</DataArray>\n    </FieldData>\n");
  }
  c.raw("    <Piece NumberOfPoints=\"" + std::to_string(grid.point_count()) + "\" NumberOfCells=\"" +
        std::to_string(grid.cell_count()) + "\">\n");
  c.raw("      <PointData>\n");
  for (const VtkArray& a : grid.point_data) c.array(a, 8);
  c.raw("      </PointData>\n      <CellData>\n");
  for (const VtkArray& a : grid.cell_data) c.array(a, 8);
  c.raw("      </CellData>\n      <Points>\n");
  c.array("Points", 3, grid.points, 8);
  c.raw("      </Points>\n      <Cells>\n");
  c.array("connectivity", 1, grid.connectivity, 8);
  c.array("offsets", 1, grid.offsets, 8);
  c.array("types", 1, grid.types, 8);
  c.raw("      </Cells>\n    </Piece>\n");
  detail::write_atomically(path, c.finish());
}

/// A ParaView data collection (.pvd): a list of (time, file) entries, rewritten atomically by
/// every add() so that it is valid whenever a run stops.
class PvdCollection {
 public:
  struct Entry {
    double time;       ///< [s]
    std::string file;  ///< path relative to the .pvd
  };

  explicit PvdCollection(std::filesystem::path path) : path_(std::move(path)) {}

  /// Loads the entries of an existing .pvd written by PvdCollection, keeping those with
  /// time <= keep_until [s] (to continue a series after a restart). A missing file gives an
  /// empty collection.
  static PvdCollection resume(std::filesystem::path path, double keep_until) {
    PvdCollection pvd(std::move(path));
    std::ifstream in(pvd.path_);
    if (!in) return pvd;
    std::string line;
    while (std::getline(in, line)) {
      if (line.find("<DataSet") == std::string::npos) continue;
      const auto t = attribute(line, "timestep");
      const auto f = attribute(line, "file");
      if (!t || !f) throw IoError("PvdCollection: malformed entry in '" + pvd.path_.string() + "': " + line);
      double time = 0.0;
      const auto [ptr, ec] = std::from_chars(t->data(), t->data() + t->size(), time);
      if (ec != std::errc() || ptr != t->data() + t->size()) {
        throw IoError("PvdCollection: bad timestep '" + *t + "' in '" + pvd.path_.string() + "'");
      }
      if (time <= keep_until) pvd.entries_.push_back({time, *f});
    }
    return pvd;
  }

  /// Adds an entry and rewrites the file.
  void add(double time, const std::string& file) {
    require_finite(time, "io::PvdCollection::add", "time");
    entries_.push_back({time, file});
    write();
  }

  /// Rewrites the file from the current entries.
  void write() const {
    std::string s = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"";
    s += std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";
    s += "\">\n  <Collection>\n";
    for (const Entry& e : entries_) {
      s += "    <DataSet timestep=\"" + detail::number_text(e.time) + "\" group=\"\" part=\"0\" file=\"" +
           detail::xml_escape(e.file) + "\"/>\n";
    }
    s += "  </Collection>\n</VTKFile>\n";
    detail::write_atomically(path_, s);
  }

  const std::vector<Entry>& entries() const { return entries_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  static std::optional<std::string> attribute(const std::string& line, const std::string& name) {
    const std::string key = " " + name + "=\"";
    const auto b = line.find(key);
    if (b == std::string::npos) return std::nullopt;
    const auto start = b + key.size();
    const auto e = line.find('"', start);
    if (e == std::string::npos) return std::nullopt;
    return line.substr(start, e - start);
  }

  std::filesystem::path path_;
  std::vector<Entry> entries_;
};

/// A numbered series of .vtu files with its .pvd: <dir>/<name>_NNNNNN.vtu and <dir>/<name>.pvd.
class VtkSeries {
 public:
  /// Creates `dir` if needed. The series starts empty (an existing .pvd is replaced at the
  /// first write; call resume() to continue it instead).
  VtkSeries(std::filesystem::path dir, std::string name, VtkEncoding encoding = VtkEncoding::Binary)
      : dir_(std::move(dir)), name_(std::move(name)), encoding_(encoding), pvd_(dir_ / (name_ + ".pvd")) {
    require(!name_.empty() && name_.find_first_of("/\\") == std::string::npos, "io::VtkSeries", "name length",
            static_cast<double>(name_.size()), "[1, inf) characters without path separators");
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec) throw IoError("io::VtkSeries: cannot create directory '" + dir_.string() + "': " + ec.message());
  }

  /// Continues an existing series after a restart: keeps the .pvd entries with
  /// time <= `time` [s]; the next frame number follows the kept entries.
  void resume(double time) {
    pvd_ = PvdCollection::resume(pvd_.path(), time);
    next_ = pvd_.entries().size();
  }

  /// Writes the next frame at `time` [s] and updates the .pvd; returns the .vtu path.
  std::filesystem::path write(VtkGrid grid, double time) {
    require_finite(time, "io::VtkSeries::write", "time");
    char num[16];
    std::snprintf(num, sizeof(num), "_%06zu.vtu", next_);
    const std::string file = name_ + num;
    grid.time = time;
    write_vtu(dir_ / file, grid, encoding_);
    pvd_.add(time, file);
    ++next_;
    return dir_ / file;
  }

  std::size_t frames() const { return next_; }
  const std::filesystem::path& pvd_path() const { return pvd_.path(); }
  const std::filesystem::path& directory() const { return dir_; }
  VtkEncoding encoding() const { return encoding_; }

 private:
  std::filesystem::path dir_;
  std::string name_;
  VtkEncoding encoding_;
  PvdCollection pvd_;
  std::size_t next_ = 0;
};

/// A user field attached to each particle: a scalar or a vector per particle.
template <class D>
struct VtkField {
  using Vec = typename D::Vec;
  std::string name;
  std::variant<std::span<const double>, std::span<const Vec>> values;

  VtkField(std::string n, std::span<const double> v) : name(std::move(n)), values(v) {}
  VtkField(std::string n, std::span<const Vec> v) : name(std::move(n)), values(v) {}
  VtkField(std::string n, const std::vector<double>& v) : name(std::move(n)), values(std::span<const double>(v)) {}
  VtkField(std::string n, const std::vector<Vec>& v) : name(std::move(n)), values(std::span<const Vec>(v)) {}
};

namespace detail {

template <class D>
std::vector<double> padded(std::span<const typename D::Vec> v) {
  std::vector<double> out(3 * v.size(), 0.0);
  for (std::size_t i = 0; i < v.size(); ++i) {
    for (int k = 0; k < D::dim; ++k) out[3 * i + k] = v[i][k];
  }
  return out;
}

template <class D>
std::vector<double> padded_angular(const std::vector<typename D::AngVec>& w) {
  std::vector<double> out(3 * w.size(), 0.0);
  for (std::size_t i = 0; i < w.size(); ++i) {
    if constexpr (D::dim == 2) {
      out[3 * i + 2] = w[i];
    } else {
      for (int k = 0; k < 3; ++k) out[3 * i + k] = w[i][k];
    }
  }
  return out;
}

inline void check_size(std::size_t got, std::size_t n, const std::string& field) {
  require(got == 0 || got == n, "io::particle_grid", "size of " + field, static_cast<double>(got),
          "0 (omitted) or the number of particles " + std::to_string(n));
}

}  // namespace detail

/// Particles of a frame as VTK_VERTEX cells. Point data: velocity, omega (3-vectors), radius,
/// mass (Float64), id (Int64), group (UInt32), force and torque (3-vectors; Simulation::frame()
/// fills them; a user field named "force" or "torque" takes their place), each written when
/// present in the frame (a frame field must be empty or hold one value per particle), then the
/// user fields.
template <class D>
VtkGrid particle_grid(const analysis::Frame<D>& frame, std::span<const VtkField<D>> fields = {}) {
  const std::size_t n = frame.x.size();
  detail::check_size(frame.v.size(), n, "Frame::v");
  detail::check_size(frame.omega.size(), n, "Frame::omega");
  detail::check_size(frame.radius.size(), n, "Frame::radius");
  detail::check_size(frame.mass.size(), n, "Frame::mass");
  detail::check_size(frame.id.size(), n, "Frame::id");
  detail::check_size(frame.group.size(), n, "Frame::group");
  detail::check_size(frame.force.size(), n, "Frame::force");
  detail::check_size(frame.torque.size(), n, "Frame::torque");
  VtkGrid g;
  g.points = detail::padded<D>(frame.x);
  g.connectivity.resize(n);
  g.offsets.resize(n);
  g.types.assign(n, kVtkVertex);
  for (std::size_t i = 0; i < n; ++i) {
    g.connectivity[i] = static_cast<std::int64_t>(i);
    g.offsets[i] = static_cast<std::int64_t>(i + 1);
  }
  if (!frame.v.empty()) g.point_data.push_back({"velocity", 3, detail::padded<D>(frame.v)});
  if (!frame.omega.empty()) g.point_data.push_back({"omega", 3, detail::padded_angular<D>(frame.omega)});
  if (!frame.radius.empty()) g.point_data.push_back({"radius", 1, frame.radius});
  if (!frame.mass.empty()) g.point_data.push_back({"mass", 1, frame.mass});
  if (!frame.id.empty()) {
    g.point_data.push_back({"id", 1, std::vector<std::int64_t>(frame.id.begin(), frame.id.end())});
  }
  if (!frame.group.empty()) g.point_data.push_back({"group", 1, frame.group});
  // (A user field of the same name replaces them, as it did before frames carried them.)
  const auto user_named = [&](const char* name) {
    for (const VtkField<D>& f : fields)
      if (f.name == name) return true;
    return false;
  };
  if (!frame.force.empty() && !user_named("force"))
    g.point_data.push_back({"force", 3, detail::padded<D>(frame.force)});
  if (!frame.torque.empty() && !user_named("torque"))
    g.point_data.push_back({"torque", 3, detail::padded_angular<D>(frame.torque)});
  for (const VtkField<D>& f : fields) {
    std::visit(
        [&](const auto& span) {
          using T = typename std::decay_t<decltype(span)>::value_type;
          require(span.size() == n, "io::particle_grid", "size of field '" + f.name + "'",
                  static_cast<double>(span.size()), "the number of particles " + std::to_string(n));
          if constexpr (std::is_same_v<std::remove_cv_t<T>, double>) {
            g.point_data.push_back({f.name, 1, std::vector<double>(span.begin(), span.end())});
          } else {
            g.point_data.push_back({f.name, 3, detail::padded<D>(span)});
          }
        },
        f.values);
  }
  return g;
}

/// What to do with particle-wall contacts in a contact network.
enum class WallContacts {
  Skip,            ///< leave them out
  ToContactPoint,  ///< draw a line from the particle centre to the contact point
};

/// Contact network of a frame as VTK_LINE cells from x_i to x_i + branch (periodic images
/// resolved by the branch vector). Cell data: fn (normal force on i, > 0 repulsive) [N],
/// ft_magnitude [N], force = fn n + ft [N] (3-vector), normal, ft (3-vectors), overlap [m],
/// id_i, id_j (particle ids, -1 for a wall), wall (wall index, -1 for a particle pair).
template <class D>
VtkGrid contact_grid(const analysis::Frame<D>& frame, WallContacts walls = WallContacts::ToContactPoint) {
  using Record = analysis::ContactRecord<D>;
  const std::size_t n = frame.x.size();
  const bool have_ids = frame.id.size() == n;
  VtkGrid g;
  std::vector<double> fn, ft_mag, overlap;
  std::vector<typename D::Vec> force, normal, ft;
  std::vector<std::int64_t> id_i, id_j, wall;
  for (std::size_t k = 0; k < frame.contacts.size(); ++k) {
    const Record& c = frame.contacts[k];
    const bool is_wall = c.j == Record::kWall;
    if (is_wall && walls == WallContacts::Skip) continue;
    require(c.i < n, "io::contact_grid", "contact " + std::to_string(k) + " particle i", c.i,
            "[0, " + std::to_string(n) + ")");
    require(is_wall || c.j < n, "io::contact_grid", "contact " + std::to_string(k) + " particle j", c.j,
            "[0, " + std::to_string(n) + ") or kWall");
    const std::int64_t a = g.add_point(frame.x[c.i]);
    const std::int64_t b = g.add_point(typename D::Vec(frame.x[c.i] + c.branch));
    g.add_cell(kVtkLine, {a, b});
    fn.push_back(c.fn);
    ft_mag.push_back(c.ft.norm());
    overlap.push_back(c.overlap);
    force.push_back(c.fn * c.normal + c.ft);
    normal.push_back(c.normal);
    ft.push_back(c.ft);
    id_i.push_back(have_ids ? static_cast<std::int64_t>(frame.id[c.i]) : static_cast<std::int64_t>(c.i));
    id_j.push_back(is_wall ? -1 : have_ids ? static_cast<std::int64_t>(frame.id[c.j]) : static_cast<std::int64_t>(c.j));
    wall.push_back(is_wall ? static_cast<std::int64_t>(c.wall) : -1);
  }
  g.cell_data.push_back({"fn", 1, std::move(fn)});
  g.cell_data.push_back({"ft_magnitude", 1, std::move(ft_mag)});
  g.cell_data.push_back({"force", 3, detail::padded<D>(force)});
  g.cell_data.push_back({"normal", 3, detail::padded<D>(normal)});
  g.cell_data.push_back({"ft", 3, detail::padded<D>(ft)});
  g.cell_data.push_back({"overlap", 1, std::move(overlap)});
  g.cell_data.push_back({"id_i", 1, std::move(id_i)});
  g.cell_data.push_back({"id_j", 1, std::move(id_j)});
  g.cell_data.push_back({"wall", 1, std::move(wall)});
  return g;
}

/// Wall surfaces as VTK_TRIANGLE and VTK_LINE cells; cell data "part" = index of the mesh in
/// `parts` (one part per wall, say).
inline VtkGrid surface_grid(std::span<const geometry::DisplayMesh> parts) {
  VtkGrid g;
  std::vector<std::uint32_t> part;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const auto base = static_cast<std::int64_t>(g.point_count());
    for (const auto& x : parts[p].points) g.add_point(x);
    for (const auto& t : parts[p].triangles) {
      g.add_cell(kVtkTriangle, {base + t[0], base + t[1], base + t[2]});
      part.push_back(static_cast<std::uint32_t>(p));
    }
    for (const auto& l : parts[p].lines) {
      g.add_cell(kVtkLine, {base + l[0], base + l[1]});
      part.push_back(static_cast<std::uint32_t>(p));
    }
  }
  g.cell_data.push_back({"part", 1, std::move(part)});
  return g;
}

/// Particle frames: `VtkWriter<D> w(dir, "particles"); w.write(frame, {{"p", p}}, t);`
template <class D>
class VtkWriter {
 public:
  VtkWriter(std::filesystem::path dir, std::string name, VtkEncoding encoding = VtkEncoding::Binary)
      : series_(std::move(dir), std::move(name), encoding) {}

  /// Writes the frame with extra per-particle fields at `time` [s] (default: frame.time).
  std::filesystem::path write(const analysis::Frame<D>& frame, const std::vector<VtkField<D>>& fields = {},
                              std::optional<double> time = std::nullopt) {
    return series_.write(particle_grid<D>(frame, fields), time.value_or(frame.time));
  }

  VtkSeries& series() { return series_; }

 private:
  VtkSeries series_;
};

/// Contact-network frames.
template <class D>
class ContactVtkWriter {
 public:
  ContactVtkWriter(std::filesystem::path dir, std::string name, VtkEncoding encoding = VtkEncoding::Binary,
                   WallContacts walls = WallContacts::ToContactPoint)
      : series_(std::move(dir), std::move(name), encoding), walls_(walls) {}

  std::filesystem::path write(const analysis::Frame<D>& frame, std::optional<double> time = std::nullopt) {
    return series_.write(contact_grid<D>(frame, walls_), time.value_or(frame.time));
  }

  VtkSeries& series() { return series_; }

 private:
  VtkSeries series_;
  WallContacts walls_;
};

/// Wall-surface frames (moving walls: tessellate at each output time).
class SurfaceVtkWriter {
 public:
  SurfaceVtkWriter(std::filesystem::path dir, std::string name, VtkEncoding encoding = VtkEncoding::Binary)
      : series_(std::move(dir), std::move(name), encoding) {}

  std::filesystem::path write(std::span<const geometry::DisplayMesh> parts, double time) {
    return series_.write(surface_grid(parts), time);
  }

  VtkSeries& series() { return series_; }

 private:
  VtkSeries series_;
};

}  // namespace granule::io
