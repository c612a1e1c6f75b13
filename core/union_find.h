// Disjoint sets over 0..n-1: UnionFind (sequential; path halving, union by rank) and
// MinRootUnionFind (unions on several threads at once, every class rooted at its smallest member).
//
// The meshing step (paper §7.1.2) uses them to give uncut local regions the region of their
// connected component, to group the local regions ("atoms") of one background element into
// element copies, and to merge the vertex copies of connected element copies (Teran et al. 2005,
// §6). All uses are dimension-free.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <numeric>
#include <utility>
#include <vector>

#include "core/huge_pages.h"
#include "core/parallel.h"

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

/// Union-find whose unions may run on several threads at once: a root is only ever linked below a
/// smaller root (compare-and-swap; a lost race retries from the new roots), so the root of every
/// class is its smallest member, whatever the order of the unions. The classes and their roots
/// are therefore the same for every thread count, which the unglue numbering (core/unglue.cpp)
/// and the regions of local regions (core/local_regions.h) rely on. Finds halve paths (a parent
/// only ever moves to an ancestor, never above the class's root).
class MinRootUnionFind {
 public:
  /// n singletons, the parents written on `threads` threads (no serial initialisation pass).
  MinRootUnionFind(std::size_t n, unsigned threads) : parent_(uninitialized_array<std::uint32_t>(n)) {
    parallel_blocks(threads, n, 1 << 16, [&](std::size_t begin, std::size_t end) {
      for (std::size_t x = begin; x < end; ++x) parent_[x] = static_cast<std::uint32_t>(x);
    });
  }
  /// The root (smallest member) of x's class; exact once no union runs concurrently.
  std::uint32_t find(std::uint32_t x) {
    for (;;) {
      std::uint32_t parent = link(x).load(std::memory_order_relaxed);
      if (parent == x) return x;
      const std::uint32_t grandparent = link(parent).load(std::memory_order_relaxed);
      // x is no root and never becomes one again, so only other halvings write parent_[x], each
      // an ancestor of x: a plain store is enough (a lost one only loses compression).
      if (grandparent != parent) link(x).store(grandparent, std::memory_order_relaxed);
      x = grandparent;
    }
  }
  /// Frees the parents (the classes are no longer needed; nothing may be called after).
  void release() { parent_.reset(); }
  void unite(std::uint32_t a, std::uint32_t b) {
    for (;;) {
      a = find(a);
      b = find(b);
      if (a == b) return;
      if (a < b) std::swap(a, b);
      std::uint32_t expected = a;  // a is still a root: link it below the smaller root b
      if (link(a).compare_exchange_strong(expected, b, std::memory_order_acq_rel)) return;
    }
  }

 private:
  std::atomic_ref<std::uint32_t> link(std::uint32_t x) { return std::atomic_ref<std::uint32_t>(parent_[x]); }
  std::unique_ptr<std::uint32_t[]> parent_;
};

}  // namespace imm
