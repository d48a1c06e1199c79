#pragma once
// Coarse-graining (CG) of a Frame onto a regular grid (Goldhirsch 2010, Granular Matter 12:239;
// Weinhart, Thornton, Luding & Bokhove 2012, Granular Matter 14:289; paper 002 eq. 4–9).
// With G the truncated Gaussian of cg_kernel.hpp, the fields at a node r are
//
//   density            ρ(r) = Σ_i m_i G(r − r_i)                                  (002 eq. 7)
//   momentum           p(r) = Σ_i m_i v_i G(r − r_i)                              (002 eq. 8)
//   velocity           V(r) = p / ρ   (0 where ρ = 0)                             (002 eq. 9)
//   packing fraction   φ(r) = Σ_i V_i G(r − r_i)            V_i: particle volume
//   kinetic stress     σ^k(r) = −Σ_i m_i v'_i ⊗ v'_i G(r − r_i),   v'_i = v_i − V(r)
//   contact stress     σ^c(r) = Σ_c b_c ⊗ F_c ∫_0^1 G(r − r_i − s b_c) ds
//
// Contact c acts on particle i with total force F_c = fn n + ft; b_c is its branch vector
// (centre of i → centre of j, or centre of i → contact point for a wall), so the segment
// r_i + s b_c, s ∈ [0, 1], is the branch (Weinhart 2012 eq. 27 for pairs and eq. 30 for the
// boundary term with the branch to the contact point).
//
// Conventions (the same in stress.hpp): tension positive, compression negative — σ = −(Weinhart's
// σ)ᵀ, identical to the sign of LIGGGHTS compute stress/atom (paper 001 eq. 8) — and the first
// index is the spatial (branch, velocity) component, the second the force component:
// σ_ab = Σ b_a F_b …. Integrated over all space, σ^c gives Σ_c b_c ⊗ F_c, the contact virial of
// stress.hpp. In 2D every field is divided by the frame thickness t, so that densities are in
// kg/m³, stresses in Pa and φ is the area fraction, as in 3D; then ∫ρ dA = M / t.
//
// Two paths produce the same fields:
//  (a) coarse_grain_direct: for every node, the sum over particles within the cutoff (cell
//      list of width ≥ c) and over contacts whose branch passes within c (segments binned by
//      midpoint). Line integrals: composite Gauss–Legendre, see cg_kernel.hpp. OpenMP over nodes.
//      The kernel normalisation is the exact continuum one, so ∫ρ dV = M exactly; the node sum
//      Σ ρ h^D approximates that integral with the lattice error of the truncated Gaussian: for
//      one particle up to ≈ 4e-3 (c = 3w) or ≈ 2e-4 (c = 4w) when w ≥ h, below 1e-10 for c ≥ 7w
//      with w ≥ 2h; it averages down over many particles at random positions.
//  (b) coarse_grain_fft: deposit m, V, m v, m v⊗v and the contact terms on a mesh with linear
//      (cloud-in-cell) weights, convolve with the kernel sampled on the mesh through FFTW
//      (r2c / c2r). Non-periodic axes are zero-padded (mesh extended by ⌊c/h⌋ + 1 nodes on each
//      side, transform length ≥ extended size + ⌊c/h⌋), so nothing wraps around; periodic axes
//      (grid tiling the frame's period) use circular convolution. The sampled kernel is
//      normalised so that Σ_k G_k h^D = 1 exactly, which makes the node sum Σ ρ h^D equal the
//      mass of the deposited particles to round-off. Contacts are deposited at 2 Gauss points
//      on each of ⌈|b| / h_min⌉ panels of the branch. The kinetic stress is formed as
//      −(Σ m v⊗v G − p⊗p / ρ), algebraically equal to the definition above. Nodes where the
//      convolved density is below 1e-12 of its maximum carry only FFT round-off: ρ, φ, p, V and
//      σ^k are set to zero there (σ^c is kept: it extends a branch beyond the particles' own
//      support, e.g. around wall contact points).
//      Accuracy: the CIC deposit is a linear interpolation of G between mesh nodes, error
//      O((h/w)²); see docs/analysis.md for the measured error against (a).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "granule/analysis/cg_kernel.hpp"
#include "granule/analysis/fftw_support.hpp"
#include "granule/analysis/frame.hpp"
#include "granule/analysis/frame_checks.hpp"
#include "granule/analysis/gauss_legendre.hpp"
#include "granule/analysis/regular_grid.hpp"
#include "granule/core/dimension.hpp"
#include "granule/core/error.hpp"

