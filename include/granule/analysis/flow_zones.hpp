#pragma once
// Flow zones of a 2D coarse-grained velocity field around a moving source (an intruder), and the
// opening of the mobile cone above it (paper 002 section 3.2, fig. 8).
//
// The field is the normalised speed v* = |V(r)| / V_source on the nodes of a RegularGrid<Dim2>
// (coarse_graining.hpp, V_source the source's speed). 002 splits it into three zones:
//   immobile   v* < slow  (0.25: "blue", weak displacements by local rearrangements)
//   cone       slow <= v* <= fast ("green", grains displaced in a conic domain above the source)
//   dragged    v* > fast  (0.75: "red", moving nearly with the source)
// Only nodes inside the granular bed count: packing fraction >= min_packing, which leaves out
// the air above the free surface, where the kernel still reaches a few grains but the velocity
// is that of an ever thinner layer.
//
// Wall mobility: the fraction of the bed nodes in a band next to each side wall, above the
// source, that are mobile (v* >= slow). 002 (section 4) finds that this mobility is lost once
// the source is above H1 = (W - L)/2 tan(beta), where the cone's edges meet the walls at the
// free surface.
//
// Cone edge: in each grid row between y_from and y_to, starting from the node nearest the
// source's axis x_c, the mobile zone is followed outwards while v* >= slow; the edge is the
// position where v* crosses `slow`, interpolated linearly between the last mobile node and the
// first immobile one. A row gives an edge on one side only if the axis node itself is mobile and
// the edge lies strictly inside (x_min, x_max) (a row whose mobile zone reaches the limits, e.g.
// a wall band, is truncated, not a cone edge). Each side's edge points x_e(y) are fitted by
// least squares with a line x_e = a + b y; the edge's inclination from the horizontal is
//   beta = atan2(1, b)  on the right side,  atan2(1, -b)  on the left side,
// i.e. 90 deg for a vertical edge, below 90 deg for a zone that widens upwards (002's beta = 60
// deg widens, and its H1 = (W - L)/2 tan(beta) measures beta from the horizontal), above 90 deg
// for one that narrows. Fitting the slope rather than a line through the source's tips makes
// the angle insensitive to the kernel: smoothing a sharp edge with a kernel of width w moves the
// v* = slow crossing sideways by a fixed distance of order w in every row, which changes a but
// not b.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <vector>

#include "granule/analysis/regular_grid.hpp"
#include "granule/core/dimension.hpp"
#include "granule/core/error.hpp"

namespace granule::analysis {

/// Thresholds of the zones (002 section 3.2).
struct FlowZoneThresholds {
  double slow = 0.25;        ///< v* below: immobile [-]
  double fast = 0.75;        ///< v* above: dragged with the source [-]
  double min_packing = 0.3;  ///< nodes with a lower packing fraction are outside the bed [-]
};

/// Areas of the zones inside the bed, above a given height.
struct FlowZoneAreas {
  double immobile = 0.0;  ///< v* < slow [m^2]
  double cone = 0.0;      ///< slow <= v* <= fast [m^2]
  double dragged = 0.0;   ///< v* > fast [m^2]
  double bed = 0.0;       ///< all bed nodes counted [m^2]
  double fraction_cone() const { return bed > 0.0 ? cone / bed : std::numeric_limits<double>::quiet_NaN(); }
  double fraction_dragged() const {
    return bed > 0.0 ? dragged / bed : std::numeric_limits<double>::quiet_NaN();
  }
};

/// Linear fit of one side's edge points.
struct ConeEdge {
  std::size_t rows = 0;  ///< rows with an edge on this side
  double intercept = std::numeric_limits<double>::quiet_NaN();  ///< a of x_e = a + b y [m]
  double slope = std::numeric_limits<double>::quiet_NaN();      ///< b = dx_e/dy [-]
  double angle = std::numeric_limits<double>::quiet_NaN();      ///< inclination from the horizontal [deg]
  double rms = std::numeric_limits<double>::quiet_NaN();        ///< RMS distance of the points from the line [m]
};

/// Both edges and their mean inclination.
struct ConeFit {
  ConeEdge left, right;
  /// Mean of both sides' inclinations [deg]; one side's when only one has enough rows; NaN when
  /// neither has.
  double angle = std::numeric_limits<double>::quiet_NaN();
};

/// Where to look for the cone (all lengths in the grid's coordinates).
struct ConeWindow {
  double x_centre = 0.0;   ///< the source's axis [m]
  double y_from = 0.0;     ///< lowest row [m]
  double y_to = 0.0;       ///< highest row [m]
  double x_min = -std::numeric_limits<double>::infinity();  ///< an edge must lie right of this [m]
  double x_max = std::numeric_limits<double>::infinity();   ///< and left of this [m]
  std::size_t min_rows = 3;  ///< rows needed on a side for its fit
};

namespace detail_fz {
inline void check_sizes(const RegularGrid<Dim2>& grid, const std::vector<double>& speed,
                        const std::vector<double>& packing, const char* where) {
  require(speed.size() == grid.size(), where, "speed.size()", static_cast<double>(speed.size()), "grid.size()");
  require(packing.size() == grid.size(), where, "packing.size()", static_cast<double>(packing.size()),
          "grid.size()");
}

inline ConeEdge fit_edge(const std::vector<double>& y, const std::vector<double>& x, bool right,
                         std::size_t min_rows) {
  ConeEdge e;
  e.rows = y.size();
  if (y.size() < std::max<std::size_t>(min_rows, 2)) return e;
  const double n = static_cast<double>(y.size());
  double my = 0.0, mx = 0.0;
  for (std::size_t k = 0; k < y.size(); ++k) {
    my += y[k] / n;
    mx += x[k] / n;
  }
  double syy = 0.0, sxy = 0.0;
  for (std::size_t k = 0; k < y.size(); ++k) {
    syy += (y[k] - my) * (y[k] - my);
    sxy += (y[k] - my) * (x[k] - mx);
  }
  if (!(syy > 0.0)) return e;
  e.slope = sxy / syy;
  e.intercept = mx - e.slope * my;
  double r2 = 0.0;
  for (std::size_t k = 0; k < y.size(); ++k) {
    const double r = x[k] - (e.intercept + e.slope * y[k]);
    r2 += r * r;
  }
  e.rms = std::sqrt(r2 / n);
  e.angle = std::atan2(1.0, right ? e.slope : -e.slope) * 180.0 / std::numbers::pi;
  return e;
}
}  // namespace detail_fz

/// v* = |V| / v_ref at every node.
inline std::vector<double> normalised_speed(const std::vector<Dim2::Vec>& velocity, double v_ref) {
  require_positive(v_ref, "normalised_speed", "v_ref");
  std::vector<double> s(velocity.size());
  for (std::size_t k = 0; k < velocity.size(); ++k) s[k] = velocity[k].norm() / v_ref;
  return s;
}

/// Areas of the three zones among the bed nodes with y >= y_from (each node stands for one grid
/// cell, RegularGrid::cell_volume).
inline FlowZoneAreas flow_zone_areas(const RegularGrid<Dim2>& grid, const std::vector<double>& speed,
                                     const std::vector<double>& packing, double y_from,
                                     const FlowZoneThresholds& t = {}) {
  detail_fz::check_sizes(grid, speed, packing, "flow_zone_areas");
  require(t.slow <= t.fast, "flow_zone_areas", "thresholds.slow", t.slow, "[0, thresholds.fast]");
  FlowZoneAreas a;
  const double cell = grid.cell_volume();
  for (std::size_t k = 0; k < grid.size(); ++k) {
    if (!(packing[k] >= t.min_packing) || grid.node(k).y() < y_from) continue;
    a.bed += cell;
    if (speed[k] < t.slow) {
      a.immobile += cell;
    } else if (speed[k] > t.fast) {
      a.dragged += cell;
    } else {
      a.cone += cell;
    }
  }
  return a;
}

/// Fraction of the bed nodes with y >= y_from and x < x_left or x > x_right (the bands along the
/// side walls) that are mobile, v* >= slow; NaN when the bands hold no bed node.
inline double wall_mobility(const RegularGrid<Dim2>& grid, const std::vector<double>& speed,
                            const std::vector<double>& packing, double y_from, double x_left, double x_right,
                            const FlowZoneThresholds& t = {}) {
  detail_fz::check_sizes(grid, speed, packing, "wall_mobility");
  std::size_t in = 0, mobile = 0;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const auto r = grid.node(k);
    if (!(packing[k] >= t.min_packing) || r.y() < y_from || (r.x() >= x_left && r.x() <= x_right)) continue;
    ++in;
    if (speed[k] >= t.slow) ++mobile;
  }
  return in > 0 ? static_cast<double>(mobile) / static_cast<double>(in) : std::numeric_limits<double>::quiet_NaN();
}

