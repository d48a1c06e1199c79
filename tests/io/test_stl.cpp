// STL reader: ASCII and binary encodings of a hand-written tetrahedron (4 facets, 4 welded
// vertices, 6 edges), scale factor, binary files whose header starts with "solid", refusal of
// degenerate facets (zero area, repeated vertex, NaN) with file name and facet index, and of
// truncated files.
#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "granule/io/stl.hpp"

using namespace granule;
using V3 = Eigen::Vector3d;

namespace {

std::filesystem::path temp_dir() {
  const auto dir = std::filesystem::temp_directory_path() / "granule_test_stl";
  std::filesystem::create_directories(dir);
  return dir;
}

// Tetrahedron (0,0,0), (10,0,0), (0,10,0), (0,0,10) in mm, outward winding.
std::vector<std::array<V3, 3>> tetra() {
  const V3 o(0, 0, 0), a(10, 0, 0), b(0, 10, 0), c(0, 0, 10);
  return {{o, b, a}, {o, a, c}, {o, c, b}, {a, b, c}};
}

void write_ascii(const std::filesystem::path& p, const std::vector<std::array<V3, 3>>& tris, bool close = true) {
  std::ofstream f(p);
  f << "solid tetra\n";
  for (const auto& t : tris) {
    f << "  facet normal 0 0 0\n    outer loop\n";
    for (const auto& v : t) f << "      vertex " << v.x() << " " << v.y() << " " << v.z() << "\n";
    f << "    endloop\n  endfacet\n";
  }
  if (close) f << "endsolid tetra\n";
}

void put32(std::string& s, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) s.push_back(static_cast<char>((v >> (8 * k)) & 0xff));
}

std::string binary_bytes(const std::vector<std::array<V3, 3>>& tris, const std::string& header) {
  std::string s = header;
  s.resize(80, ' ');
  put32(s, static_cast<std::uint32_t>(tris.size()));
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) put32(s, std::bit_cast<std::uint32_t>(0.0f));
    for (const auto& v : t) {
      for (int k = 0; k < 3; ++k) put32(s, std::bit_cast<std::uint32_t>(static_cast<float>(v[k])));
    }
    s.push_back(0);
    s.push_back(0);
  }
  return s;
}

