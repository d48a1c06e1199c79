// VTK writer round trip: files written by granule::io are read back with the reference VTK
// reader (python3 vtk module, tests/io/vtk_roundtrip.py) and compared value by value, exactly
// (ASCII uses shortest round-trip decimals, Binary stores raw doubles), for both encodings and
// both dimensions. Also: the .pvd collection, contact networks, wall surfaces, size checks.
// The test FAILS (it does not skip) when no python3 with the vtk module is found: CI installs
// python3-vtk9.
#include <catch2/catch.hpp>

#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#if __has_include(<sys/wait.h>)
#include <sys/wait.h>
#endif

#include "granule/granule.hpp"
#include "granule/io/vtk.hpp"

#ifndef GRANULE_SOURCE_DIR
#define GRANULE_SOURCE_DIR_FALLBACK 1
#endif

using namespace granule;
namespace fs = std::filesystem;

namespace {

// ---- a minimal JSON reader (objects, arrays, numbers, strings, literals) -------------------
struct Json {
  enum class Kind { Null, Number, String, Array, Object } kind = Kind::Null;
  double number = 0.0;
  std::string text;
  std::vector<Json> items;
  std::map<std::string, Json> fields;
  const Json& operator[](const std::string& k) const {
    const auto it = fields.find(k);
    if (it == fields.end()) throw std::runtime_error("JSON: no key '" + k + "'");
    return it->second;
  }
  const Json& operator[](std::size_t i) const { return items.at(i); }
  bool has(const std::string& k) const { return fields.count(k) > 0; }
};

class JsonParser {
 public:
  explicit JsonParser(const std::string& s) : s_(s) {}
  Json parse() {
    Json v = value();
    skip();
    if (p_ != s_.size()) throw std::runtime_error("JSON: trailing text");
    return v;
  }

 private:
  void skip() {
    while (p_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[p_]))) ++p_;
  }
  Json value() {
    skip();
    if (p_ >= s_.size()) throw std::runtime_error("JSON: unexpected end");
    Json v;
    const char c = s_[p_];
    if (c == '{') {
      v.kind = Json::Kind::Object;
      ++p_;
      skip();
      if (s_[p_] == '}') { ++p_; return v; }
      while (true) {
        skip();
        const std::string key = string();
        skip();
        ++p_;  // ':'
        v.fields[key] = value();
        skip();
        if (s_[p_++] == '}') break;
      }
    } else if (c == '[') {
      v.kind = Json::Kind::Array;
      ++p_;
      skip();
      if (s_[p_] == ']') { ++p_; return v; }
      while (true) {
        v.items.push_back(value());
        skip();
        if (s_[p_++] == ']') break;
      }
    } else if (c == '"') {
      v.kind = Json::Kind::String;
      v.text = string();
    } else if (s_.compare(p_, 4, "null") == 0) {
      p_ += 4;
    } else {
      v.kind = Json::Kind::Number;
      std::size_t e = p_;
      while (e < s_.size() && std::string_view("+-0123456789.eE").find(s_[e]) != std::string_view::npos) ++e;
      const auto [ptr, ec] = std::from_chars(s_.data() + p_, s_.data() + e, v.number);
      if (ec != std::errc() || ptr != s_.data() + e) throw std::runtime_error("JSON: bad number");
      p_ = e;
    }
    return v;
  }
  std::string string() {
    std::string out;
    ++p_;  // opening quote
    while (s_[p_] != '"') {
      if (s_[p_] == '\\') ++p_;
      out += s_[p_++];
    }
    ++p_;
    return out;
  }
  const std::string& s_;
  std::size_t p_ = 0;
};

// ---- running the reference reader ------------------------------------------------------------
fs::path source_dir() {
#ifdef GRANULE_SOURCE_DIR_FALLBACK
  return fs::path(__FILE__).parent_path().parent_path().parent_path();
#else
  return fs::path(GRANULE_SOURCE_DIR);
#endif
}