/// The edges of the mobile zone above a source and their inclination (file comment).
inline ConeFit cone_edges(const RegularGrid<Dim2>& grid, const std::vector<double>& speed,
                          const std::vector<double>& packing, const ConeWindow& w,
                          const FlowZoneThresholds& t = {}) {
  detail_fz::check_sizes(grid, speed, packing, "cone_edges");
  require(w.y_to >= w.y_from, "cone_edges", "window.y_to", w.y_to, "[window.y_from, inf)");
  const auto n = grid.count();
  const double hx = grid.spacing().x();
  const double x0 = grid.lo().x();
  const int ic = static_cast<int>(std::lround((w.x_centre - x0) / hx));
  ConeFit fit;
  if (ic < 0 || ic >= n.x()) return fit;
  std::vector<double> yl, xl, yr, xr;
  for (int j = 0; j < n.y(); ++j) {
    const double y = grid.lo().y() + j * grid.spacing().y();
    if (y < w.y_from || y > w.y_to) continue;
    auto at = [&](int i) { return grid.index(Dim2::IVec(i, j)); };
    const std::size_t c = at(ic);
    if (!(packing[c] >= t.min_packing) || !(speed[c] >= t.slow)) continue;
    for (int dir : {-1, +1}) {
      int i = ic;
      bool found = false;
      double xe = 0.0;
      while (i + dir >= 0 && i + dir < n.x()) {
        const std::size_t a = at(i), b = at(i + dir);
        if (!(packing[b] >= t.min_packing)) break;  // left the bed sideways: no edge in this row
        if (speed[b] < t.slow) {
          const double f = (speed[a] - t.slow) / (speed[a] - speed[b]);  // in [0, 1]
          xe = x0 + hx * (i + dir * f);
          found = true;
          break;
        }
        i += dir;
      }
      if (!found || !(xe > w.x_min && xe < w.x_max)) continue;
      (dir < 0 ? yl : yr).push_back(y);
      (dir < 0 ? xl : xr).push_back(xe);
    }
  }
  fit.left = detail_fz::fit_edge(yl, xl, false, w.min_rows);
  fit.right = detail_fz::fit_edge(yr, xr, true, w.min_rows);
  const bool l = std::isfinite(fit.left.angle), r = std::isfinite(fit.right.angle);
  if (l && r) {
    fit.angle = 0.5 * (fit.left.angle + fit.right.angle);
  } else if (l) {
    fit.angle = fit.left.angle;
  } else if (r) {
    fit.angle = fit.right.angle;
  }
  return fit;
}

}  // namespace granule::analysis