void write_bytes(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

TEST_CASE("read_stl reads ASCII and binary encodings alike", "[io][stl]") {
  const auto dir = temp_dir();
  write_ascii(dir / "tetra_ascii.stl", tetra());
  write_bytes(dir / "tetra_binary.stl", binary_bytes(tetra(), "binary tetra"));
  write_bytes(dir / "tetra_solid_header.stl", binary_bytes(tetra(), "solid exported by some CAD tool"));
  for (const char* name : {"tetra_ascii.stl", "tetra_binary.stl", "tetra_solid_header.stl"}) {
    INFO(name);
    const io::StlData d = io::read_stl(dir / name, 1e-3);
    CHECK(d.binary == (std::string(name) != "tetra_ascii.stl"));
    REQUIRE(d.triangles.size() == 4u);
    const auto ref = tetra();
    for (std::size_t t = 0; t < 4; ++t) {
      for (int v = 0; v < 3; ++v) CHECK((d.triangles[t][v] - 1e-3 * ref[t][v]).norm() < 1e-15);
    }
    const geometry::TriangleMeshShape mesh = io::read_stl_mesh(dir / name, 1e-3, geometry::MeshSides::OneSided);
    CHECK(mesh.vertices().size() == 4u);
    CHECK(mesh.edge_count() == 6u);
    // From the centroid (2.5, 2.5, 2.5) mm the slanted face x + y + z = 10 mm is nearest:
    // (10 - 7.5)/sqrt(3) mm < 2.5 mm to the axis faces; inside, so negative.
    const auto s = mesh.closest(V3::Constant(2.5e-3));
    CHECK(s.distance == Approx(-2.5e-3 / std::sqrt(3.0)).epsilon(1e-12));
    CHECK((s.normal - V3::Constant(1.0 / std::sqrt(3.0))).norm() < 1e-12);
  }
  CHECK(io::read_stl(dir / "tetra_ascii.stl").name == "tetra");
  CHECK(io::read_stl(dir / "tetra_binary.stl").name == "binary tetra");
}

TEST_CASE("read_stl refuses degenerate facets naming file and facet", "[io][stl]") {
  const auto dir = temp_dir();
  auto tris = tetra();
  tris[2] = {V3(0, 0, 0), V3(1, 1, 1), V3(2, 2, 2)};  // collinear: zero area
  write_ascii(dir / "zero_area.stl", tris);
  CHECK_THROWS_AS(io::read_stl(dir / "zero_area.stl"), IoError);
  CHECK_THROWS_WITH(io::read_stl(dir / "zero_area.stl"),
                    Catch::Contains("zero_area.stl") && Catch::Contains("facet 2") && Catch::Contains("zero area"));
  tris = tetra();
  tris[1][2] = tris[1][1];
  write_bytes(dir / "repeated.stl", binary_bytes(tris, "x"));
  CHECK_THROWS_WITH(io::read_stl(dir / "repeated.stl"),
                    Catch::Contains("repeated.stl") && Catch::Contains("facet 1") && Catch::Contains("repeated"));
  tris = tetra();
  tris[3][0].x() = std::nan("");
  write_bytes(dir / "nan.stl", binary_bytes(tris, "x"));
  CHECK_THROWS_WITH(io::read_stl(dir / "nan.stl"), Catch::Contains("facet 3") && Catch::Contains("non-finite"));
  write_ascii(dir / "nan_ascii.stl", tris);
  CHECK_THROWS_WITH(io::read_stl(dir / "nan_ascii.stl"), Catch::Contains("facet 3"));
  // A facet that only collapses when corners are welded with a coarse tolerance.
  tris = tetra();
  tris.push_back({V3(20, 20, 20), V3(20.001, 20, 20), V3(20, 20.001, 20)});
  write_ascii(dir / "tiny.stl", tris);
  CHECK_NOTHROW(io::read_stl_mesh(dir / "tiny.stl"));
  CHECK_THROWS_WITH(io::read_stl_mesh(dir / "tiny.stl", 1.0, geometry::MeshSides::TwoSided, 0.01),
                    Catch::Contains("facet 4"));
}

TEST_CASE("read_stl refuses truncated and foreign files", "[io][stl]") {
  const auto dir = temp_dir();
  const std::string full = binary_bytes(tetra(), "binary");
  write_bytes(dir / "cut.stl", full.substr(0, full.size() - 10));
  CHECK_THROWS_WITH(io::read_stl(dir / "cut.stl"), Catch::Contains("cut.stl") && Catch::Contains("truncated"));
  write_bytes(dir / "cut_solid.stl", binary_bytes(tetra(), "solid header").substr(0, 150));
  CHECK_THROWS_AS(io::read_stl(dir / "cut_solid.stl"), IoError);
  write_ascii(dir / "open.stl", tetra(), false);
  CHECK_THROWS_WITH(io::read_stl(dir / "open.stl"), Catch::Contains("endsolid"));
  std::string text;
  {
    write_ascii(dir / "whole.stl", tetra());
    std::ifstream f(dir / "whole.stl");
    text.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  }
  write_bytes(dir / "mid_facet.stl", text.substr(0, text.find("vertex 0 10 0")));
  CHECK_THROWS_WITH(io::read_stl(dir / "mid_facet.stl"), Catch::Contains("facet 0") && Catch::Contains("truncated"));
  write_bytes(dir / "short.stl", "hello");
  CHECK_THROWS_WITH(io::read_stl(dir / "short.stl"), Catch::Contains("not an STL file"));
  CHECK_THROWS_WITH(io::read_stl(dir / "does_not_exist.stl"), Catch::Contains("cannot open"));
  CHECK_THROWS_AS(io::read_stl(dir / "whole.stl", 0.0), InvalidParameter);
  write_bytes(dir / "empty.stl", binary_bytes({}, "none"));
  CHECK(io::read_stl(dir / "empty.stl").triangles.empty());
  CHECK_THROWS_WITH(io::read_stl_mesh(dir / "empty.stl"), Catch::Contains("no facets"));
}