std::string read_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("granule_test_vtk_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

#ifdef GRANULE_PYTHON
const char* const kConfiguredPython = GRANULE_PYTHON;
#else
const char* const kConfiguredPython = nullptr;
#endif

int exit_code(int status) {
#ifdef WEXITSTATUS
  return status == -1 ? -1 : WEXITSTATUS(status);
#else
  return status;
#endif
}

// Reads the files with the reference reader (tests/io/vtk_roundtrip.py, one python run) and
// returns a JSON object mapping each path (as given) to its contents. Interpreters are tried
// in order: GRANULE_PYTHON, /usr/bin/python3 (Debian's python3-vtk9), python3 on PATH; one
// that lacks the vtk module (script exit code 2) or does not exist (127) passes the turn to
// the next. The first that works is remembered.
Json read_back(const std::vector<fs::path>& files) {
  static std::string chosen;
  const fs::path script = source_dir() / "tests" / "io" / "vtk_roundtrip.py";
  if (!fs::exists(script)) FAIL("Reader script not found: " << script << " (is GRANULE_SOURCE_DIR right?)");
  const fs::path out = fs::path(files.at(0)).replace_extension(".json");
  const fs::path err = fs::path(files.at(0)).replace_extension(".err");
  std::vector<std::string> candidates;
  if (!chosen.empty()) {
    candidates.push_back(chosen);
  } else {
    if (kConfiguredPython) candidates.emplace_back(kConfiguredPython);
    candidates.emplace_back("/usr/bin/python3");
    candidates.emplace_back("python3");
  }
  std::string tried;
  for (const std::string& py : candidates) {
    std::string cmd = "\"" + py + "\" \"" + script.string() + "\"";
    for (const fs::path& f : files) cmd += " \"" + f.string() + "\"";
    cmd += " > \"" + out.string() + "\" 2> \"" + err.string() + "\"";
    const int code = exit_code(std::system(cmd.c_str()));
    if (code == 0) {
      chosen = py;
      return JsonParser(read_text(out)).parse();
    }
    if (code != 2 && code != 127) {
      FAIL("The VTK reader failed (exit code " << code << ").\ncommand: " << cmd << "\nstderr: " << read_text(err));
    }
    tried += "  " + py + " (exit code " + std::to_string(code) + "): " + read_text(err) + "\n";
  }
  FAIL("No python3 with the 'vtk' module was found, so the VTK round trip cannot run.\n"
       "Install python3-vtk9 (Debian/Ubuntu) or configure CMake with -DPython3_EXECUTABLE=<python with vtk>.\n"
       "Tried:\n" << tried);
  return {};
}

Json read_back(const fs::path& file) { return read_back(std::vector<fs::path>{file})[file.string()]; }

const std::vector<io::VtkEncoding> kEncodings = {io::VtkEncoding::Ascii, io::VtkEncoding::Binary};
const char* encoding_name(io::VtkEncoding e) { return e == io::VtkEncoding::Ascii ? "ascii" : "binary"; }

template <class D>
analysis::Frame<D> sample_frame() {
  analysis::Frame<D> f;
  f.time = 0.125;
  const int n = 5;
  for (int i = 0; i < n; ++i) {
    typename D::Vec x, v;
    for (int k = 0; k < D::dim; ++k) {
      x[k] = 0.1 * i + 1.0 / (3.0 + k);  // non-terminating binary fractions
      v[k] = -std::sqrt(2.0 + i + k);
    }
    f.x.push_back(x);
    f.v.push_back(v);
    if constexpr (D::dim == 2) {
      f.omega.push_back(std::exp(0.3 * i) - 1.0);
    } else {
      f.omega.emplace_back(1.0 / 7.0 * i, -2.0 / 9.0, std::cos(double(i)));
    }
    f.radius.push_back(1e-3 * (1.0 + i / 11.0));
    f.mass.push_back(std::numbers::pi * 1e-6 * (i + 1));
    f.id.push_back(1234567890123ull + 7ull * i);
    f.group.push_back(static_cast<std::uint32_t>(i % 3));
    typename D::Vec force;
    for (int k = 0; k < D::dim; ++k) force[k] = std::sin(1.0 + i + 2.0 * k) * 1e-3;
    f.force.push_back(force);
    if constexpr (D::dim == 2) {
      f.torque.push_back(-1e-6 / (i + 3.0));
    } else {
      f.torque.emplace_back(1e-6 / (i + 3.0), -2e-7 * i, std::cos(0.5 * i) * 1e-6);
    }
  }
  return f;
}

template <class V>
void check_vec_tuple(const Json& t, const V& v) {
  for (int k = 0; k < 3; ++k) CHECK(t[k].number == (k < v.size() ? v[k] : 0.0));
}

}  // namespace

