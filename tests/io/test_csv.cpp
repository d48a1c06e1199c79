// CsvWriter: header with units in brackets, rows that read back bit-exact (std::from_chars of
// the written text equals the value), validity after each row, refusal of a wrong column
// count, append with header check and removal of a partial last row.
#include <catch2/catch.hpp>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "granule/io/csv.hpp"

using namespace granule;
namespace fs = std::filesystem;

namespace {
std::vector<std::string> lines(const fs::path& p) {
  std::ifstream f(p);
  std::vector<std::string> out;
  std::string l;
  while (std::getline(f, l)) out.push_back(l);
  return out;
}
std::vector<double> parse_row(const std::string& line) {
  std::vector<double> out;
  std::stringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ',')) {
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
    REQUIRE(ec == std::errc());
    REQUIRE(ptr == cell.data() + cell.size());
    out.push_back(v);
  }
  return out;
}
fs::path temp_file(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "granule_test_csv";
  fs::create_directories(dir);
  fs::remove(dir / name);
  return dir / name;
}
}  // namespace

TEST_CASE("CsvWriter header and exact rows", "[io][csv]") {
  const fs::path p = temp_file("series.csv");
  io::CsvWriter w(p, {{"time", "s"}, {"force_z", "N"}, {"contacts", ""}});
  CHECK(w.header() == "time [s],force_z [N],contacts");
  const double third = 1.0 / 3.0;
  const double tiny = 5e-324;  // smallest subnormal
  w.write_row({0.1, third, 12.0});
  // Valid after each row, before the writer is closed.
  auto l = lines(p);
  REQUIRE(l.size() == 2u);
  CHECK(l[0] == "time [s],force_z [N],contacts");
  CHECK(l[1] == "0.1,0.3333333333333333,12");
  const std::vector<double> row = {std::nextafter(1.0, 2.0), -tiny, 6.02214076e23};
  w.write_row(row);
  l = lines(p);
  REQUIRE(l.size() == 3u);
  const auto back = parse_row(l[2]);
  REQUIRE(back.size() == 3u);
  for (int k = 0; k < 3; ++k) CHECK(back[k] == row[k]);
  CHECK(w.rows() == 2u);
  w.write_row({std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), -0.0});
  CHECK(lines(p)[3] == "nan,inf,-0");
}

TEST_CASE("CsvWriter refuses a wrong number of values and bad names", "[io][csv]") {
  const fs::path p = temp_file("bad.csv");
  io::CsvWriter w(p, {{"time", "s"}, {"x", "m"}});
  CHECK_THROWS_AS(w.write_row({1.0}), InvalidParameter);
  CHECK_THROWS_WITH(w.write_row({1.0, 2.0, 3.0}), Catch::Contains("number of values") && Catch::Contains("2"));
  CHECK(lines(p).size() == 1u);  // nothing written
  CHECK_THROWS_AS(io::CsvWriter(temp_file("b2.csv"), {{"a,b", "s"}}), InvalidParameter);
  CHECK_THROWS_AS(io::CsvWriter(temp_file("b3.csv"), {}), InvalidParameter);
}

TEST_CASE("CsvWriter appends to a file with the same header", "[io][csv]") {
  const fs::path p = temp_file("append.csv");
  {
    io::CsvWriter w(p, {{"time", "s"}, {"e", "J"}});
    w.write_row({0.0, 1.0});
    w.write_row({0.5, 2.0});
  }
  {  // A crash left half a row.
    std::ofstream f(p, std::ios::app);
    f << "1.0,3";
  }
  {
    io::CsvWriter w(p, {{"time", "s"}, {"e", "J"}}, {true, true});
    w.write_row({1.0, 3.5});
  }
  const auto l = lines(p);
  REQUIRE(l.size() == 4u);
  CHECK(l[2] == "0.5,2");
  CHECK(l[3] == "1,3.5");
  CHECK_THROWS_AS(io::CsvWriter(p, {{"time", "s"}, {"f", "N"}}, {true, true}), IoError);
  // Without append the file starts over.
  io::CsvWriter fresh(p, {{"time", "s"}});
  CHECK(lines(p).size() == 1u);
}
