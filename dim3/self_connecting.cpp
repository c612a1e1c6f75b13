// Helper boxes for self-connecting cells (dim3/self_connecting.h). CGAL-free: it only rebuilds.
#include "dim3/self_connecting.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "core/verdicts.h"

namespace imm::dim3 {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// A box whose face crosses the cell with bounding box `cell` (see the header), nudged off
/// centre by an amount that changes with `attempt`, so a retry moves the face.
Box3 cutting_box(const Box3& cell, int attempt) {
  std::array<int, 3> axes{0, 1, 2};
  std::array<double, 3> extent{};
  for (int d = 0; d < 3; ++d) extent[d] = cell.hi[d] - cell.lo[d];
  std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) { return extent[a] > extent[b]; });
  const double size = std::max(extent[axes[0]], 1e-300);
  Box3 box;
  for (int d = 0; d < 3; ++d) {
    // Margins are odd fractions of the cell's size, so that box faces miss mesh vertices.
    const double margin = 0.1173 * size + 0.0311 * extent[d];
    box.lo[d] = cell.lo[d] - margin;
    box.hi[d] = cell.hi[d] + margin * 1.0729;
  }
  const int cut = axes[1];  // the face is orthogonal to the middle axis, so it contains the longest
  box.hi[cut] = cell.lo[cut] + (0.5 + 0.0123457 + 0.0731 * attempt) * extent[cut];
  return box;
}

Surface inside_out(Surface s) {
  for (Triangle& t : s.triangles) std::swap(t[1], t[2]);
  return s;
}

std::string describe_box(const Box3& b) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "[%.6g, %.6g] x [%.6g, %.6g] x [%.6g, %.6g]", b.lo[0], b.hi[0], b.lo[1], b.hi[1],
                b.lo[2], b.hi[2]);
  return buf;
}

}  // namespace

Surface box_surface(const Box3& b) {
  Surface s;
  for (int i = 0; i < 8; ++i) {
    s.vertices.push_back({i & 1 ? b.hi[0] : b.lo[0], i & 2 ? b.hi[1] : b.lo[1], i & 4 ? b.hi[2] : b.lo[2]});
  }
  // Outward: each quad listed counter-clockwise seen from outside.
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.triangles.push_back({q[0], q[1], q[2]});
    s.triangles.push_back({q[0], q[2], q[3]});
  }
  for (std::uint32_t t = 0; t < s.triangles.size(); ++t) s.source_face.push_back(t / 2);
  return s;
}

Immersed immerse_surface(const Surface& surface, const ImmerseOptions& options) {
  Immersed out;
  out.input_triangles = surface.triangle_count();
  out.input_vertices = surface.vertex_count();
  Surface current = surface;
  int attempt = 0;
  std::optional<Box3> pending;  // the box being tried
  Box3 pending_cell;            // bounding box of the cell it cuts
  bool reversed_input = false;  // build_complex flips inside-out input as a whole
  Surface before_box;
  BuildOptions build_options = options.build;
  while (true) {
    auto start = std::chrono::steady_clock::now();
    BuildResult build = build_complex(current, build_options);
    out.build_seconds += seconds_since(start);
    if (!out.repair && build.repair) {
      // The user's local folds, repaired (or not) on the first build: later builds start from the
      // repaired surface.
      out.repair = build.repair;
      if (build.repair->ok) current = build.repair->surface;
    }
    build_options.repair_folds.reset();
    if (!out.contacts && build.contacts) {
      // The user's contacts, resolved (or not) on the first build. Later builds start from the
      // perturbed surface and are strict: a helper box that touches it is moved, not perturbed.
      out.contacts = build.contacts;
      if (build.contacts->perturbation) current = build.contacts->resolved;
    }
    build_options.strict = true;
    if (pending && !build.report.ok() && attempt < 4) {
      // The helper box touched the surface in a non-generic way: move its face and retry.
      out.notes.push_back("helper box " + describe_box(*pending) + " touches the input non-generically; moved");
      ++attempt;
      pending = cutting_box(pending_cell, attempt);
      current = merge(before_box, reversed_input ? inside_out(box_surface(*pending)) : box_surface(*pending));
      continue;
    }
    out.build = std::move(build);
    out.surface = current;
    if (!out.build.report.ok() || out.build.inversion || !out.build.complex) return out;
    if (pending) {
      out.helper_boxes.push_back(*pending);
      pending.reset();
    }
    const Complex& c3 = *out.build.complex;
    start = std::chrono::steady_clock::now();
    out.search = find_immersions(c3.complex, options.search);
    out.search_seconds += seconds_since(start);
    if (out.search.status != ImmersionStatus::SelfConnectingCell) return out;
    if (static_cast<int>(out.helper_boxes.size()) >= options.max_boxes || out.search.conflict.cells.empty()) {
      if (options.max_boxes > 0) {
        out.notes.push_back("stopped after " + std::to_string(out.helper_boxes.size()) +
                            " helper box(es): a self-connecting cell remains");
      }
      return out;
    }
    const CellId cell = out.search.conflict.cells.front();
    const RegionId region = c3.complex.region_of(cell);
    pending_cell = c3.region_box[region];
    reversed_input = c3.reversed;
    attempt = 0;
    pending = cutting_box(pending_cell, attempt);
    out.notes.push_back("cell " + std::to_string(cell.value()) + " (winding number " +
                        std::to_string(c3.complex.winding_number(cell)) + ", boundary genus " +
                        std::to_string(c3.region_genus[region]) + ") may be self-connecting: cut with helper box " +
                        describe_box(*pending) + " (paper §6.2)");
    before_box = current;
    // An inside-out input is flipped as a whole by build_complex: flip the box with it.
    current = merge(current, reversed_input ? inside_out(box_surface(*pending)) : box_surface(*pending));
  }
}

std::string helper_box_hint(const Immersed& im, bool boxes_allowed) {
  const std::size_t boxes = im.helper_boxes.size();
  std::string hint;
  if (im.search.status == ImmersionStatus::SelfConnectingCell && !boxes_allowed) {
    hint = " (helper boxes disabled by --no-helper-boxes)";
  } else if (im.search.status == ImmersionStatus::SelfConnectingCell) {
    hint = " (still self-connecting after " + plural(boxes, "helper box", "helper boxes") + ")";
  }
  if (boxes > 0) {
    hint += " [cell, patch and arc ids refer to the input with " + plural(boxes, "helper box", "helper boxes") +
            " added; see the notes above]";
  }
  return hint;
}

std::string helper_box_defect_note(const Immersed& im) {
  for (const Defect& d : im.build.report.defects) {
    for (long f : d.facets) {
      if (f >= static_cast<long>(im.input_triangles)) {
        return "triangles from id " + std::to_string(im.input_triangles) +
               " on belong to the helper boxes added for self-connecting cells; run with "
               "--no-helper-boxes to see the verdict without them";
      }
    }
  }
  return "";
}

}  // namespace imm::dim3