TEMPLATE_TEST_CASE("VtkWriter particle frames read back exactly with VTK", "[io][vtk]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  const auto frame = sample_frame<D>();
  std::vector<double> pressure;
  std::vector<Vec> displacement;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    pressure.push_back(1e5 / (i + 3.0));
    displacement.push_back(Vec::Constant(std::log(2.0 + i)));
  }
  std::vector<fs::path> files;  // first and second frame, per encoding
  for (io::VtkEncoding enc : kEncodings) {
    const fs::path dir = temp_dir(std::string("particles_") + encoding_name(enc) + std::to_string(D::dim));
    io::VtkWriter<D> w(dir, "particles", enc);
    files.push_back(w.write(frame, {{"pressure", pressure}, {"displacement", displacement}}, 0.25));
    files.push_back(w.write(frame));
    CHECK(files[files.size() - 2].filename() == "particles_000000.vtu");
    CHECK(files.back().filename() == "particles_000001.vtu");
  }
  const Json all = read_back(files);
  for (std::size_t e = 0; e < kEncodings.size(); ++e) {
    INFO("encoding " << encoding_name(kEncodings[e]));
    const fs::path dir = files[2 * e].parent_path();
    const Json& j = all[files[2 * e].string()];
    REQUIRE(j["points"].items.size() == frame.size());
    for (std::size_t i = 0; i < frame.size(); ++i) {
      check_vec_tuple(j["points"][i], frame.x[i]);
      CHECK(j["cell_types"][i].number == 1.0);  // VTK_VERTEX
      CHECK(j["cells"][i][0].number == double(i));
      const Json& pd = j["point_data"];
      check_vec_tuple(pd["velocity"]["tuples"][i], frame.v[i]);
      if constexpr (D::dim == 2) {
        check_vec_tuple(pd["omega"]["tuples"][i], Eigen::Vector3d(0, 0, frame.omega[i]));
      } else {
        check_vec_tuple(pd["omega"]["tuples"][i], frame.omega[i]);
      }
      CHECK(pd["radius"]["tuples"][i][0].number == frame.radius[i]);
      CHECK(pd["mass"]["tuples"][i][0].number == frame.mass[i]);
      CHECK(pd["id"]["tuples"][i][0].number == double(frame.id[i]));
      CHECK(pd["group"]["tuples"][i][0].number == double(frame.group[i]));
      check_vec_tuple(pd["force"]["tuples"][i], frame.force[i]);
      if constexpr (D::dim == 2) {
        check_vec_tuple(pd["torque"]["tuples"][i], Eigen::Vector3d(0, 0, frame.torque[i]));
      } else {
        check_vec_tuple(pd["torque"]["tuples"][i], frame.torque[i]);
      }
      CHECK(pd["pressure"]["tuples"][i][0].number == pressure[i]);
      check_vec_tuple(pd["displacement"]["tuples"][i], displacement[i]);
    }
    CHECK(j["point_data"]["id"]["type"].text == "Int64");
    CHECK(j["point_data"]["group"]["type"].text == "UInt32");
    CHECK(j["point_data"]["radius"]["type"].text == "Float64");
    CHECK(j["field_data"]["TimeValue"]["tuples"][0][0].number == 0.25);
    CHECK(all[files[2 * e + 1].string()]["field_data"]["TimeValue"]["tuples"][0][0].number == frame.time);

    // The .pvd lists both frames, and no temporary file is left behind.
    const std::string pvd = read_text(dir / "particles.pvd");
    CHECK(pvd.find("timestep=\"0.25\"") != std::string::npos);
    CHECK(pvd.find("file=\"particles_000001.vtu\"") != std::string::npos);
    for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().extension() != ".tmp");
  }
}

