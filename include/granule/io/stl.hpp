#pragma once
// STL reader (stereolithography triangle files), ASCII and binary.
//
// Binary layout: 80-byte header, uint32 facet count n, then n records of 50 bytes (normal and
// three vertices as 12 little-endian float32, a uint16 attribute). A file is read as binary
// when its size is exactly 84 + 50 n (also when its header starts with "solid", as many
// exporters write); otherwise it must be ASCII, starting with "solid":
//   solid name / facet normal nx ny nz / outer loop / vertex x y z (x3) / endloop / endfacet /
//   ... / endsolid name        (keywords case-insensitive; several solids may follow)
// Anything else (a binary file cut short, a missing "endsolid", a malformed number) is refused
// with IoError naming the file. Facets with a non-finite coordinate, a repeated vertex or zero
// area are refused with IoError naming the file and the facet index (0-based, in file order).
// Coordinates are multiplied by `scale` (1e-3 for a file in mm).
#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include "granule/boundaries/geometry/triangle_mesh.hpp"
#include "granule/core/error.hpp"
#include "granule/io/file.hpp"

namespace granule::io {

/// Contents of an STL file.
struct StlData {
  std::string name;                                 ///< solid name (ASCII) or header text (binary)
  bool binary = false;                              ///< encoding that was detected
  std::vector<geometry::TriangleCorners> triangles;  ///< scaled vertices [m]
  std::vector<Eigen::Vector3d> normals;             ///< facet normals as stored (may be zero)
};

namespace detail {

inline std::string stl_where(const std::filesystem::path& path) { return "read_stl: '" + path.string() + "'"; }

inline std::uint32_t read_le32(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

inline double read_le_float(const unsigned char* p) { return static_cast<double>(std::bit_cast<float>(read_le32(p))); }

inline bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

/// Whitespace tokenizer over the ASCII text, tracking line numbers for messages.
class StlTokens {
 public:
  explicit StlTokens(std::string_view text) : text_(text) {}
  /// Next token, empty at the end of the file.
  std::string_view next() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  /// Rest of the current line (trimmed), consumed.
  std::string rest_of_line() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    std::string s(text_.substr(start, pos_ - start));
    const auto b = s.find_first_not_of(" \t\r");
    const auto e = s.find_last_not_of(" \t\r");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
  }
  int line() const { return line_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  int line_ = 1;
};

inline void check_facet(const std::filesystem::path& path, std::size_t facet, const geometry::TriangleCorners& t) {
  const std::string defect = geometry::detail::triangle_defect(t[0], t[1], t[2]);
  if (!defect.empty()) {
    throw IoError(stl_where(path) + ": facet " + std::to_string(facet) + " is degenerate (" + defect + ")");
  }
}

inline void read_stl_binary(const std::filesystem::path& path, const std::string& bytes, double scale, StlData& out) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::uint32_t n = read_le32(data + 80);
  std::string header(bytes.data(), 80);
  header.erase(std::find(header.begin(), header.end(), '\0'), header.end());
  const auto e = header.find_last_not_of(" \t\r\n");
  out.name = e == std::string::npos ? std::string() : header.substr(0, e + 1);
  out.binary = true;
  out.triangles.reserve(n);
  out.normals.reserve(n);
  for (std::uint32_t f = 0; f < n; ++f) {
    const unsigned char* rec = data + 84 + 50 * static_cast<std::size_t>(f);
    Eigen::Vector3d normal;
    for (int k = 0; k < 3; ++k) normal[k] = read_le_float(rec + 4 * k);
    geometry::TriangleCorners t;
    for (int v = 0; v < 3; ++v) {
      for (int k = 0; k < 3; ++k) t[v][k] = scale * read_le_float(rec + 12 + 12 * v + 4 * k);
    }
    check_facet(path, f, t);
    out.triangles.push_back(t);
    out.normals.push_back(normal);
  }
}

inline void read_stl_ascii(const std::filesystem::path& path, const std::string& text, double scale, StlData& out) {
  StlTokens tok(text);
  const std::string where = stl_where(path);
  auto fail = [&](const std::string& what) -> void {
    throw IoError(where + ": " + what + " (line " + std::to_string(tok.line()) + ")");
  };
  auto expect = [&](std::string_view keyword, std::size_t facet) {
    const std::string_view t = tok.next();
    if (!iequals(t, keyword)) {
      fail("facet " + std::to_string(facet) + ": expected '" + std::string(keyword) + "', found " +
           (t.empty() ? std::string("end of file (truncated file?)") : "'" + std::string(t) + "'"));
    }
  };
  auto number = [&](std::size_t facet) {
    const std::string_view t = tok.next();
    double v = 0.0;
    const char* first = t.data();
    if (!t.empty() && *first == '+') ++first;
    const auto [ptr, ec] = std::from_chars(first, t.data() + t.size(), v);
    if (t.empty() || ec != std::errc() || ptr != t.data() + t.size()) {
      fail("facet " + std::to_string(facet) + ": expected a number, found " +
           (t.empty() ? std::string("end of file (truncated file?)") : "'" + std::string(t) + "'"));
    }
    return v;
  };
  out.binary = false;
  std::string_view t = tok.next();
  if (!iequals(t, "solid")) fail("an ASCII STL file must start with 'solid'");
  out.name = tok.rest_of_line();
  while (true) {
    t = tok.next();
    if (t.empty()) fail("missing 'endsolid' (truncated file?)");
    if (iequals(t, "endsolid")) {
      tok.rest_of_line();
      t = tok.next();
      if (t.empty()) break;
      if (!iequals(t, "solid")) fail("expected 'solid' or end of file after 'endsolid', found '" + std::string(t) + "'");
      tok.rest_of_line();
      continue;
    }
    const std::size_t facet = out.triangles.size();
    if (!iequals(t, "facet")) fail("expected 'facet' or 'endsolid', found '" + std::string(t) + "'");
    expect("normal", facet);
    Eigen::Vector3d normal;
    for (int k = 0; k < 3; ++k) normal[k] = number(facet);
    expect("outer", facet);
    expect("loop", facet);
    geometry::TriangleCorners tri;
    for (int v = 0; v < 3; ++v) {
      expect("vertex", facet);
      for (int k = 0; k < 3; ++k) tri[v][k] = scale * number(facet);
    }
    expect("endloop", facet);
    expect("endfacet", facet);
    check_facet(path, facet, tri);
    out.triangles.push_back(tri);
    out.normals.push_back(normal);
  }
}

}  // namespace detail

/// Reads an ASCII or binary STL file; coordinates multiplied by `scale` (> 0).
inline StlData read_stl(const std::filesystem::path& path, double scale = 1.0) {
  require_positive(scale, "read_stl", "scale");
  const std::string bytes = read_file(path, "read_stl");
  StlData out;
  if (bytes.size() >= 84) {
    const std::uint64_t n = detail::read_le32(reinterpret_cast<const unsigned char*>(bytes.data()) + 80);
    if (bytes.size() == 84 + 50 * n) {
      detail::read_stl_binary(path, bytes, scale, out);
      return out;
    }
  }
  const auto first = bytes.find_first_not_of(" \t\r\n");
  if (first == std::string::npos || !detail::iequals(std::string_view(bytes).substr(first, 5), "solid")) {
    std::string what = detail::stl_where(path) + ": not an STL file: neither ASCII (starting with 'solid') nor binary";
    if (bytes.size() >= 84) {
      const std::uint64_t n = detail::read_le32(reinterpret_cast<const unsigned char*>(bytes.data()) + 80);
      what += " (the header announces " + std::to_string(n) + " facets = " + std::to_string(84 + 50 * n) +
              " bytes, the file has " + std::to_string(bytes.size()) + " bytes: truncated?)";
    } else {
      what += " (" + std::to_string(bytes.size()) + " bytes, shorter than the 84-byte binary header)";
    }
    throw IoError(what);
  }
  detail::read_stl_ascii(path, bytes, scale, out);
  return out;
}

/// Reads an STL file into a welded triangle mesh wall. Corners closer than `weld_tolerance`
/// [m] (after scaling) are merged; a facet that collapses by welding is refused.
inline geometry::TriangleMeshShape read_stl_mesh(const std::filesystem::path& path, double scale = 1.0,
                                                 geometry::MeshSides sides = geometry::MeshSides::TwoSided,
                                                 double weld_tolerance = 0.0) {
  const StlData data = read_stl(path, scale);
  if (data.triangles.empty()) throw IoError(detail::stl_where(path) + ": the file holds no facets");
  geometry::IndexedTriangles mesh = geometry::weld_triangles(data.triangles, weld_tolerance);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      throw IoError(detail::stl_where(path) + ": facet " + std::to_string(f) +
                    " is degenerate after welding corners closer than " + granule::detail::to_text(weld_tolerance) +
                    " m");
    }
    const std::string defect =
        geometry::detail::triangle_defect(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
    if (!defect.empty()) {
      throw IoError(detail::stl_where(path) + ": facet " + std::to_string(f) + " is degenerate after welding (" +
                    defect + ")");
    }
  }
  return geometry::TriangleMeshShape(std::move(mesh), sides);
}

}  // namespace granule::io
