// Tests of io/lammps_data.hpp: exact round trip, reading a file in the layout LIGGGHTS 3.8
// `write_data` produces, and the error paths. Reference for the format: LAMMPS manual,
// `read_data`, atom_style sphere (id type diameter density x y z; Velocities id v w).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "granule/io/lammps_data.hpp"

namespace {

using granule::Dim3;
using Frame3 = granule::analysis::Frame<Dim3>;

std::string lammps_temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("granule_test_lammps_data_" + name)).string();
}

std::string lammps_read_text(const std::string& path) {
  std::ifstream f(path);
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
}

// Four particles with awkward doubles, given out of id order.
Frame3 sample_frame() {
  Frame3 f;
  f.x = {Dim3::Vec(1.0 / 3.0, 0.1, 0.2), Dim3::Vec(0.7, 2.0 / 7.0, 1e-7),
         Dim3::Vec(0.05, 0.9, 0.999999999999), Dim3::Vec(0.5, 0.5, 0.5)};
  f.v = {Dim3::Vec(1e-9, -2.5, 3.0), Dim3::Vec(0.0, 0.0, -1.0 / 3.0), Dim3::Vec::Zero(),
         Dim3::Vec(-4e-300, 1e300, 5.0)};
  f.omega = {Dim3::Vec(0.1, 0.2, 0.3), Dim3::Vec::Zero(), Dim3::Vec(-7.0, 1.0 / 7.0, 0.0),
             Dim3::Vec(1.0, 1.0, 1.0)};
  f.radius = {1.25e-3, 1.0e-3, 0.1 / 3.0, 2.0e-3};
  f.id = {7, 0, 3, 12};
  f.box_lo = Dim3::Vec(0.0, 0.0, 0.0);
  f.box_hi = Dim3::Vec(1.0, 1.0, 1.0);
  return f;
}

}  // namespace

TEST_CASE("lammps_data: write then read reproduces every value exactly", "[io][lammps_data]") {
  const Frame3 f = sample_frame();
  const std::string path = lammps_temp_path("roundtrip.data");
  const double density = 2500.0;  // [kg/m^3]
  granule::io::write_lammps_data(path, f, f.box_lo, f.box_hi, density, {true, false, false});
  const auto data = granule::io::read_lammps_data(path);
  const Frame3& g = data.frame;

  REQUIRE(g.size() == 4);
  CHECK(g.box_lo == f.box_lo);
  CHECK(g.box_hi == f.box_hi);
  // The reader sorts by id: ids 0, 3, 7, 12 are input rows 1, 2, 0, 3.
  const std::size_t order[4] = {1, 2, 0, 3};
  for (std::size_t k = 0; k < 4; ++k) {
    const std::size_t i = order[k];
    CHECK(g.id[k] == f.id[i]);
    CHECK(g.x[k] == f.x[i]);          // bitwise: shortest round-trip formatting
    CHECK(g.v[k] == f.v[i]);
    CHECK(g.omega[k] == f.omega[i]);
    CHECK(g.radius[k] == f.radius[i]);
    CHECK(data.density[k] == density);
    CHECK(data.type[k] == 1u);
    // m = rho 4/3 pi r^3 (sphere volume).
    const double m = density * 4.0 / 3.0 * std::numbers::pi * std::pow(f.radius[i], 3);
    CHECK(g.mass[k] == Approx(m).epsilon(1e-15));
  }
  // LAMMPS ids are 1-based: granule id 0 is written as 1.
  const std::string text = lammps_read_text(path);
  CHECK(text.find("\n1 1 0.002 2500 0.7 ") != std::string::npos);
  CHECK(text.find("4 atoms\n1 atom types\n") != std::string::npos);
  CHECK(text.find("Atoms # sphere") != std::string::npos);
  std::remove(path.c_str());
}

