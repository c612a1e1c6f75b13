// 2D meshing of an immersion (paper §7 with d = 2): local regions of the background triangles
// (dim2/virtual_triangles.cpp) become per-node atoms, glued through the immersion graph, and the
// dimension-generic driver (core/unglue.h) duplicates and connects the triangles.
// CGAL-free: the exact work happens in background.cpp and virtual_triangles.cpp.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "core/unglue.h"
#include "dim2/mesh2.h"
#include "dim2/mesh2_detail.h"

namespace imm::dim2 {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

namespace detail {

void assemble(const Complex2& complex, const Immersion& immersion, const Background& background,
              const LocalRegions& local, bool record_contents, MeshResult& result) {
  const CellComplex<2>& cc = complex.complex;
  const NodeLayout& layout = immersion.layout;
  // 3. Atoms, fusions and adjacencies for the driver.
  std::vector<std::array<std::int32_t, 3>> elements;
  elements.reserve(background.triangles.size());
  for (const auto& t : background.triangles) elements.push_back({t[0], t[1], t[2]});
  AtomExpansion<2> expansion(cc, immersion, local.first, local.region, std::move(elements));
  local.glue(expansion);
  const UnglueInput<2>& input = expansion.input();
  const auto atom_of = [&](std::uint32_t lr, NodeId node) { return expansion.atom(lr, node); };

  // 4. Duplicate and connect.
  const UnglueResult<2> unglued = unglue<2>(input);
  TriangleMesh& mesh = result.mesh;
  mesh.vertices.reserve(unglued.vertex_source.size());
  for (std::int32_t v : unglued.vertex_source) mesh.vertices.push_back(background.vertices[v]);
  mesh.triangles.reserve(unglued.copies.size());
  mesh.reference.reserve(unglued.copies.size());
  result.background_triangle.reserve(unglued.copies.size());
  result.stats.copies_per_cell.assign(cc.cell_count(), 0);
  for (std::size_t c = 0; c < unglued.copies.size(); ++c) {
    const auto& copy = unglued.copies[c];
    mesh.triangles.push_back({copy[0], copy[1], copy[2]});
    mesh.reference.push_back(unglued.copy_node[c].value());
    result.background_triangle.push_back(static_cast<int>(unglued.copy_element[c]));
    ++result.stats.copies_per_cell[layout.cell(unglued.copy_node[c]).index()];
  }
  result.stats.output_triangles = mesh.triangles.size();
  result.stats.output_vertices = mesh.vertices.size();

  // 5. Embedding: each input vertex goes into the copy holding the owner of its patch, on the
  // patch's inner side (the owner's copy of the patch is the boundary of the immersed manifold).
  result.embedding.resize(local.vertices.size());
  for (std::size_t v = 0; v < local.vertices.size(); ++v) {
    const auto& location = local.vertices[v];
    if (location.local_region == LocalRegions::kNone) continue;
    const std::uint32_t atom = atom_of(location.local_region, immersion.owner[location.patch]);
    result.embedding[v] = {static_cast<int>(unglued.atom_copy[atom]), location.weights};
  }

  if (record_contents) {
    result.contents.resize(unglued.copies.size());
    for (std::uint32_t a = 0; a < input.atoms.size(); ++a) {
      const UnglueAtom& atom = input.atoms[a];
      const std::uint32_t lr = local.first[atom.element] + static_cast<std::uint32_t>(atom.local_region);
      result.contents[unglued.atom_copy[a]].atoms.push_back(
          {atom.node, local.region[lr], atom.local_region});
    }
    for (const auto& piece : local.inner_pieces) {
      const std::uint32_t atom = atom_of(piece.local_region, immersion.owner[piece.patch]);
      result.contents[unglued.atom_copy[atom]].owned_segments.push_back(piece.input_segment);
    }
    for (CopyContent& content : result.contents) {
      auto& s = content.owned_segments;
      std::sort(s.begin(), s.end());
      s.erase(std::unique(s.begin(), s.end()), s.end());
    }
  }
}

}  // namespace detail

MeshResult mesh_immersion(const Complex2& complex, const Immersion& immersion,
                          const MeshOptions& options) {
  MeshResult result;
  const auto log = [&](const std::string& message) {
    if (options.progress) options.progress(message);
  };

  // 1. Background.
  auto start = std::chrono::steady_clock::now();
  const detail::Background background = detail::make_background(complex, options, result.report);
  result.stats.seconds_background = seconds_since(start);
  if (!result.report.ok()) return result;
  result.stats.background_triangles = background.triangles.size();
  result.background.vertices = background.vertices;
  result.background.triangles = background.triangles;
  log("meshing: " + std::to_string(background.triangles.size()) + " background triangles");

  // 2. Local regions (virtual triangles).
  start = std::chrono::steady_clock::now();
  const detail::LocalRegions local =
      options.method == MeshMethod::Csg
          ? detail::compute_local_regions_csg(complex, background, options.record_contents, result.report)
          : detail::compute_local_regions(complex, background, options.record_contents, result.report);
  result.stats.seconds_virtual = seconds_since(start);
  result.stats.cut_triangles = local.cut_elements;
  if (!result.report.ok()) return result;
  log("meshing: " + std::to_string(local.cut_elements) + " cut triangles");

  // 3.-5. Atoms, duplicate and connect, embedding.
  start = std::chrono::steady_clock::now();
  detail::assemble(complex, immersion, background, local, options.record_contents, result);
  result.stats.seconds_assembly = seconds_since(start);
  // DESIGN §4.6: the .emb weights reproduce every vertex within 1e-9 of the diagonal. Measured
  // in the doubles a reader has: a background far larger than the input loses the digits.
  {
    double worst = 0.0;
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    // The .emb is in file order; complex.curves holds a clockwise input reversed (vertex 0 kept,
    // the rest in reverse), so file vertex i of a curve of m is its entry (m - i) % m.
    std::size_t v = 0;
    for (const Curve& curve : complex.curves.curves) {
      const std::size_t m = curve.vertices.size();
      for (std::size_t i = 0; i < m; ++i) {
        const Point& p = curve.vertices[complex.reversed ? (m - i) % m : i];
        lo[0] = std::min(lo[0], p.x), lo[1] = std::min(lo[1], p.y);
        hi[0] = std::max(hi[0], p.x), hi[1] = std::max(hi[1], p.y);
        if (v < result.embedding.size() && result.embedding[v].element >= 0) {
          const EmbeddedVertex& e = result.embedding[v];
          const auto& t = result.mesh.triangles[static_cast<std::size_t>(e.element)];
          double x = 0.0, y = 0.0;
          for (int k = 0; k < 3; ++k) {
            x += e.weights[k] * result.mesh.vertices[static_cast<std::size_t>(t[k])].x;
            y += e.weights[k] * result.mesh.vertices[static_cast<std::size_t>(t[k])].y;
          }
          worst = std::max(worst, std::hypot(x - p.x, y - p.y));
        }
        ++v;
      }
    }
    const double size = v > 0 ? std::hypot(hi[0] - lo[0], hi[1] - lo[1]) : 0.0;
    result.stats.embedding_error = size > 0 ? worst / size : worst;
  }
  log("meshing: " + std::to_string(result.mesh.triangles.size()) + " output triangles");
  return result;
}

namespace {

std::string node_colour(int node) {
  // Golden-ratio hues: neighbouring node ids get well separated colours.
  const double hue = std::fmod(0.13 + 0.6180339887498949 * node, 1.0) * 6.0;
  const double x = 1.0 - std::abs(std::fmod(hue, 2.0) - 1.0);
  double rgb[3] = {0, 0, 0};
  const int sector = static_cast<int>(hue);
  const double table[6][3] = {{1, x, 0}, {x, 1, 0}, {0, 1, x}, {0, x, 1}, {x, 0, 1}, {1, 0, x}};
  for (int k = 0; k < 3; ++k) rgb[k] = 0.25 + 0.6 * table[sector % 6][k];
  std::ostringstream os;
  os << '#' << std::hex << std::setfill('0');
  for (double c : rgb) os << std::setw(2) << static_cast<int>(std::lround(c * 255.0));
  return os.str();
}

std::vector<int> sheet_layers(const Immersion& immersion) {
  const NodeLayout& layout = immersion.layout;
  const std::size_t n = layout.node_count();
  std::vector<std::vector<NodeId>> neighbours(n);
  for (const ImmersionEdge& e : immersion.edges) {
    neighbours[e.inner.index()].push_back(e.outer);
    neighbours[e.outer.index()].push_back(e.inner);
  }
  std::vector<int> layer(n, -1);
  const auto free_layer = [&](NodeId node, int wanted) {
    const CellId cell = layout.cell(node);
    for (;; ++wanted) {
      bool taken = false;
      for (NodeId other = layout.first(cell); layout.cell(other) == cell; other = NodeId(other.value() + 1)) {
        taken = taken || layer[other.index()] == wanted;
        if (other.index() + 1 == n) break;
      }
      if (!taken) return wanted;
    }
  };
  for (NodeId start : ids<NodeId>(n)) {
    if (layer[start.index()] >= 0) continue;
    layer[start.index()] = free_layer(start, 0);
    std::vector<NodeId> queue = {start};
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const NodeId node = queue[head];
      for (NodeId next : neighbours[node.index()]) {
        if (layer[next.index()] >= 0) continue;
        layer[next.index()] = free_layer(next, layer[node.index()]);
        queue.push_back(next);
      }
    }
  }
  return layer;
}

}  // namespace