TEMPLATE_TEST_CASE("ContactVtkWriter writes the contact network as lines", "[io][vtk]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  auto frame = sample_frame<D>();
  analysis::ContactRecord<D> pair;
  pair.i = 1;
  pair.j = 3;
  pair.normal = Vec::Unit(0);
  pair.branch = Vec::Constant(0.3);  // e.g. a periodic image, not x_j - x_i
  pair.fn = 2.5;
  pair.ft = 0.75 * Vec::Unit(D::dim - 1);
  pair.overlap = 1e-5;
  analysis::ContactRecord<D> wall;
  wall.i = 4;
  wall.wall = 2;
  wall.normal = Vec::Unit(D::dim - 1);
  wall.branch = -1e-3 * Vec::Unit(D::dim - 1);
  wall.fn = 0.5;
  frame.contacts = {pair, wall};
  std::vector<fs::path> files;
  for (io::VtkEncoding enc : kEncodings) {
    const fs::path dir = temp_dir(std::string("contacts_") + encoding_name(enc) + std::to_string(D::dim));
    io::ContactVtkWriter<D> w(dir, "contacts", enc);
    files.push_back(w.write(frame));
  }
  io::ContactVtkWriter<D> skip(temp_dir("contacts_skip" + std::to_string(D::dim)), "c", io::VtkEncoding::Binary,
                               io::WallContacts::Skip);
  files.push_back(skip.write(frame));
  const Json all = read_back(files);
  CHECK(all[files[2].string()]["cell_types"].items.size() == 1u);
  for (std::size_t e = 0; e < kEncodings.size(); ++e) {
    INFO("encoding " << encoding_name(kEncodings[e]));
    const Json& j = all[files[e].string()];
    REQUIRE(j["cell_types"].items.size() == 2u);
    CHECK(j["cell_types"][0].number == 3.0);  // VTK_LINE
    check_vec_tuple(j["points"][0], frame.x[1]);
    check_vec_tuple(j["points"][1], Vec(frame.x[1] + pair.branch));
    check_vec_tuple(j["points"][3], Vec(frame.x[4] + wall.branch));
    const Json& cd = j["cell_data"];
    CHECK(cd["fn"]["tuples"][0][0].number == 2.5);
    CHECK(cd["ft_magnitude"]["tuples"][0][0].number == 0.75);
    check_vec_tuple(cd["force"]["tuples"][0], Vec(2.5 * Vec::Unit(0) + 0.75 * Vec::Unit(D::dim - 1)));
    CHECK(cd["id_i"]["tuples"][0][0].number == double(frame.id[1]));
    CHECK(cd["id_j"]["tuples"][0][0].number == double(frame.id[3]));
    CHECK(cd["id_j"]["tuples"][1][0].number == -1.0);
    CHECK(cd["wall"]["tuples"][1][0].number == 2.0);
    CHECK(cd["overlap"]["tuples"][0][0].number == 1e-5);
  }
  frame.contacts[0].j = 99;
  CHECK_THROWS_AS(io::contact_grid<D>(frame), InvalidParameter);
}

TEST_CASE("SurfaceVtkWriter writes triangles and lines with part ids", "[io][vtk]") {
  using V3 = Eigen::Vector3d;
  using V2 = Eigen::Vector2d;
  const std::vector<geometry::DisplayMesh> parts = {
      geometry::tessellate(geometry::CylinderShape(V3::Zero(), V3::UnitZ(), 0.1, 0.2), 8),
      geometry::tessellate(geometry::SpheroLineShape(V2(0, 0), V2(1, 0), 0.05), 8)};
  io::SurfaceVtkWriter w(temp_dir("surfaces"), "walls", io::VtkEncoding::Ascii);
  const Json j = read_back(w.write(parts, 1.5));
  const std::size_t tris = parts[0].triangles.size();
  const std::size_t lines = parts[1].lines.size();
  REQUIRE(j["cell_types"].items.size() == tris + lines);
  CHECK(j["cell_types"][0].number == 5.0);          // VTK_TRIANGLE
  CHECK(j["cell_types"][tris].number == 3.0);       // VTK_LINE
  CHECK(j["cell_data"]["part"]["tuples"][tris - 1][0].number == 0.0);
  CHECK(j["cell_data"]["part"]["tuples"][tris][0].number == 1.0);
  CHECK(j["cells"][tris][0].number == double(parts[0].points.size() + parts[1].lines[0][0]));
  CHECK(j["points"].items.size() == parts[0].points.size() + parts[1].points.size());
}

