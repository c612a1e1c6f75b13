// Disjoint sets over 0..n-1 with path compression (path halving) and union by rank.
//
// Used twice by the meshing step (paper §7.1.2): to group the local regions ("atoms") of one
// background element into element copies, and to merge the vertex copies of connected element
// copies (Teran et al. 2005, §6). Both uses are dimension-free.
#pragma once

#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace imm {

/// Disjoint-set forest. Amortised near-constant time per operation (inverse Ackermann).
class UnionFind {
 public:
  UnionFind() = default;
  /// n singleton sets {0}, {1}, ..., {n-1}.
  explicit UnionFind(std::size_t n) : parent_(n), rank_(n, 0) {
    std::iota(parent_.begin(), parent_.end(), std::uint32_t{0});
  }

  [[nodiscard]] std::size_t size() const { return parent_.size(); }

  /// Adds a new singleton set. @return its element.
  std::uint32_t add() {
    parent_.push_back(static_cast<std::uint32_t>(parent_.size()));
    rank_.push_back(0);
    return parent_.back();
  }

  /// @return the representative of x's set. @pre x < size().
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];  // path halving
      x = parent_[x];
    }
    return x;
  }

  /// Merges the sets of a and b. @return true when they were different sets.
  bool unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (rank_[a] < rank_[b]) std::swap(a, b);
    parent_[b] = a;
    if (rank_[a] == rank_[b]) ++rank_[a];
    return true;
  }

  [[nodiscard]] bool same(std::uint32_t a, std::uint32_t b) { return find(a) == find(b); }

 private:
  std::vector<std::uint32_t> parent_;
  std::vector<std::uint8_t> rank_;  // rank <= log2(n) < 256
};

}  // namespace imm