namespace granule::analysis {

/// Options of the coarse-graining paths.
struct CgOptions {
  int line_points = 7;          ///< direct path: Gauss–Legendre points per panel (≤ w) of a branch
  bool contact_stress = true;   ///< compute σ^c (the most expensive field)
};

/// Coarse-grained fields sampled on the nodes of `grid` (flat node index, see RegularGrid).
template <class D>
struct CgFields {
  using Vec = typename D::Vec;
  using Mat = typename D::Mat;
  RegularGrid<D> grid;
  std::vector<double> density;           ///< ρ [kg/m^3]
  std::vector<Vec> momentum;             ///< p [kg/(m^2 s)]
  std::vector<Vec> velocity;             ///< V = p/ρ [m/s]
  std::vector<double> packing_fraction;  ///< φ [-]
  std::vector<Mat> kinetic_stress;       ///< σ^k [Pa]
  std::vector<Mat> contact_stress;       ///< σ^c [Pa] (zero when CgOptions::contact_stress is off)

  /// Total stress σ^k + σ^c at node idx [Pa].
  Mat stress(std::size_t idx) const { return kinetic_stress[idx] + contact_stress[idx]; }
  std::size_t size() const { return density.size(); }
};

namespace detail_cg {

using granule::detail::check_frame;
using granule::detail::min_image;

/// Items (points) binned in cells at least `radius` wide, for "all items within radius of p"
/// queries. Periodic axes of the frame wrap; other axes span the items' bounding box.
template <class D>
class CellBins {
 public:
  using Vec = typename D::Vec;
  using IVec = typename D::IVec;

