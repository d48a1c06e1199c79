#pragma once
// Bounding-volume hierarchy of axis-aligned boxes (a binary tree built top-down by splitting
// the items at the median of their box centres along the widest axis). Queries:
//   for_each_near(x, r, f): every item whose box is within distance r of x;
//   nearest(x, dist): the item minimising an exact distance dist(item) >= box distance,
//     by depth-first branch and bound (nearer child first, prune when the box is farther
//     than the best distance found).
// Median splits keep the depth <= ceil(log2(n)) + 1, so a fixed-size traversal stack suffices.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <numeric>
#include <span>
#include <utility>
#include <vector>

#include "granule/boundaries/geometry/aabb.hpp"

namespace granule::geometry {

/// Static BVH over a list of boxes; items are identified by their index in that list.
template <class D>
class AabbTree {
 public:
  using Vec = typename D::Vec;

  AabbTree() = default;

  /// Builds the tree; `leaf_size` items at most per leaf (>= 1).
  explicit AabbTree(std::span<const Aabb<D>> boxes, std::uint32_t leaf_size = 4)
      : leaf_size_(std::max<std::uint32_t>(1, leaf_size)) {
    order_.resize(boxes.size());
    std::iota(order_.begin(), order_.end(), 0u);
    if (boxes.empty()) return;
    nodes_.reserve(2 * boxes.size() / leaf_size_ + 2);
    nodes_.emplace_back();
    build(boxes, 0, 0, static_cast<std::uint32_t>(boxes.size()));
    item_boxes_.reserve(boxes.size());
    for (std::uint32_t item : order_) item_boxes_.push_back(boxes[item]);
  }

  std::size_t size() const { return order_.size(); }
  bool empty() const { return order_.empty(); }
  /// Box around all items (empty box for an empty tree).
  Aabb<D> bounds() const { return nodes_.empty() ? Aabb<D>::empty() : nodes_[0].box; }

  /// Calls f(item) for every item whose box lies within distance r of x (r >= 0) [m].
  template <class F>
  void for_each_near(const Vec& x, double r, F&& f) const {
    if (nodes_.empty()) return;
    const double r2 = r * r;
    std::array<std::uint32_t, kMaxDepth> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (node.box.squared_distance(x) > r2) continue;
      if (node.count > 0) {
        for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
          if (item_boxes_[k].squared_distance(x) <= r2) f(order_[k]);
        }
      } else {
        stack[top++] = node.first + 1;
        stack[top++] = node.first;
      }
    }
  }

  /// Item minimising dist(item) and that distance; {size(), +inf} for an empty tree.
  /// `dist` must never be smaller than the distance from x to the item's box.
  template <class Dist>
  std::pair<std::uint32_t, double> nearest(const Vec& x, Dist&& dist) const {
    std::uint32_t best = static_cast<std::uint32_t>(order_.size());
    double best_d = std::numeric_limits<double>::infinity();
    if (nodes_.empty()) return {best, best_d};
    std::array<std::uint32_t, kMaxDepth> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      const double box_d2 = node.box.squared_distance(x);
      if (box_d2 >= best_d * best_d) continue;
      if (node.count > 0) {
        for (std::uint32_t k = 0; k < node.count; ++k) {
          const std::uint32_t item = order_[node.first + k];
          const double d = dist(item);
          if (d < best_d || (d == best_d && item < best)) {
            best_d = d;
            best = item;
          }
        }
      } else {
        const std::uint32_t l = node.first;
        const std::uint32_t r = node.first + 1;
        const bool left_first = nodes_[l].box.squared_distance(x) <= nodes_[r].box.squared_distance(x);
        stack[top++] = left_first ? r : l;
        stack[top++] = left_first ? l : r;
      }
    }
    return {best, best_d};
  }

 private:
  static constexpr int kMaxDepth = 128;

  struct Node {
    Aabb<D> box = Aabb<D>::empty();
    std::uint32_t first = 0;  ///< leaf: first position in order_; inner: index of the left child
    std::uint32_t count = 0;  ///< leaf: number of items; inner: 0
  };

  void build(std::span<const Aabb<D>> boxes, std::uint32_t node_index, std::uint32_t begin, std::uint32_t end) {
    Aabb<D> box = Aabb<D>::empty();
    Aabb<D> centres = Aabb<D>::empty();
    for (std::uint32_t k = begin; k < end; ++k) {
      box.extend(boxes[order_[k]]);
      centres.extend(boxes[order_[k]].centre());
    }
    nodes_[node_index].box = box;
    if (end - begin <= leaf_size_) {
      nodes_[node_index].first = begin;
      nodes_[node_index].count = end - begin;
      return;
    }
    Eigen::Index axis = 0;
    centres.extent().maxCoeff(&axis);
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](std::uint32_t i, std::uint32_t j) {
                       const double ci = boxes[i].lo[axis] + boxes[i].hi[axis];
                       const double cj = boxes[j].lo[axis] + boxes[j].hi[axis];
                       return ci < cj || (ci == cj && i < j);
                     });
    const std::uint32_t left = static_cast<std::uint32_t>(nodes_.size());
    nodes_.emplace_back();
    nodes_.emplace_back();
    nodes_[node_index].first = left;
    nodes_[node_index].count = 0;
    build(boxes, left, begin, mid);
    build(boxes, left + 1, mid, end);
  }

  std::uint32_t leaf_size_ = 4;
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> order_;
  std::vector<Aabb<D>> item_boxes_;  // boxes in leaf order (order_[k] owns item_boxes_[k])
};

}  // namespace granule::geometry