TEST_CASE("lammps_data: periodic directions are wrapped, others must hold the centre",
          "[io][lammps_data]") {
  Frame3 f;
  f.x = {Dim3::Vec(1.25, 0.5, 0.5), Dim3::Vec(-0.5, 0.25, 0.0)};
  f.radius = {0.1, 0.1};
  const std::string path = lammps_temp_path("wrap.data");
  granule::io::write_lammps_data(path, f, Dim3::Vec(0, 0, 0), Dim3::Vec(1, 1, 1), 1000.0,
                                 {true, false, false});
  const auto data = granule::io::read_lammps_data(path);
  // x wrapped by whole box lengths: 1.25 -> 0.25, -0.5 -> 0.5; y, z untouched.
  CHECK(data.frame.x[0].x() == Approx(0.25).margin(1e-15));
  CHECK(data.frame.x[1].x() == Approx(0.5).margin(1e-15));
  CHECK(data.frame.x[1].z() == 0.0);
  // Without ids in the frame, the particle index is the id.
  CHECK(data.frame.id[0] == 0);
  CHECK(data.frame.id[1] == 1);
  // No velocities in the frame: no Velocities section, particles read back at rest.
  CHECK(lammps_read_text(path).find("Velocities") == std::string::npos);
  CHECK(data.frame.v[1] == Dim3::Vec::Zero());

  f.x[1].y() = 1.5;  // outside the non-periodic y extent
  CHECK_THROWS_AS(granule::io::write_lammps_data(path, f, Dim3::Vec(0, 0, 0), Dim3::Vec(1, 1, 1),
                                                 1000.0, {true, false, false}),
                  granule::InvalidParameter);
  std::remove(path.c_str());
}

TEST_CASE("lammps_data: overload takes box and periodicity from the frame", "[io][lammps_data]") {
  Frame3 f;
  f.x = {Dim3::Vec(-0.1, 0.5, 0.5)};
  f.radius = {0.1};
  f.v = {Dim3::Vec(1.0, 2.0, 3.0)};
  f.box_lo = Dim3::Vec(0, 0, 0);
  f.box_hi = Dim3::Vec(2, 1, 1);
  f.periodic[0] = true;
  const std::string path = lammps_temp_path("frame_box.data");
  granule::io::write_lammps_data(path, f, 1100.0, /*with_velocities=*/false);
  const auto data = granule::io::read_lammps_data(path);
  CHECK(data.frame.box_hi == f.box_hi);
  CHECK(data.frame.x[0].x() == Approx(1.9).margin(1e-15));  // wrapped by the 2 m period
  CHECK(data.frame.v[0] == Dim3::Vec::Zero());                // velocities left out on request
  std::remove(path.c_str());
}

TEST_CASE("lammps_data: reads the layout of LIGGGHTS write_data", "[io][lammps_data]") {
  // Shape of a LIGGGHTS 3.8 write_data file: no style comment, image flags, unsorted ids.
  const std::string text =
      "LAMMPS data file via write_data, version Version LIGGGHTS-PUBLIC 3.8.0, timestep = 30000\n"
      "\n"
      "3 atoms\n"
      "1 atom types\n"
      "\n"
      "0.0000000000000000e+00 5.9999999999999998e-02 xlo xhi\n"
      "0.0000000000000000e+00 5.9999999999999998e-02 ylo yhi\n"
      "0.0000000000000000e+00 1.0000000000000001e-01 zlo zhi\n"
      "\n"
      "Atoms\n"
      "\n"
      "2183 1 2.0000000000000000e-03 1.1000000000000000e+03 1.5e-03 9.9e-04 9.99e-04 0 0 0\n"
      "17 1 2.0000000000000000e-03 1.1000000000000000e+03 5.3e-03 9.7e-04 9.96e-04 1 0 0\n"
      "330 1 2.0000000000000000e-03 1.1000000000000000e+03 8.3e-03 9.6e-04 9.97e-04 0 0 0\n"
      "\n"
      "Velocities\n"
      "\n"
      "330 0 0 -1e-3 0 0 0\n"
      "2183 1 2 3 4 5 6\n"
      "17 0 0 0 0 0 0\n";
  const std::string path = lammps_temp_path("liggghts.data");
  write_text(path, text);
  const auto data = granule::io::read_lammps_data(path);
  REQUIRE(data.frame.size() == 3);
  CHECK(data.frame.id[0] == 16);
  CHECK(data.frame.id[1] == 329);
  CHECK(data.frame.id[2] == 2182);
  CHECK(data.frame.x[0].x() == 5.3e-03);   // image flags ignored
  CHECK(data.frame.v[1].z() == -1e-3);
  CHECK(data.frame.omega[2] == Dim3::Vec(4, 5, 6));
  CHECK(data.frame.radius[2] == 1e-3);
  CHECK(data.frame.box_hi.z() == 1.0000000000000001e-01);
  std::remove(path.c_str());
}