  CellBins(const std::vector<Vec>& pts, double radius, const Frame<D>& f) {
    Vec lo = Vec::Zero();
    Vec hi = Vec::Zero();
    if (!pts.empty()) {
      lo = pts[0];
      hi = pts[0];
      for (const Vec& p : pts) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
    double r = radius;
    for (;;) {
      std::size_t total = 1;
      for (int a = 0; a < D::dim; ++a) {
        per_[a] = f.periodic[a];
        const double extent = per_[a] ? f.box_hi[a] - f.box_lo[a] : hi[a] - lo[a];
        origin_[a] = per_[a] ? f.box_lo[a] : lo[a];
        const double cells = std::floor(extent / r);
        n_[a] = static_cast<int>(std::clamp(cells, 1.0, 1e6));
        cell_[a] = std::max(extent / n_[a], r);  // never narrower than the search radius
        total *= static_cast<std::size_t>(n_[a]);
      }
      if (total <= 8 * pts.size() + 64) break;
      r *= 2.0;  // sparse items in a large region: coarser cells keep memory bounded
    }
    std::size_t ncell = 1;
    for (int a = 0; a < D::dim; ++a) ncell *= static_cast<std::size_t>(n_[a]);
    start_.assign(ncell + 1, 0);
    std::vector<std::uint32_t> cell_of(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      cell_of[i] = static_cast<std::uint32_t>(flat(item_cell(pts[i])));
      ++start_[cell_of[i] + 1];
    }
    for (std::size_t k = 0; k < ncell; ++k) start_[k + 1] += start_[k];
    items_.resize(pts.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < pts.size(); ++i) items_[fill[cell_of[i]]++] = static_cast<std::uint32_t>(i);
  }

  /// Calls f(item) for every item in the cells adjacent to p's cell (a superset of the items
  /// within `radius` of p).
  template <class F>
  void for_each_near(const Vec& p, F&& f) const {
    int lo[3] = {0, 0, 0};
    int hi[3] = {0, 0, 0};
    int base[3] = {0, 0, 0};
    bool wrap[3] = {false, false, false};
    for (int a = 0; a < D::dim; ++a) {
      const int k = static_cast<int>(std::floor((p[a] - origin_[a]) / cell_[a]));
      if (per_[a]) {
        if (n_[a] < 3) {
          lo[a] = 0;
          hi[a] = n_[a] - 1;
        } else {
          lo[a] = -1;
          hi[a] = 1;
          base[a] = ((k % n_[a]) + n_[a]) % n_[a];
          wrap[a] = true;
        }
      } else {
        lo[a] = std::max(k - 1, 0);
        hi[a] = std::min(k + 1, n_[a] - 1);
        if (lo[a] > hi[a]) return;
      }
    }
    IVec c;
    if constexpr (D::dim == 2) {
      for (int j = lo[1]; j <= hi[1]; ++j) {
        c[1] = wrap[1] ? (base[1] + j + n_[1]) % n_[1] : j;
        for (int i = lo[0]; i <= hi[0]; ++i) {
          c[0] = wrap[0] ? (base[0] + i + n_[0]) % n_[0] : i;
          visit(flat(c), f);
        }
      }
    } else {
      for (int k = lo[2]; k <= hi[2]; ++k) {
        c[2] = wrap[2] ? (base[2] + k + n_[2]) % n_[2] : k;
        for (int j = lo[1]; j <= hi[1]; ++j) {
          c[1] = wrap[1] ? (base[1] + j + n_[1]) % n_[1] : j;
          for (int i = lo[0]; i <= hi[0]; ++i) {
            c[0] = wrap[0] ? (base[0] + i + n_[0]) % n_[0] : i;
            visit(flat(c), f);
          }
        }
      }
    }
  }

 private:
  template <class F>
  void visit(std::size_t cell, F& f) const {
    for (std::uint32_t k = start_[cell]; k < start_[cell + 1]; ++k) f(items_[k]);
  }
  IVec item_cell(const Vec& p) const {
    IVec c;
    for (int a = 0; a < D::dim; ++a) {
      int k = static_cast<int>(std::floor((p[a] - origin_[a]) / cell_[a]));
      if (per_[a]) {
        k = ((k % n_[a]) + n_[a]) % n_[a];
      } else {
        k = std::clamp(k, 0, n_[a] - 1);
      }
      c[a] = k;
    }
    return c;
  }
  std::size_t flat(const IVec& c) const {
    std::size_t idx = 0;
    for (int a = D::dim - 1; a >= 0; --a) idx = idx * static_cast<std::size_t>(n_[a]) + c[a];
    return idx;
  }

  Vec origin_ = Vec::Zero();
  Vec cell_ = Vec::Ones();
  IVec n_ = IVec::Ones();
  Eigen::Matrix<bool, D::dim, 1> per_ = Eigen::Matrix<bool, D::dim, 1>::Constant(false);
  std::vector<std::uint32_t> start_;
  std::vector<std::uint32_t> items_;
};

/// Checks shared by both paths; returns the largest branch length [m].
template <class D>
double check_inputs(const Frame<D>& f, const RegularGrid<D>& grid, const GaussianCgKernel<D>& kernel,
                    const CgOptions& opt, const std::string& where) {
  check_frame(f, where);
  require(opt.line_points >= 1 && opt.line_points <= 64, where, "options.line_points",
          opt.line_points, "[1, 64]");
  double max_branch = 0.0;
  if (opt.contact_stress) {
    for (const auto& c : f.contacts) max_branch = std::max(max_branch, c.branch.norm());
  }
  for (int a = 0; a < D::dim; ++a) {
    if (grid.periodic()[a]) {
      require(f.periodic[a], where, "grid.periodic()[" + std::to_string(a) + "]", 1.0,
              "false: the frame is not periodic on this axis");
    }
    if (!f.periodic[a]) continue;
    const double length = f.box_hi[a] - f.box_lo[a];
    require_positive(length, where, "periodic box length on axis " + std::to_string(a));
    require(2.0 * (kernel.cutoff() + 0.5 * max_branch) < length, where,
            "2 (cutoff + max branch / 2) on periodic axis " + std::to_string(a),
            2.0 * (kernel.cutoff() + 0.5 * max_branch), "(0, box length = " + granule::detail::to_text(length) + ")");
  }
  return max_branch;
}

}  // namespace detail_cg

/// Direct-summation coarse-graining of `frame` on the nodes of `grid` (path (a) above).
template <class D>
CgFields<D> coarse_grain_direct(const Frame<D>& frame, const RegularGrid<D>& grid,
                                const GaussianCgKernel<D>& kernel, const CgOptions& options = {}) {
  using Vec = typename D::Vec;
  using Mat = typename D::Mat;
  const double max_branch =
      detail_cg::check_inputs(frame, grid, kernel, options, "coarse_grain_direct");
  const double scale = (D::dim == 2) ? 1.0 / frame.thickness : 1.0;
  const double c = kernel.cutoff();
  const double c2 = c * c;
  const std::size_t n = frame.size();

  std::vector<double> vol(n);
  for (std::size_t i = 0; i < n; ++i) vol[i] = granule::detail::particle_volume(frame, i);
  const detail_cg::CellBins<D> particle_bins(frame.x, c, frame);

  const bool with_contacts = options.contact_stress && !frame.contacts.empty();
  std::vector<Vec> mid;
  std::vector<Mat> bf;
  if (with_contacts) {
    mid.reserve(frame.contacts.size());
    bf.reserve(frame.contacts.size());
    for (const auto& ct : frame.contacts) {
      mid.push_back(frame.x[ct.i] + 0.5 * ct.branch);
      bf.push_back(ct.branch * granule::detail::contact_force(ct).transpose());
    }
  }
  const detail_cg::CellBins<D> contact_bins(mid, c + 0.5 * max_branch, frame);
  const granule::detail::GaussLegendreRule rule(options.line_points);

  CgFields<D> out;
  out.grid = grid;
  const std::size_t nodes = grid.size();
  out.density.assign(nodes, 0.0);
  out.momentum.assign(nodes, Vec::Zero());
  out.velocity.assign(nodes, Vec::Zero());
  out.packing_fraction.assign(nodes, 0.0);
  out.kinetic_stress.assign(nodes, Mat::Zero());
  out.contact_stress.assign(nodes, Mat::Zero());

#pragma omp parallel
  {
    std::vector<std::pair<std::uint32_t, double>> near;
    near.reserve(256);
#pragma omp for schedule(dynamic, 16)
    for (std::ptrdiff_t t = 0; t < static_cast<std::ptrdiff_t>(nodes); ++t) {
      const Vec r = grid.node(static_cast<std::size_t>(t));
      near.clear();
      particle_bins.for_each_near(r, [&](std::uint32_t i) {
        const Vec d = granule::detail::min_image<D>(r - frame.x[i], frame);
        const double d2 = d.squaredNorm();
        if (d2 < c2) near.emplace_back(i, kernel.value_sq(d2));
      });
      double rho = 0.0;
      double phi = 0.0;
      Vec p = Vec::Zero();
      for (const auto& [i, g] : near) {
        rho += frame.mass[i] * g;
        phi += vol[i] * g;
        p += (frame.mass[i] * g) * frame.v[i];
      }
      const Vec vel = rho > 0.0 ? Vec(p / rho) : Vec(Vec::Zero());
      Mat kin = Mat::Zero();
      for (const auto& [i, g] : near) {
        const Vec dv = frame.v[i] - vel;
        kin -= (frame.mass[i] * g) * dv * dv.transpose();
      }
      Mat con = Mat::Zero();
      if (with_contacts) {
        contact_bins.for_each_near(r, [&](std::uint32_t k) {
          const auto& ct = frame.contacts[k];
          const Vec a = granule::detail::min_image<D>(r - mid[k], frame) + 0.5 * ct.branch;
          const double li = kernel.line_integral(a, ct.branch, rule);
          if (li != 0.0) con += li * bf[k];
        });
      }
      const auto s = static_cast<std::size_t>(t);
      out.density[s] = scale * rho;
      out.packing_fraction[s] = scale * phi;
      out.momentum[s] = scale * p;
      out.velocity[s] = vel;
      out.kinetic_stress[s] = scale * kin;
      out.contact_stress[s] = scale * con;
    }
  }
  return out;
}

/// FFT (grid) coarse-graining of `frame` on the nodes of `grid` (path (b) above). Every axis on
/// which the frame is periodic must be a periodic grid axis tiling the box (RegularGrid::covering).
template <class D>
CgFields<D> coarse_grain_fft(const Frame<D>& frame, const RegularGrid<D>& grid,
                             const GaussianCgKernel<D>& kernel, const CgOptions& options = {}) {
  using Vec = typename D::Vec;
  using Mat = typename D::Mat;
  constexpr int dim = D::dim;
  const std::string where = "coarse_grain_fft";
  detail_cg::check_inputs(frame, grid, kernel, options, where);
  for (int a = 0; a < dim; ++a) {
    if (!frame.periodic[a]) continue;
    const double length = frame.box_hi[a] - frame.box_lo[a];
    require(grid.periodic()[a] && std::abs(grid.period(a) - length) <= 1e-9 * length, where,
            "grid period on periodic axis " + std::to_string(a),
            grid.periodic()[a] ? grid.period(a) : 0.0,
            "the frame's box length " + granule::detail::to_text(length) +
                " (build the grid with RegularGrid::covering)");
  }
  const double scale = (dim == 2) ? 1.0 / frame.thickness : 1.0;
  const double c = kernel.cutoff();
  const Vec h = grid.spacing();

  // Mesh layout per axis: margin m, transform length N; mesh node u sits at lo + (u − m) h.
  int kk[3] = {0, 0, 0};
  int margin[3] = {0, 0, 0};
  int len[3] = {1, 1, 1};
  for (int a = 0; a < dim; ++a) {
    kk[a] = static_cast<int>(std::floor(c / h[a]));
    const int na = grid.count()[a];
    if (grid.periodic()[a]) {
      require(2 * kk[a] + 1 <= na, where,
              "2 floor(cutoff / spacing) + 1 on periodic axis " + std::to_string(a),
              2 * kk[a] + 1, "[1, nodes on the axis = " + std::to_string(na) + "]");
      margin[a] = 0;
      len[a] = na;
    } else {
      margin[a] = kk[a] + 1;
      len[a] = granule::detail::fftw_good_size(na + 2 * margin[a] + kk[a]);
    }
  }
  std::size_t total = 1;
  for (int a = 0; a < dim; ++a) total *= static_cast<std::size_t>(len[a]);
  std::size_t ctotal = static_cast<std::size_t>(len[0] / 2 + 1);
  for (int a = 1; a < dim; ++a) ctotal *= static_cast<std::size_t>(len[a]);
  std::vector<int> fftw_dims;
  for (int a = dim - 1; a >= 0; --a) fftw_dims.push_back(len[a]);  // x fastest = last dim
  auto mesh_index = [&](const int* u) {
    std::size_t idx = 0;
    for (int a = dim - 1; a >= 0; --a) idx = idx * static_cast<std::size_t>(len[a]) + u[a];
    return idx;
  };

  // Sampled kernel, normalised so that Σ_k G_k h^D = 1, and its transform.
  granule::detail::FftwBuffer<double> kreal(total);
  granule::detail::FftwBuffer<fftw_complex> kspec(ctotal);
  const auto r2c = granule::detail::FftwPlan::r2c(fftw_dims, kreal.data(), kspec.data());
  granule::detail::FftwBuffer<double> scratch_real(total);
  granule::detail::FftwBuffer<fftw_complex> scratch_spec(ctotal);
  const auto c2r =
      granule::detail::FftwPlan::c2r(fftw_dims, scratch_spec.data(), scratch_real.data());
  {
    std::fill(kreal.data(), kreal.data() + total, 0.0);
    double sum = 0.0;
    int k[3] = {0, 0, 0};
    int u[3] = {0, 0, 0};
    const int k2max = (dim == 3) ? kk[2] : 0;
    for (k[2] = -k2max; k[2] <= k2max; ++k[2]) {
      for (k[1] = -kk[1]; k[1] <= kk[1]; ++k[1]) {
        for (k[0] = -kk[0]; k[0] <= kk[0]; ++k[0]) {
          double r2 = 0.0;
          for (int a = 0; a < dim; ++a) {
            r2 += (k[a] * h[a]) * (k[a] * h[a]);
            u[a] = ((k[a] % len[a]) + len[a]) % len[a];
          }
          const double g = kernel.value_sq(r2);
          kreal[mesh_index(u)] += g;
          sum += g;
        }
      }
    }
    const double norm = 1.0 / (sum * grid.cell_volume() * static_cast<double>(total));
    for (std::size_t q = 0; q < total; ++q) kreal[q] *= norm;  // includes FFTW's 1/N
    r2c.execute_r2c(kreal.data(), kspec.data());
  }

  // Channels: 0 mass, 1 volume, then momentum (dim), momentum flux (upper triangle), contact
  // stress (dim × dim, row-major) when requested.
  const int n_mom = dim;
  const int n_flux = dim * (dim + 1) / 2;
  const bool with_contacts = options.contact_stress && !frame.contacts.empty();
  const int n_con = with_contacts ? dim * dim : 0;
  const int n_channels = 2 + n_mom + n_flux + n_con;
  int flux_a[6];
  int flux_b[6];
  {
    int q = 0;
    for (int a = 0; a < dim; ++a)
      for (int b = a; b < dim; ++b) {
        flux_a[q] = a;
        flux_b[q] = b;
        ++q;
      }
  }
  const std::size_t n = frame.size();
  std::vector<double> vol(n);
  for (std::size_t i = 0; i < n; ++i) vol[i] = granule::detail::particle_volume(frame, i);
  // Contact sample points along each branch (2 Gauss points per panel no longer than h_min).
  std::vector<Vec> sample_x;
  std::vector<double> sample_w;
  std::vector<std::uint32_t> sample_c;
  if (with_contacts) {
    const double hmin = h.minCoeff();
    const double g = 0.5 / std::sqrt(3.0);
    for (std::size_t k = 0; k < frame.contacts.size(); ++k) {
      const auto& ct = frame.contacts[k];
      const int panels = std::max(1, static_cast<int>(std::ceil(ct.branch.norm() / hmin)));
      for (int p = 0; p < panels; ++p) {
        for (double off : {-g, g}) {
          const double s = (p + 0.5 + off) / panels;
          sample_x.push_back(frame.x[ct.i] + s * ct.branch);
          sample_w.push_back(0.5 / panels);
          sample_c.push_back(static_cast<std::uint32_t>(k));
        }
      }
    }
  }
  std::vector<Mat> bf;
  if (with_contacts) {
    for (const auto& ct : frame.contacts)
      bf.push_back(ct.branch * granule::detail::contact_force(ct).transpose());
  }

  const std::size_t nodes = grid.size();
  std::vector<std::vector<double>> channel(static_cast<std::size_t>(n_channels),
                                           std::vector<double>(nodes, 0.0));

  // Linear (CIC) deposit of value at x into the mesh.
  auto deposit = [&](double* mesh, const Vec& x, double value) {
    int u0[3] = {0, 0, 0};
    double fr[3] = {0.0, 0.0, 0.0};
    for (int a = 0; a < dim; ++a) {
      const double s = (x[a] - grid.lo()[a]) / h[a] + margin[a];
      const double fl = std::floor(s);
      u0[a] = static_cast<int>(fl);
      fr[a] = s - fl;
    }
    const int corners = 1 << dim;
    for (int m = 0; m < corners; ++m) {
      int u[3] = {0, 0, 0};
      double wgt = value;
      bool inside = true;
      for (int a = 0; a < dim; ++a) {
        const int bit = (m >> a) & 1;
        int ua = u0[a] + bit;
        wgt *= bit ? fr[a] : 1.0 - fr[a];
        if (grid.periodic()[a]) {
          ua = ((ua % len[a]) + len[a]) % len[a];
        } else if (ua < 0 || ua >= grid.count()[a] + 2 * margin[a]) {
          inside = false;
        }
        u[a] = ua;
      }
      if (inside) mesh[mesh_index(u)] += wgt;
    }
  };

#pragma omp parallel
  {
    granule::detail::FftwBuffer<double> real(total);
    granule::detail::FftwBuffer<fftw_complex> spec(ctotal);
#pragma omp for schedule(dynamic, 1)
    for (int ch = 0; ch < n_channels; ++ch) {
      double* mesh = real.data();
      std::fill(mesh, mesh + total, 0.0);
      if (ch < 2 + n_mom + n_flux) {
        for (std::size_t i = 0; i < n; ++i) {
          double value;
          if (ch == 0) {
            value = frame.mass[i];
          } else if (ch == 1) {
            value = vol[i];
          } else if (ch < 2 + n_mom) {
            value = frame.mass[i] * frame.v[i][ch - 2];
          } else {
            const int q = ch - 2 - n_mom;
            value = frame.mass[i] * frame.v[i][flux_a[q]] * frame.v[i][flux_b[q]];
          }
          deposit(mesh, frame.x[i], value);
        }
      } else {
        const int q = ch - 2 - n_mom - n_flux;
        const int a = q / dim;
        const int b = q % dim;
        for (std::size_t s = 0; s < sample_x.size(); ++s)
          deposit(mesh, sample_x[s], sample_w[s] * bf[sample_c[s]](a, b));
      }
      r2c.execute_r2c(mesh, spec.data());
      for (std::size_t q = 0; q < ctotal; ++q) {
        const double re = spec[q][0] * kspec[q][0] - spec[q][1] * kspec[q][1];
        const double im = spec[q][0] * kspec[q][1] + spec[q][1] * kspec[q][0];
        spec[q][0] = re;
        spec[q][1] = im;
      }
      c2r.execute_c2r(spec.data(), mesh);
      std::vector<double>& dst = channel[static_cast<std::size_t>(ch)];
      for (std::size_t t = 0; t < nodes; ++t) {
        const auto k = grid.coords(t);
        int u[3] = {0, 0, 0};
        for (int a = 0; a < dim; ++a) u[a] = k[a] + margin[a];
        dst[t] = scale * mesh[mesh_index(u)];
      }
    }
  }

  CgFields<D> out;
  out.grid = grid;
  out.density.assign(nodes, 0.0);
  out.momentum.assign(nodes, Vec::Zero());
  out.velocity.assign(nodes, Vec::Zero());
  out.packing_fraction.assign(nodes, 0.0);
  out.kinetic_stress.assign(nodes, Mat::Zero());
  out.contact_stress.assign(nodes, Mat::Zero());
  double rho_max = 0.0;
  for (double r : channel[0]) rho_max = std::max(rho_max, r);
  const double floor_rho = 1e-12 * rho_max;
  for (std::size_t t = 0; t < nodes; ++t) {
    if (with_contacts) {
      Mat s;
      for (int q = 0; q < n_con; ++q)
        s(q / dim, q % dim) = channel[static_cast<std::size_t>(2 + n_mom + n_flux + q)][t];
      out.contact_stress[t] = s;
    }
    const double rho = channel[0][t];
    if (!(rho > floor_rho)) continue;
    out.density[t] = rho;
    out.packing_fraction[t] = channel[1][t];
    Vec p;
    for (int a = 0; a < dim; ++a) p[a] = channel[static_cast<std::size_t>(2 + a)][t];
    out.momentum[t] = p;
    out.velocity[t] = p / rho;
    Mat flux;
    for (int q = 0; q < n_flux; ++q) {
      const double v = channel[static_cast<std::size_t>(2 + n_mom + q)][t];
      flux(flux_a[q], flux_b[q]) = v;
      flux(flux_b[q], flux_a[q]) = v;
    }
    out.kinetic_stress[t] = -(flux - p * p.transpose() / rho);
  }
  return out;
}

}  // namespace granule::analysis
