#include "render/mesh_scenes.h"

#include <cmath>

#include <algorithm>
#include <map>
#include <unordered_map>

namespace imm::render {

std::vector<bool> intersecting_triangles(const dim3::Complex& complex) {
  std::vector<std::size_t> pieces(complex.surface.triangle_count(), 0);
  for (std::uint32_t source : complex.cut_triangle_source)
    if (source < pieces.size()) ++pieces[source];
  std::vector<bool> result(pieces.size());
  for (std::size_t t = 0; t < pieces.size(); ++t) result[t] = pieces[t] > 1;
  return result;
}

Part surface_part(const dim3::Surface& surface, const std::vector<bool>& intersecting, const Color& color,
                  bool smooth) {
  Part part;
  part.name = "surface";
  part.vertices.assign(surface.vertices.begin(), surface.vertices.end());
  part.triangles.assign(surface.triangles.begin(), surface.triangles.end());
  part.color = color;
  part.smooth = smooth;
  if (intersecting.size() == surface.triangle_count() &&
      std::find(intersecting.begin(), intersecting.end(), true) != intersecting.end()) {
    part.triangle_colors.reserve(intersecting.size());
    for (bool crossing : intersecting) part.triangle_colors.push_back(crossing ? colors::kIntersecting : color);
  }
  return part;
}

Scene surface_scene(const dim3::Surface& surface, const dim3::Complex* complex, bool smooth) {
  Scene scene;
  scene.parts.push_back(surface_part(surface, complex ? intersecting_triangles(*complex) : std::vector<bool>{},
                                     colors::kSurface, smooth));
  if (complex) {
    for (const auto& points : complex->arc_points) {
      Polyline line;
      for (std::uint32_t p : points)
        if (p < complex->points.size()) line.points.push_back(complex->points[p]);
      line.color = {0.45, 0.02, 0.02};
      scene.polylines.push_back(std::move(line));
    }
  }
  return scene;
}

dim3::Box3 tet_mesh_bounds(const dim3::TetMesh& mesh) {
  dim3::Box3 b{mesh.vertices.front(), mesh.vertices.front()};
  for (const dim3::Point3& p : mesh.vertices)
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = std::min(b.lo[d], p[d]);
      b.hi[d] = std::max(b.hi[d], p[d]);
    }
  return b;
}

CutPlane cut_across(const dim3::Box3& bounds, int axis, double fraction, bool keep_upper) {
  CutPlane plane;
  plane.normal = {0, 0, 0};
  axis = std::clamp(axis, 0, 2);
  const double position = bounds.lo[axis] + fraction * (bounds.hi[axis] - bounds.lo[axis]);
  plane.normal[axis] = keep_upper ? -1.0 : 1.0;
  plane.offset = keep_upper ? -position : position;
  return plane;
}

View view_facing_cut(int axis, bool keep_upper, int up) {
  // fit_camera's frame: azimuth 0 looks from +front ((up + 1) % 3), 90 from +side ((up + 2) % 3).
  up = ((up % 3) + 3) % 3;
  axis = ((axis % 3) + 3) % 3;
  if (axis == up) return View{30, keep_upper ? -45.0 : 50.0, up};
  const double azimuth = axis == (up + 1) % 3 ? 25.0 : 65.0;
  return View{keep_upper ? azimuth + 180.0 : azimuth, 25.0, up};
}

