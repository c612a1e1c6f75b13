#include "dim3/repair_folds.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "dim3/cut_mesh.h"

namespace imm::dim3 {
namespace {

/// Fractions of the way to the ring's centroid, tried in order: dyadic, so that small folds get
/// small moves and each step at most doubles the last one's displacement.
constexpr double kSchedule[] = {1.0 / 64, 1.0 / 32, 1.0 / 16, 1.0 / 8, 1.0 / 4, 3.0 / 8,
                                1.0 / 2,  5.0 / 8,  3.0 / 4,  7.0 / 8,  1.0};
constexpr std::size_t kSteps = sizeof(kSchedule) / sizeof(kSchedule[0]);

double distance(const Point3& a, const Point3& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

/// Centroid of the vertices sharing a triangle with v (its ring), from the input positions.
std::vector<Point3> ring_centroids(const Surface& s) {
  std::vector<std::set<std::uint32_t>> ring(s.vertex_count());
  for (const Triangle& t : s.triangles)
    for (int k = 0; k < 3; ++k) {
      ring[t[k]].insert(t[(k + 1) % 3]);
      ring[t[k]].insert(t[(k + 2) % 3]);
    }
  std::vector<Point3> centroid(s.vertex_count());
  for (std::size_t v = 0; v < ring.size(); ++v) {
    Point3 c{};
    for (std::uint32_t w : ring[v])
      for (int d = 0; d < 3; ++d) c[d] += s.vertices[w][d];
    if (!ring[v].empty())
      for (double& x : c) x /= static_cast<double>(ring[v].size());
    centroid[v] = c;
  }
  return centroid;
}

std::string format_double(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

Point3 toward(const Point3& from, const Point3& to, double t) {
  return {from[0] + t * (to[0] - from[0]), from[1] + t * (to[1] - from[1]), from[2] + t * (to[2] - from[2])};
}

}  // namespace

std::vector<std::uint32_t> local_fold_vertices(const Surface& surface, unsigned threads, bool* complete) {
  const RefineResult r = refine_surface(surface, {}, threads);
  std::set<std::uint32_t> vertices;
  std::size_t listed = 0, total = 0;
  for (const Defect& d : r.report.defects) {
    if (d.kind != DefectKind::LocalFold) continue;
    ++listed;
    for (long v : d.vertices) vertices.insert(static_cast<std::uint32_t>(v));
  }
  for (const auto& [kind, n] : r.counts)
    if (kind == DefectKind::LocalFold) total += n;
  if (complete) *complete = listed == total;
  return {vertices.begin(), vertices.end()};
}

FoldRepair repair_folds(const Surface& surface, double max_displacement, unsigned threads) {
  FoldRepair out;
  out.surface = surface;
  const std::vector<Point3> centroid = ring_centroids(surface);
  // Per vertex being repaired: the index of its current step in kSchedule.
  std::map<std::uint32_t, std::size_t> step;
  bool complete = true;
  std::vector<std::uint32_t> folded = local_fold_vertices(surface, threads, &complete);
  ++out.checks;
  std::set<std::uint32_t> unreachable;  // needs more than max_displacement, or more than the centroid
  while (!folded.empty()) {
    bool advanced = false;
    for (std::uint32_t v : folded) {
      auto [it, fresh] = step.try_emplace(v, 0);
      if (!fresh) ++it->second;  // still folded at its last step: go further
      while (it->second < kSteps &&
             distance(surface.vertices[v], toward(surface.vertices[v], centroid[v], kSchedule[it->second])) >
                 max_displacement)
        it->second = kSteps;  // the next step already moves too far
      if (it->second >= kSteps) {
        unreachable.insert(v);
        continue;
      }
      out.surface.vertices[v] = toward(surface.vertices[v], centroid[v], kSchedule[it->second]);
      advanced = true;
    }
    if (!unreachable.empty() || !advanced) break;
    // The exact re-check, on the whole surface: a move may fold a neighbour's star, which is then
    // repaired the same way. A move that makes a triangle degenerate counts as not repaired.
    if (!validate_surface(out.surface).ok()) {
      // Advance every moved vertex (the degenerate triangle is among their stars).
      folded.clear();
      for (const auto& [v, k] : step) folded.push_back(v);
      continue;
    }
    folded = local_fold_vertices(out.surface, threads, &complete);
    ++out.checks;
  }
  if (!unreachable.empty()) {
    std::string list;
    std::size_t shown = 0;
    for (std::uint32_t v : unreachable) {
      if (shown++ == 10) {
        list += ", ...";
        break;
      }
      const double full = distance(surface.vertices[v], centroid[v]);
      list += (list.empty() ? "" : ", ") + std::string("vertex ") + std::to_string(v) + " " +
              format_point(surface.vertices[v]) +
              (step[v] >= kSteps && full * kSchedule[kSteps - 1] <= max_displacement
                   ? " (still folded at its ring's centroid, " + format_double(full) + " away)"
                   : " (needs more than " + format_double(max_displacement) + "; its ring's centroid is " +
                         format_double(full) + " away)");
    }
    out.failure = std::to_string(unreachable.size()) + " fold vertex(es) not repaired within --repair-folds " +
                  format_double(max_displacement) + ": " + list;
    out.surface = surface;
    return out;
  }
  for (const auto& [v, k] : step) {
    MovedVertex m{v, surface.vertices[v], out.surface.vertices[v], 0.0};
    m.distance = distance(m.from, m.to);
    out.max_displacement = std::max(out.max_displacement, m.distance);
    out.moved.push_back(m);
  }
  out.ok = true;
  return out;
}

std::string fold_repair_note(const FoldRepair& repair, double max_displacement) {
  if (!repair.ok) return "--repair-folds: " + repair.failure;
  std::string text = "local folds repaired (--repair-folds " + format_double(max_displacement) + "): " +
                     std::to_string(repair.moved.size()) + (repair.moved.size() == 1 ? " vertex" : " vertices") +
                     " moved by at most " + format_double(repair.max_displacement) + ":";
  std::size_t shown = 0;
  for (const MovedVertex& m : repair.moved) {
    if (shown++ == 10) {
      text += " ...";
      break;
    }
    text += (shown > 1 ? "; vertex " : " vertex ") + std::to_string(m.vertex) + " " + format_point(m.from) + " -> " +
            format_point(m.to) + " by " + format_double(m.distance);
  }
  return text + "; the complex, the mesh and the .emb describe the repaired surface";
}

}  // namespace imm::dim3
