// Strongly typed indices for the paper's combinatorial objects.
//
// Every object of the cell complex and of the immersion graph is addressed by a dense 0-based
// index wrapped in its own type, so that a patch index can never be passed where a cell index
// is expected (the compiler refuses). `IdMap<Id, T>` is a vector indexed by such an id.
#pragma once

#include <compare>
#include <cstdint>
#include <functional>
#include <limits>
#include <ostream>
#include <vector>

namespace imm {

/// A dense index with a tag type. The default-constructed id is invalid.
template <class Tag>
class StrongId {
 public:
  using value_type = std::int32_t;
  static constexpr value_type kInvalid = -1;

  constexpr StrongId() = default;
  constexpr explicit StrongId(value_type v) : value_(v) {}
  constexpr explicit StrongId(std::size_t v) : value_(static_cast<value_type>(v)) {}

  /// @return the raw index; @pre is_valid().
  [[nodiscard]] constexpr value_type value() const { return value_; }
  [[nodiscard]] constexpr std::size_t index() const { return static_cast<std::size_t>(value_); }
  [[nodiscard]] constexpr bool is_valid() const { return value_ >= 0; }

  constexpr auto operator<=>(const StrongId&) const = default;

  friend std::ostream& operator<<(std::ostream& os, StrongId id) { return os << id.value_; }

 private:
  value_type value_ = kInvalid;
};

// Paper vocabulary (§4): regions are the connected components of R^d minus the input, RegionId{0}
// is the unbounded one; cells are the regions with a non-zero winding number; patches are the
// connected components of the input minus its self-intersection; arcs are the components of the
// double-point set (points in 2D, curves in 3D); nodes are the cell copies of the immersion graph.
using RegionId = StrongId<struct RegionTag>;
using CellId = StrongId<struct CellTag>;
using PatchId = StrongId<struct PatchTag>;
using ArcId = StrongId<struct ArcTag>;
using NodeId = StrongId<struct NodeTag>;
using VertexId = StrongId<struct VertexTag>;
using ElementId = StrongId<struct ElementTag>;

/// The unbounded region (libigl's `extract_cells` convention).
inline constexpr RegionId kOutsideRegion{0};

/// A vector indexed by a strong id.
template <class Id, class T>
class IdMap {
 public:
  IdMap() = default;
  explicit IdMap(std::size_t n, const T& value = T()) : data_(n, value) {}

  T& operator[](Id id) { return data_[id.index()]; }
  const T& operator[](Id id) const { return data_[id.index()]; }

  [[nodiscard]] std::size_t size() const { return data_.size(); }
  [[nodiscard]] bool empty() const { return data_.empty(); }
  void resize(std::size_t n, const T& value = T()) { data_.resize(n, value); }
  Id push_back(T value) {
    data_.push_back(std::move(value));
    return Id(data_.size() - 1);
  }
  auto begin() { return data_.begin(); }
  auto end() { return data_.end(); }
  auto begin() const { return data_.begin(); }
  auto end() const { return data_.end(); }
  const std::vector<T>& raw() const { return data_; }
  std::vector<T>& raw() { return data_; }

 private:
  std::vector<T> data_;
};

/// All ids 0..n-1 of a type, for range-for loops: `for (CellId c : ids<CellId>(n))`.
template <class Id>
class IdRange {
 public:
  class iterator {
   public:
    explicit iterator(typename Id::value_type v) : v_(v) {}
    Id operator*() const { return Id(v_); }
    iterator& operator++() {
      ++v_;
      return *this;
    }
    bool operator!=(const iterator& o) const { return v_ != o.v_; }
    bool operator==(const iterator& o) const { return v_ == o.v_; }

   private:
    typename Id::value_type v_;
  };
  explicit IdRange(std::size_t n) : n_(static_cast<typename Id::value_type>(n)) {}
  iterator begin() const { return iterator(0); }
  iterator end() const { return iterator(n_); }

 private:
  typename Id::value_type n_;
};

template <class Id>
IdRange<Id> ids(std::size_t n) {
  return IdRange<Id>(n);
}

}  // namespace imm

template <class Tag>
struct std::hash<imm::StrongId<Tag>> {
  std::size_t operator()(imm::StrongId<Tag> id) const noexcept {
    return std::hash<std::int32_t>()(id.value());
  }
};