Scene tet_mesh_scene(const dim3::TetMesh& mesh, const TetStyle& style) {
  Scene scene;
  const std::size_t tets = mesh.tets.size();
  auto reference = [&](std::size_t t) { return t < mesh.reference.size() ? mesh.reference[t] : 0; };
  auto centroid = [&](std::size_t t) {
    Vec3 c{0, 0, 0};
    for (int v : mesh.tets[t])
      for (int d = 0; d < 3; ++d) c[d] += mesh.vertices[v][d] / 4.0;
    return c;
  };
  // Kept tets.
  std::vector<char> kept(tets, 0);
  for (std::size_t t = 0; t < tets; ++t) {
    const auto& tet = mesh.tets[t];
    bool valid = true;
    for (int v : tet) valid = valid && v >= 0 && static_cast<std::size_t>(v) < mesh.vertices.size();
    if (!valid) continue;
    std::array<int, 4> sorted = tet;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) continue;
    if (style.cut) {
      const Vec3 c = centroid(t);
      const Vec3& n = style.cut->normal;
      if (n[0] * c[0] + n[1] * c[1] + n[2] * c[2] > style.cut->offset) continue;
    }
    kept[t] = 1;
  }
  // Colour group of each tet.
  auto group = [&](std::size_t t) -> long {
    switch (style.color_by) {
      case TetStyle::ColorBy::Reference: return reference(t);
      case TetStyle::ColorBy::Flag: return t < style.flag.size() && style.flag[t] != 0 ? 1 : 0;
      default: return 0;
    }
  };
  // Explode offsets per reference.
  std::map<int, Vec3> offset;
  if (style.explode != 0.0) {
    std::map<int, std::pair<Vec3, double>> sums;
    Vec3 all{0, 0, 0};
    double count = 0;
    for (std::size_t t = 0; t < tets; ++t) {
      if (!kept[t]) continue;
      const Vec3 c = centroid(t);
      auto& [s, n] = sums[reference(t)];
      for (int d = 0; d < 3; ++d) {
        s[d] += c[d];
        all[d] += c[d];
      }
      n += 1;
      count += 1;
    }
    for (auto& [ref, sn] : sums)
      for (int d = 0; d < 3; ++d) offset[ref][d] = style.explode * (sn.first[d] / sn.second - all[d] / count);
  }
  // Faces of kept tets, each with its sorted key; a face is drawn when exactly one kept tet has it.
  static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  struct Face {
    std::array<int, 3> key;
    std::uint32_t tet;
    std::uint8_t local;
  };
  std::vector<Face> faces;
  faces.reserve(4 * tets);
  for (std::size_t t = 0; t < tets; ++t) {
    if (!kept[t]) continue;
    for (std::uint8_t f = 0; f < 4; ++f) {
      std::array<int, 3> key{mesh.tets[t][kFace[f][0]], mesh.tets[t][kFace[f][1]], mesh.tets[t][kFace[f][2]]};
      std::sort(key.begin(), key.end());
      faces.push_back({key, static_cast<std::uint32_t>(t), f});
    }
  }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) {
    return a.key != b.key ? a.key < b.key : a.tet < b.tet;
  });
  // One part per group; vertices of a part are the mesh vertices its faces use (moved by the
  // explode offset of the face's reference, so a vertex shared by two references is split).
  struct Builder {
    Part part;
    std::unordered_map<long long, std::uint32_t> index;  // (vertex, reference) -> part vertex
  };
  std::map<long, Builder> builders;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i == 1) {
      const std::size_t t = faces[i].tet;
      const int ref = reference(t);
      Builder& b = builders[group(t)];
      std::array<std::uint32_t, 3> tri{};
      for (int k = 0; k < 3; ++k) {
        const int v = mesh.tets[t][kFace[faces[i].local][k]];
        const long long key = static_cast<long long>(v) * 1048576LL + (style.explode != 0.0 ? ref & 0xFFFFF : 0);
        auto [it, inserted] = b.index.emplace(key, static_cast<std::uint32_t>(b.part.vertices.size()));
        if (inserted) {
          Vec3 p = mesh.vertices[v];
          if (style.explode != 0.0) {
            const Vec3& o = offset[ref];
            for (int d = 0; d < 3; ++d) p[d] += o[d];
          }
          b.part.vertices.push_back(p);
          if (style.color_by == TetStyle::ColorBy::Scalar)
            b.part.vertex_scalar.push_back(static_cast<std::size_t>(v) < style.vertex_scalar.size()
                                               ? style.vertex_scalar[v]
                                               : 0.0);
        }
        tri[k] = it->second;
      }
      b.part.triangles.push_back(tri);
    }
    i = j;
  }
  for (auto& [g, b] : builders) {
    Part& part = b.part;
    part.edges = style.edges;
    switch (style.color_by) {
      case TetStyle::ColorBy::Reference:
        part.name = "copies of graph node " + std::to_string(g);
        part.color = palette(static_cast<std::size_t>(std::max(0L, g)));
        break;
      case TetStyle::ColorBy::Flag:
        part.name = g ? "highlighted tets" : "other tets";
        part.color = g ? style.highlight : style.color;
        break;
      case TetStyle::ColorBy::Scalar:
        part.name = "scalar field";
        break;
      default:
        part.name = "tets";
        part.color = style.color;
    }
    scene.parts.push_back(std::move(part));
  }
  if (style.color_by == TetStyle::ColorBy::Scalar) {
    // The range of the values there are (a vertex without one, NaN or infinite, is drawn grey).
    std::optional<ScalarRange> range;
    for (double v : style.vertex_scalar)
      if (std::isfinite(v)) range = range ? ScalarRange{std::min(range->lo, v), std::max(range->hi, v)} : ScalarRange{v, v};
    scene.scalar_range = range;
  }
  return scene;
}

dim3::Surface embedded_surface(const dim3::Surface& surface, const dim3::TetMesh& mesh,
                               const std::vector<dim3::EmbeddedVertex3>& embedding) {
  dim3::Surface out = surface;
  for (std::size_t v = 0; v < out.vertices.size() && v < embedding.size(); ++v) {
    const dim3::EmbeddedVertex3& e = embedding[v];
    if (e.element < 0 || static_cast<std::size_t>(e.element) >= mesh.tets.size()) continue;
    dim3::Point3 p{0, 0, 0};
    for (int k = 0; k < 4; ++k)
      for (int d = 0; d < 3; ++d) p[d] += e.weights[k] * mesh.vertices[mesh.tets[e.element][k]][d];
    out.vertices[v] = p;
  }
  return out;
}

}  // namespace imm::render