TEST_CASE("lammps_data: bad input is rejected", "[io][lammps_data]") {
  Frame3 f;
  f.x = {Dim3::Vec(0.5, 0.5, 0.5)};
  f.radius = {0.1};
  const std::string path = lammps_temp_path("bad.data");
  const Dim3::Vec lo(0, 0, 0), hi(1, 1, 1);
  using granule::InvalidParameter;
  using granule::IoError;
  CHECK_THROWS_AS(granule::io::write_lammps_data(path, f, lo, hi, -1.0, {false, false, false}),
                  InvalidParameter);
  CHECK_THROWS_AS(granule::io::write_lammps_data(path, f, hi, lo, 1.0, {false, false, false}),
                  InvalidParameter);
  f.radius = {0.0};
  CHECK_THROWS_AS(granule::io::write_lammps_data(path, f, lo, hi, 1.0, {false, false, false}),
                  InvalidParameter);
  f.radius = {0.1};
  f.x.push_back(Dim3::Vec(0.2, 0.2, 0.2));
  f.radius.push_back(0.1);
  f.id = {4, 4};
  CHECK_THROWS_AS(granule::io::write_lammps_data(path, f, lo, hi, 1.0, {false, false, false}),
                  InvalidParameter);
  try {
    granule::io::write_lammps_data(path, f, lo, hi, -2.0, {false, false, false});
  } catch (const InvalidParameter& e) {
    CHECK(std::string(e.what()).find("write_lammps_data: density = -2") != std::string::npos);
  }

  CHECK_THROWS_AS(granule::io::read_lammps_data(lammps_temp_path("does_not_exist.data")), IoError);
  const std::string header = "title\n\n2 atoms\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n\n";
  write_text(path, header + "Atoms # sphere\n\n1 1 0.1 1000 0.5 0.5 0.5\n");
  CHECK_THROWS_AS(granule::io::read_lammps_data(path), IoError);  // 1 row for 2 atoms
  write_text(path, header + "Atoms # atomic\n\n1 1 0.5 0.5 0.5\n2 1 0.2 0.2 0.2\n");
  CHECK_THROWS_AS(granule::io::read_lammps_data(path), IoError);  // wrong atom style
  write_text(path, header + "Atoms\n\n1 1 0.1 1000 0.5 0.5 0.5\n1 1 0.1 1000 0.2 0.2 0.2\n");
  CHECK_THROWS_AS(granule::io::read_lammps_data(path), IoError);  // duplicate id
  write_text(path, header + "Atoms\n\n1 1 0.1 1000 0.5 0.5 0.5\n2 1 0.1 1000 0.2 0.2 0.2\n"
                            "\nVelocities\n\n3 0 0 0 0 0 0\n");
  CHECK_THROWS_AS(granule::io::read_lammps_data(path), IoError);  // velocity of unknown id
  write_text(path, "title\n\n1 atoms\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n0.5 0 0 xy xz yz\n"
                   "\nAtoms\n\n1 1 0.1 1000 0.5 0.5 0.5\n");
  CHECK_THROWS_AS(granule::io::read_lammps_data(path), IoError);  // triclinic
  std::remove(path.c_str());
}