TEST_CASE("PvdCollection resumes a series after a restart", "[io][vtk]") {
  const fs::path dir = temp_dir("pvd");
  {
    io::VtkSeries s(dir, "p", io::VtkEncoding::Binary);
    analysis::Frame<Dim3> f;
    f.x = {Eigen::Vector3d::Zero()};
    for (int k = 0; k < 4; ++k) s.write(io::particle_grid<Dim3>(f), 0.1 * k);
  }
  io::VtkSeries s(dir, "p", io::VtkEncoding::Binary);
  s.resume(0.15);  // keeps t = 0 and 0.1
  CHECK(s.frames() == 2u);
  analysis::Frame<Dim3> f;
  f.x = {Eigen::Vector3d::Ones()};
  CHECK(s.write(io::particle_grid<Dim3>(f), 0.2).filename() == "p_000002.vtu");
  const auto pvd = io::PvdCollection::resume(dir / "p.pvd", 1e9);
  REQUIRE(pvd.entries().size() == 3u);
  CHECK(pvd.entries()[1].time == 0.1);
  CHECK(pvd.entries()[2].time == 0.2);
  CHECK(pvd.entries()[2].file == "p_000002.vtu");
}

TEMPLATE_TEST_CASE("particle_grid refuses fields of the wrong size", "[io][vtk]", Dim2, Dim3) {
  auto frame = sample_frame<TestType>();
  const std::vector<double> short_field(2, 1.0);
  CHECK_THROWS_WITH(io::particle_grid<TestType>(frame, std::vector<io::VtkField<TestType>>{{"p", short_field}}),
                    Catch::Contains("'p'"));
  frame.radius.pop_back();
  CHECK_THROWS_WITH(io::particle_grid<TestType>(frame), Catch::Contains("Frame::radius"));
  io::VtkGrid g;
  g.add_point(Eigen::Vector3d::Zero());
  g.add_cell(io::kVtkLine, {0, 1});
  CHECK_THROWS_AS(io::write_vtu(temp_dir("bad") / "bad.vtu", g), InvalidParameter);
}

// Frames of a simulation carry each particle's force and torque, so a .vtu holds them without
// user fields; a user field of the same name takes their place.
TEMPLATE_TEST_CASE("particle frames of a simulation carry force and torque", "[io][vtk]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  SimulationConfig<D> cfg;
  cfg.domain.hi = Vec::Constant(0.01);
  cfg.gravity = -9.81 * Vec::Unit(D::dim - 1);
  cfg.dt = 1e-6;
  cfg.thickness = 1e-3;
  Simulation<D, contact::HertzMindlin> sim(cfg);
  Material m;
  m.youngs_modulus = 1e7;
  m.poisson_ratio = 0.3;
  m.density = 2500;
  m.restitution = 0.5;
  m.friction = 0.5;
  const auto mat = sim.add_material(m);
  // Two particles pressed together off-centre with spin: forces and torques are not zero.
  sim.add_particle(Vec::Constant(0.004), 5e-4, mat, Vec::Unit(0) * 0.2);
  Vec x2 = Vec::Constant(0.004);
  x2[0] += 9.5e-4;
  x2[D::dim - 1] += 2e-4;
  sim.add_particle(x2, 5e-4, mat, -Vec::Unit(0) * 0.2);
  sim.run(20);
  const auto frame = sim.frame();
  REQUIRE(frame.force.size() == 2);
  REQUIRE(frame.torque.size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    CHECK(frame.force[i] == sim.particles().f[i]);
    CHECK(frame.torque[i] == sim.particles().torque[i]);
  }
  CHECK(frame.force[0][0] != 0.0);
  const io::VtkGrid g = io::particle_grid<D>(frame);
  const auto find = [&](const io::VtkGrid& grid, const std::string& name) -> const io::VtkArray* {
    for (const auto& a : grid.point_data)
      if (a.name == name) return &a;
    return nullptr;
  };
  const io::VtkArray* force = find(g, "force");
  const io::VtkArray* torque = find(g, "torque");
  REQUIRE(force != nullptr);
  REQUIRE(torque != nullptr);
  CHECK(force->components == 3);
  CHECK(std::get<std::vector<double>>(force->values)[0] == frame.force[0][0]);
  if constexpr (D::dim == 2) {
    CHECK(std::get<std::vector<double>>(torque->values)[2] == frame.torque[0]);
  } else {
    CHECK(std::get<std::vector<double>>(torque->values)[2] == frame.torque[0][2]);
  }
  const std::vector<double> mine{1.0, 2.0};
  const std::vector<io::VtkField<D>> fields{{"force", mine}};
  const io::VtkGrid replaced = io::particle_grid<D>(frame, fields);
  CHECK_NOTHROW(replaced.validate());
  REQUIRE(find(replaced, "force") != nullptr);
  CHECK(find(replaced, "force")->components == 1);
}