std::string format_mesh_svg(const Complex2& complex, const Immersion& immersion,
                            const MeshResult& result) {
  const TriangleMesh& mesh = result.mesh;
  const NodeLayout& layout = immersion.layout;
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin;
  double xmax = -xmin, ymax = -xmin;
  const auto grow = [&](const Point& p) {
    xmin = std::min(xmin, p.x);
    ymin = std::min(ymin, p.y);
    xmax = std::max(xmax, p.x);
    ymax = std::max(ymax, p.y);
  };
  for (const Point& p : mesh.vertices) grow(p);
  for (const Curve& c : complex.curves.curves)
    for (const Point& p : c.vertices) grow(p);
  if (!(xmin <= xmax)) return "<svg xmlns=\"http://www.w3.org/2000/svg\"/>\n";
  // Layers: a breadth-first walk over the immersion graph keeps a node on its neighbour's layer
  // unless another copy of its cell is there already. Each layer is drawn in its own panel, side
  // by side, over a faint copy of the input, so the sheets of the immersion are seen apart while
  // glued copies stay together; two immersions of one curve give different layers.
  const std::vector<int> layer = sheet_layers(immersion);
  int layers = 1;
  for (int ref : mesh.reference) layers = std::max(layers, layer[static_cast<std::size_t>(ref)] + 1);
  const double panel = 1.08 * (xmax - xmin);
  const double width = 900.0;
  const double pad = 10.0;
  const double title = 16.0;
  const double scale = (width - 2 * pad) / std::max(panel * layers, 1e-300);
  const double drawing_height = (ymax - ymin) * scale + 2 * pad + title;
  const double height = drawing_height + 14.0 * static_cast<double>(layout.node_count()) + pad;
  const auto sx = [&](double x) { return (x - xmin) * scale + pad; };
  const auto sy = [&](double y) { return (ymax - y) * scale + pad + title; };

  std::ostringstream os;
  os << std::setprecision(6);
  os << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
     << "\" viewBox=\"0 0 " << width << ' ' << height << "\">\n";
  os << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (int k = 0; k < layers; ++k) {
    const double shift = k * panel;
    os << "<text x=\"" << sx(xmin + shift) << "\" y=\"" << pad + 10.0
       << "\" font-family=\"sans-serif\" font-size=\"12\">layer " << k << "</text>\n";
    for (const Curve& c : complex.curves.curves) {
      os << "<polygon fill=\"none\" stroke=\"#999999\" stroke-width=\"0.8\" points=\"";
      for (const Point& p : c.vertices) os << sx(p.x + shift) << ',' << sy(p.y) << ' ';
      os << "\"/>\n";
    }
  }
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const int node = mesh.reference[i];
    const double shift = layer[static_cast<std::size_t>(node)] * panel;
    const std::string colour = node_colour(node);
    os << "<polygon fill=\"" << colour << "\" fill-opacity=\"0.55\" stroke=\"" << colour
       << "\" stroke-width=\"0.6\" points=\"";
    for (int v : mesh.triangles[i]) {
      const Point& p = mesh.vertices[v];
      os << sx(p.x + shift) << ',' << sy(p.y) << ' ';
    }
    os << "\"/>\n";
  }
  for (NodeId n : ids<NodeId>(layout.node_count())) {
    os << "<text x=\"" << pad << "\" y=\"" << drawing_height + 14.0 * (n.value() + 1)
       << "\" font-family=\"sans-serif\" font-size=\"12\" fill=\"" << node_colour(n.value())
       << "\">node " << n << " (cell " << layout.cell(n) << ", copy " << layout.copy(n)
       << ", layer " << layer[n.index()] << ")</text>\n";
  }
  os << "</svg>\n";
  return os.str();
}

}  // namespace imm::dim2
