// Seeded benchmark inputs shared by the bench_*.cpp families. Everything is derived from the
// CGAL-free generators of tests/support/random_curves.h (the ones the property tests use), and
// every random choice takes an explicit seed, so a run is reproducible bit for bit.
#pragma once

#include <cstdint>
#include <memory>
#include <random>
#include <utility>

#include "dim2/complex2.h"
#include "support/random_curves.h"

namespace imm::bench {

/// Radius of the star-shaped disks (integer coordinates up to ~10^6 * sqrt(disks)).
inline constexpr int kDiskRadius = 1'000'000;

/// `disks` counter-clockwise star-shaped simple polygons (test_support::random_star_curve with one turn
/// and no backtracking, `vertices` each, radius in [0.35, 1] kDiskRadius) whose centres lie on a
/// square grid of pitch `pitch_percent`% of kDiskRadius with a seeded jitter of 0.2 kDiskRadius,
/// so that each disk's jagged boundary crosses those of its (up to 8) grid neighbours.
///
/// Every curve bounds an embedded disk, so the set is immersible (the disks kept apart are an
/// immersion) and every winding number is >= 0. The smaller the pitch, the deeper the overlaps
/// (higher winding numbers) and the harder the search. For a fixed pitch and `vertices` the
/// number of arcs grows linearly with `disks`.
inline dim2::CurveSet overlapping_disks(std::uint64_t seed, std::size_t disks, std::size_t vertices,
                                        int pitch_percent) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> jitter(-kDiskRadius / 5, kDiskRadius / 5);
  std::size_t columns = 1;
  while (columns * columns < disks) ++columns;
  const int pitch = kDiskRadius / 100 * pitch_percent;
  dim2::CurveSet set;
  for (std::size_t k = 0; k < disks; ++k) {
    dim2::Curve disk =
        test_support::random_star_curve(seed * 1009 + k, vertices, kDiskRadius, /*backtrack=*/0.0);
    const double dx = static_cast<double>(static_cast<int>(k % columns) * pitch + jitter(rng));
    const double dy = static_cast<double>(static_cast<int>(k / columns) * pitch + jitter(rng));
    for (dim2::Point& p : disk.vertices) {
      p.x += dx;
      p.y += dy;
    }
    set.curves.push_back(std::move(disk));
  }
  return set;
}

/// A built complex together with the seed that produced it.
struct BuiltInput {
  dim2::CurveSet curves;
  std::shared_ptr<dim2::Complex2> complex;
  std::uint64_t seed = 0;
};

/// Tries seeds first_seed, first_seed + 1, ... (at most `attempts`) until `make(seed)` gives a
/// curve set whose complex builds without defects and without inversion, and `accept(complex)`
/// holds. Integer coordinates can, rarely, produce a touching or a triple point: such inputs are
/// invalid (exit 2) and skipped. @return an empty complex when no seed worked.
template <class Make, class Accept>
BuiltInput first_valid(std::uint64_t first_seed, int attempts, Make&& make, Accept&& accept) {
  for (std::uint64_t seed = first_seed; seed < first_seed + static_cast<std::uint64_t>(attempts);
       ++seed) {
    dim2::CurveSet curves = make(seed);
    dim2::BuildResult built = dim2::build_complex(curves);
    if (!built.report.ok() || built.inversion || !built.complex || !accept(*built.complex))
      continue;
    return {std::move(curves), std::move(built.complex), seed};
  }
  return {};
}

}  // namespace imm::bench
