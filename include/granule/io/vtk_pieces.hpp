#pragma once
// Particle output of a distributed run as VTK's parallel unstructured grid (docs/mpi.md,
// "Output"): at each frame every rank writes its own particles as one .vtu piece
// (<name>_<frame>_<rank>.vtu, the format of io/vtk.hpp), and rank 0 writes <name>_<frame>.pvtu,
// which declares the arrays once (<PPointData>, <PPoints>) and names every piece
// (<Piece Source=...>), and adds it to <name>.pvd, the time series ParaView opens. The pieces
// are written before the .pvtu (the outcome of every rank's write is agreed first, so an error
// on one rank is thrown on every rank and no .pvtu names a piece that is missing). In one
// process the same writer writes one piece.
//
//   io::PieceVtkWriter<Dim3> out("out", "particles");
//   sim.every(1000, [&](auto& s) { out.write(s); });   // collective in a distributed run
#include <filesystem>
#include <string>
#include <vector>

#include "granule/io/vtk.hpp"

namespace granule::io {

/// Writes the .pvtu of one frame: the arrays of `layout` (any piece's grid: names, types and
/// components; its values are not used) and the piece files, relative to the .pvtu.
inline void write_pvtu(const std::filesystem::path& path, const VtkGrid& layout, const std::vector<std::string>& pieces) {
  std::string x = "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"";
  x += std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";
  x += "\" header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n";
  auto declare = [&](const std::string& name, const char* type, int components) {
    x += "      <PDataArray type=\"";
    x += type;
    x += "\" Name=\"" + detail::xml_escape(name) + "\" NumberOfComponents=\"" + std::to_string(components) + "\"/>\n";
  };
  auto declare_all = [&](const std::vector<VtkArray>& arrays) {
    for (const VtkArray& a : arrays)
      std::visit([&](const auto& v) { declare(a.name, detail::vtk_type_name<typename std::decay_t<decltype(v)>::value_type>(), a.components); },
                 a.values);
  };
  x += "    <PPointData>\n";
  declare_all(layout.point_data);
  x += "    </PPointData>\n    <PCellData>\n";
  declare_all(layout.cell_data);
  x += "    </PCellData>\n    <PPoints>\n";
  declare("Points", detail::vtk_type_name<double>(), 3);
  x += "    </PPoints>\n";
  for (const std::string& p : pieces) x += "    <Piece Source=\"" + detail::xml_escape(p) + "\"/>\n";
  x += "  </PUnstructuredGrid>\n</VTKFile>\n";
  detail::write_atomically(path, x);
}

/// Particle frames of a distributed run: one piece per rank, a .pvtu per frame, a .pvd series.
template <class D>
class PieceVtkWriter {
 public:
  PieceVtkWriter(std::filesystem::path dir, std::string name, VtkEncoding encoding = VtkEncoding::Binary)
      : dir_(std::move(dir)), name_(std::move(name)), encoding_(encoding), pvd_(dir_ / (name_ + ".pvd")) {
    require(!name_.empty() && name_.find_first_of("/\\") == std::string::npos, "io::PieceVtkWriter", "name length",
            static_cast<double>(name_.size()), "[1, inf) characters without path separators");
  }

  /// Writes the next frame of `sim` (its own particles, Simulation::frame()) with extra fields
  /// (per own particle) at `time` [s] (default: the simulation's); returns the .pvtu path.
  /// Collective in a distributed run.
  template <class Sim>
  std::filesystem::path write(const Sim& sim, const std::vector<VtkField<D>>& fields = {},
                              std::optional<double> time = std::nullopt) {
    const analysis::Frame<D> frame = sim.frame();
    const double t = time.value_or(frame.time);
    const int rank = sim.rank(), ranks = sim.ranks();
    char num[32];
    std::snprintf(num, sizeof(num), "_%06zu", next_);
    const std::string stem = name_ + num;
    auto piece = [&](int r) { return stem + "_" + std::to_string(r) + ".vtu"; };
    VtkGrid grid;
    std::string error;
    try {
      require_finite(t, "io::PieceVtkWriter::write", "time");
      std::error_code ec;
      std::filesystem::create_directories(dir_, ec);
      if (ec) throw IoError("io::PieceVtkWriter: cannot create directory '" + dir_.string() + "': " + ec.message());
      grid = particle_grid<D>(frame, fields);
      grid.time = t;
      write_vtu(dir_ / piece(rank), grid, encoding_);
    } catch (const std::exception& e) {
      error = e.what();
    }
    agree(sim, error);
    if (rank == 0) {
      try {
        std::vector<std::string> pieces;
        for (int r = 0; r < ranks; ++r) pieces.push_back(piece(r));
        write_pvtu(dir_ / (stem + ".pvtu"), grid, pieces);
        pvd_.add(t, stem + ".pvtu");
      } catch (const std::exception& e) {
        error = e.what();
      }
    }
    agree(sim, error);
    ++next_;
    return dir_ / (stem + ".pvtu");
  }

  std::size_t frames() const { return next_; }
  const std::filesystem::path& pvd_path() const { return pvd_.path(); }

 private:
  // Every rank learns whether any rank failed; each throws (its own message, or the lowest
  // failing rank's).
  template <class Sim>
  void agree(const Sim& sim, const std::string& error) {
    if constexpr (Sim::ParallelPolicy::distributed) {
      sim.parallel_engine().context().collective([&] {
        if (!error.empty()) throw IoError(error);
      });
    } else {
      if (!error.empty()) throw IoError(error);
    }
  }

  std::filesystem::path dir_;
  std::string name_;
  VtkEncoding encoding_;
  PvdCollection pvd_;
  std::size_t next_ = 0;
};

}  // namespace granule::io
