#pragma once
// The materials of a scene and their precomputed pair properties. Particle and wall materials
// share one table; an index into it is what a particle or a wall stores.
#include <cstdint>
#include <string>
#include <vector>

#include "granule/materials/pair_material.hpp"

namespace granule {

class MaterialTable {
 public:
  /// Adds a material and returns its index. `is_wall` relaxes the density requirement.
  std::uint32_t add(const Material& m, bool is_wall = false) {
    m.validate(is_wall);
    materials_.push_back(m);
    const std::size_t n = materials_.size();
    std::vector<PairMaterial> grown(n * n);
    for (std::size_t a = 0; a < n; ++a)
      for (std::size_t b = 0; b < n; ++b)
        grown[a * n + b] = (a < n - 1 && b < n - 1) ? pairs_[a * (n - 1) + b]
                                                    : mix(materials_[a], materials_[b]);
    pairs_ = std::move(grown);
    return static_cast<std::uint32_t>(n - 1);
  }

  /// Replaces the fields that `o` sets in the pair properties of materials a and b (both
  /// orders), on top of the mix and of earlier overrides. Later add() calls keep them (they
  /// only mix the pairs of the new material).
  void set_pair(std::uint32_t a, std::uint32_t b, const PairOverride& o,
                const std::string& where = "MaterialTable::set_pair") {
    check_index(a, "a");
    check_index(b, "b");
    o.validate(where);
    const std::size_t n = materials_.size();
    pairs_[a * n + b] = pairs_[b * n + a] = o.apply(pairs_[a * n + b]);
  }

  /// Overrides the pair properties of materials a and b (both orders).
  void set_pair(std::uint32_t a, std::uint32_t b, const PairMaterial& p) {
    check_index(a, "a");
    check_index(b, "b");
    const std::string where = "MaterialTable::set_pair";
    require(p.E_eff > 0.0, where, "E_eff", p.E_eff, "(0, inf) Pa");
    require(p.G_eff > 0.0, where, "G_eff", p.G_eff, "(0, inf) Pa");
    require(p.restitution > 0.0 && p.restitution <= 1.0, where, "restitution", p.restitution, "(0, 1]");
    require(p.mu_s >= 0.0, where, "mu_s", p.mu_s, "[0, inf)");
    require(p.mu_r >= 0.0, where, "mu_r", p.mu_r, "[0, inf)");
    require(p.k_c >= 0.0, where, "k_c", p.k_c, "[0, inf) J/m^3");
    require(p.surface_energy >= 0.0 && std::isfinite(p.surface_energy), where, "surface_energy",
            p.surface_energy, "[0, inf) J/m^2");
    const std::size_t n = materials_.size();
    pairs_[a * n + b] = p;
    pairs_[b * n + a] = p;
  }

  const PairMaterial& pair(std::uint32_t a, std::uint32_t b) const {
    return pairs_[a * materials_.size() + b];
  }
  const Material& operator[](std::uint32_t i) const { return materials_[i]; }
  std::size_t size() const { return materials_.size(); }

 private:
  void check_index(std::uint32_t i, const char* name) const {
    require(i < materials_.size(), "MaterialTable", name, i,
            "[0, " + std::to_string(materials_.size()) + ")");
  }
  std::vector<Material> materials_;
  std::vector<PairMaterial> pairs_;
};

}  // namespace granule
