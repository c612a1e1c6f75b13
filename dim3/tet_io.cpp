// Readers (Vega .veg, Medit .mesh, TetGen .node/.ele) and writers (.mesh, .vtu, .veg) of
// tetrahedral meshes (dim3/tet_mesh.h): the background meshes a user may pass to the meshing step
// and the unglued output.
//
// Small hand-written parsers, like dim3/surface_io.cpp and sharing its tokenizer and number
// parsing (dim3/text_io.h): every error names the file and the line, numbers are parsed with
// std::from_chars (correctly rounded) so that a written mesh reads back bit for bit. Each format is first read into a raw mesh (indices 0-based but unchecked); the
// common finish checks indices and coordinates and orients every tet with the exact predicate
// (CGAL Epick's orientation is exact on doubles), so that downstream code can rely on
// det(v1 - v0, v2 - v0, v3 - v0) > 0 without ever looking at a tolerance.
//
// A parse error (Unreadable) stops the reading of that file: later lines of a broken file would
// only produce follow-up errors. Tets that are defective (bad index, non-finite or zero volume)
// are left out of `mesh.tets`; the defect names them by their file order.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string_view>

#include "core/medit.h"
#include "dim3/tet_mesh.h"
#include "dim3/text_io.h"

namespace imm::dim3 {
namespace {

using namespace text;  // the helpers shared with the other dim3 reader

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

constexpr const char* kStage = "background";

/// Defects with at most kMaxDefectsPerKind listed per kind; the rest go to report.unlisted.
class Defects {
 public:
  void add(DefectKind kind, std::string message, std::vector<long> tets = {},
           std::vector<long> vertices = {}, std::vector<std::vector<double>> points = {}) {
    std::size_t& n = count_[kind];
    if (++n > kMaxDefectsPerKind) {
      ++report_.unlisted;
      return;
    }
    report_.add(Defect{kind, kStage, std::move(message), std::move(tets), std::move(vertices),
                       std::move(points)});
  }
  [[nodiscard]] bool any() const { return !count_.empty(); }
  [[nodiscard]] bool any(DefectKind kind) const { return count_.count(kind) > 0; }
  ValidationReport take() { return std::move(report_); }

 private:
  ValidationReport report_;
  std::map<DefectKind, std::size_t> count_;
};

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

/// A mesh as written in the file: indices made 0-based but not checked yet.
struct RawMesh {
  std::vector<Point3> vertices;
  std::vector<std::uint64_t> vertex_line;
  std::vector<std::array<long long, 4>> tets;
  std::vector<int> reference;
  std::vector<std::uint64_t> tet_line;
  std::string vertex_file;  ///< for messages (TetGen: the .node file)
  std::string tet_file;     ///< (TetGen: the .ele file)
  int index_base = 1;       ///< how the file numbers vertices, for messages
};

/// Reads `x y z` after an index token, on its line.
bool read_point(Tokens& tokens, Point3& p) {
  for (int k = 0; k < 3; ++k) {
    const auto token = tokens.next_on_line();
    const auto value = token ? parse_double(*token) : std::nullopt;
    if (!value) return false;
    p[k] = *value;
  }
  return true;
}

void truncated(Defects& defects, const std::string& file, const char* what, long long i,
               long long n, std::uint64_t header_line) {
  defects.add(DefectKind::Unreadable, truncated_message(file, what, i, n, header_line));
}

/// Reads a vertex section of Vega or TetGen (.node): the header 'N 3 ...' (the rest of its line is
/// skipped), then N lines 'index x y z ...'. The first index numbers the vertices from 0 or 1
/// (raw.index_base); the others must follow consecutively. `bad_header` is the message for a
/// header that is not 'N 3', `numbering` says in a message how the format numbers vertices.
/// @return false when it reported an Unreadable defect (the reading stops)
bool read_vertex_section(std::string_view text, Tokens& tokens, const std::string& file,
                         const char* bad_header, const char* numbering, RawMesh& raw,
                         Defects& defects) {
  const auto n = parse_count(tokens.next());
  const std::uint64_t header_line = tokens.line();
  const auto dimension = tokens.next_on_line();
  if (!n || !dimension || parse_integer(*dimension) != 3) {
    defects.add(DefectKind::Unreadable, at(file, header_line) + bad_header);
    return false;
  }
  tokens.skip_line();
  reserve_records(raw.vertices, *n, text, 8);
  for (long long i = 0; i < *n; ++i) {
    const auto index_token = tokens.next();
    if (!index_token) {
      truncated(defects, file, "vertices", i, *n, header_line);
      return false;
    }
    const std::uint64_t line = tokens.line();
    const auto index = parse_integer(*index_token);
    if (i == 0 && index && (*index == 0 || *index == 1)) raw.index_base = static_cast<int>(*index);
    Point3 p{};
    if (!index || *index != i + raw.index_base || !read_point(tokens, p)) {
      defects.add(DefectKind::Unreadable,
                  at(file, line) + "expected vertex " + std::to_string(i + raw.index_base) +
                      " as 'index x y z' (vertices numbered consecutively from " + numbering +
                      "), found " + quoted(*index_token) + " ...");
      return false;
    }
    raw.vertices.push_back(p);
    raw.vertex_line.push_back(line);
    tokens.skip_line();  // TetGen: attributes, boundary marker
  }
  return true;
}

/// Reads the `m` tet lines of Vega or TetGen (.ele) after their header on line `header_line`:
/// 'index v0 v1 ... [attributes]' with `corners` vertex numbers (4, or 10 for a quadratic tet
/// whose corners come first), kept as numbered in the file. When `attributes` > 0, the first one
/// (TetGen's region number) becomes the reference if it is an integer; otherwise it is 0.
/// `record` is the expected line for a message ("'index v0 v1 v2 v3'").
/// @return false when it reported an Unreadable defect (the reading stops)
bool read_tet_records(std::string_view text, Tokens& tokens, const std::string& file, long long m,
                      std::uint64_t header_line, long long corners, long long attributes,
                      const char* record, RawMesh& raw, Defects& defects) {
  reserve_records(raw.tets, m, text, 10);
  for (long long e = 0; e < m; ++e) {
    const auto index_token = tokens.next();
    if (!index_token) {
      truncated(defects, file, "tets", e, m, header_line);
      return false;
    }
    const std::uint64_t line = tokens.line();
    std::array<long long, 4> tet{};
    bool ok = parse_integer(*index_token).has_value();
    for (long long k = 0; k < corners && ok; ++k) {
      const auto t = tokens.next_on_line();
      const auto v = t ? parse_integer(*t) : std::nullopt;
      ok = v.has_value();
      if (ok && k < 4) tet[k] = *v;
    }
    if (!ok) {
      defects.add(DefectKind::Unreadable, at(file, line) + "expected tet " + std::to_string(e) +
                                              " as " + record + " (integers)");
      return false;
    }
    int reference = 0;
    if (attributes > 0) {
      if (const auto t = tokens.next_on_line()) {
        if (const auto value = parse_double(*t); value && std::isfinite(*value) &&
                                                 *value == std::trunc(*value) &&
                                                 std::abs(*value) < 2e9)
          reference = static_cast<int>(*value);
      }
    }
    raw.tets.push_back(tet);
    raw.reference.push_back(reference);
    raw.tet_line.push_back(line);
    tokens.skip_line();
  }
  return true;
}

/// Makes the tets' vertex numbers 0-based, once the vertices have told how the file numbers them.
void to_zero_based(RawMesh& raw) {
  for (auto& tet : raw.tets) {
    for (long long& v : tet) v -= raw.index_base;
  }
}

// ---- Vega .veg ---------------------------------------------------------------------------------

void parse_veg(std::string_view text, RawMesh& raw, Defects& defects) {
  const std::string& file = raw.vertex_file;
  Tokens tokens(text, {TokenRules::Hash::CommentAnywhere, /*comma_separates=*/true});
  bool saw_vertices = false;
  bool saw_elements = false;
  std::optional<std::string_view> token = tokens.next();
  while (token) {
    if (token->front() != '*') {
      defects.add(DefectKind::Unreadable,
                  at(file, tokens.line()) +
                      "expected a section ('*VERTICES', '*ELEMENTS', ...), found " +
                      quoted(*token));
      return;
    }
    const std::string keyword = upper(*token);
    // Each of *VERTICES and *ELEMENTS once: a second one would replace or extend the first.
    auto first_section = [&](bool& seen) {
      if (seen) {
        defects.add(DefectKind::Unreadable,
                    at(file, tokens.line()) + "a second '" + keyword + "' section");
        return false;
      }
      seen = true;
      return true;
    };
    if (keyword == "*VERTICES") {
      if (!first_section(saw_vertices)) return;
      tokens.skip_line();
      if (!read_vertex_section(text, tokens, file,
                               "expected the vertex header 'N 3 0 0' (N vertices in 3D)", "1", raw,
                               defects))
        return;
      token = tokens.next();
    } else if (keyword == "*ELEMENTS") {
      if (!first_section(saw_elements)) return;
      tokens.skip_line();
      const auto type = tokens.next();
      if (!type || upper(*type) != "TET") {
        defects.add(DefectKind::Unreadable,
                    at(file, tokens.line()) + "expected the element type 'TET', found " +
                        quoted(type.value_or("end of file")) + " (only tetrahedra are supported)");
        return;
      }
      tokens.skip_line();
      const auto m = parse_count(tokens.next());
      const std::uint64_t header_line = tokens.line();
      const auto per_element = tokens.next_on_line();
      if (!m || !per_element || parse_integer(*per_element) != 4) {
        defects.add(DefectKind::Unreadable,
                    at(file, header_line) + "expected the element header 'M 4 0' (M tets)");
        return;
      }
      tokens.skip_line();
      if (!read_tet_records(text, tokens, file, *m, header_line, /*corners=*/4, /*attributes=*/0,
                            "'index v0 v1 v2 v3'", raw, defects))
        return;
      token = tokens.next();
    } else if (keyword == "*INCLUDE") {
      defects.add(
          DefectKind::Unreadable,
          at(file, tokens.line()) + "'*INCLUDE' is not supported: inline the included file");
      return;
    } else {
      // *MATERIAL, *REGION, *SET, *CONSTRAINTS, ...: nothing a background mesh needs.
      do {
        tokens.skip_line();
        token = tokens.next();
      } while (token && token->front() != '*');
    }
  }
  // The element section refers to the vertices' numbering; Vega counts from 1.
  to_zero_based(raw);
  if (!saw_vertices || !saw_elements) {
    defects.add(
        DefectKind::Empty,
        file + " has no '" + std::string(saw_vertices ? "*ELEMENTS" : "*VERTICES") + "' section");
  }
}

// ---- Medit .mesh (core/medit.h) ---------------------------------------------------------------

void parse_medit(std::string_view text, RawMesh& raw, Defects& defects) {
  MeditMesh<3> medit;
  const std::string error = imm::parse_medit<3>(text, raw.vertex_file, medit);
  raw.vertices = std::move(medit.vertices);
  raw.vertex_line = std::move(medit.vertex_line);
  raw.tets = std::move(medit.elements);
  raw.reference = std::move(medit.reference);
  raw.tet_line = std::move(medit.element_line);
  if (!error.empty()) defects.add(DefectKind::Unreadable, error);
}

// ---- TetGen .node / .ele -----------------------------------------------------------------------

void parse_node(std::string_view text, RawMesh& raw, Defects& defects) {
  Tokens tokens(text, {TokenRules::Hash::CommentAnywhere});
  read_vertex_section(text, tokens, raw.vertex_file,
                      "expected the header 'N 3 attributes boundary_marker'", "0 or 1", raw,
                      defects);
}

void parse_ele(std::string_view text, RawMesh& raw, Defects& defects) {
  const std::string& file = raw.tet_file;
  Tokens tokens(text, {TokenRules::Hash::CommentAnywhere});
  const auto m = parse_count(tokens.next());
  const std::uint64_t header_line = tokens.line();
  const auto per_tet_token = tokens.next_on_line();
  // Nodes per tet: 4, or 10 for a quadratic tet (its corners come first).
  const long long corners = per_tet_token ? parse_integer(*per_tet_token).value_or(0) : 0;
  const auto attributes_token = tokens.next_on_line();
  const auto attributes =
      attributes_token ? parse_integer(*attributes_token) : std::optional<long long>(0);
  if (!m || (corners != 4 && corners != 10) || !attributes || *attributes < 0) {
    defects.add(DefectKind::Unreadable,
                at(file, header_line) + "expected the header 'M 4 attributes' (or 'M 10 ...')");
    return;
  }
  tokens.skip_line();
  if (read_tet_records(text, tokens, file, *m, header_line, corners, *attributes,
                       "'index v0 v1 v2 v3 [attributes]'", raw, defects))
    to_zero_based(raw);  // numbered like the .node file
}

// ---- common ------------------------------------------------------------------------------------

std::optional<std::string> read_file(const std::string& path, Defects& defects) {
  std::string error;
  auto data = text::read_file(path, error);
  if (!data) defects.add(DefectKind::Unreadable, std::move(error));
  return data;
}

/// Index range, non-finite coordinates, exact orientation: the raw mesh becomes a TetMesh whose
/// tets are all positively oriented.
void finish(RawMesh& raw, TetReadResult& result, Defects& defects) {
  TetMesh& mesh = result.mesh;
  mesh.vertices = std::move(raw.vertices);
  const auto n = static_cast<long long>(mesh.vertices.size());
  const std::string base_note =
      raw.index_base == 1 ? " (0-based ids; the file numbers vertices from 1)" : "";
  for (long long v = 0; v < n; ++v) {
    const Point3& p = mesh.vertices[v];
    if (is_finite(p)) continue;
    defects.add(DefectKind::NonFinite,
                at(raw.vertex_file, raw.vertex_line[v]) + "vertex " + std::to_string(v) +
                    " has a non-finite coordinate " + format_point(p) + base_note,
                {}, {static_cast<long>(v)}, {coordinates(p)});
  }
  mesh.tets.reserve(raw.tets.size());
  mesh.reference.reserve(raw.tets.size());
  for (std::size_t t = 0; t < raw.tets.size(); ++t) {
    const auto& tet = raw.tets[t];
    const std::string where = at(raw.tet_file, raw.tet_line[t]) + "tet " + std::to_string(t);
    bool in_range = true;
    for (long long v : tet) {
      if (v >= 0 && v < n) continue;
      defects.add(DefectKind::OutOfRange,
                  where + " refers to vertex " + std::to_string(v + raw.index_base) +
                      " (as numbered in the file), but the file has " + std::to_string(n) +
                      " vertices, numbered " + std::to_string(raw.index_base) + ".." +
                      std::to_string(n - 1 + raw.index_base),
                  {static_cast<long>(t)}, {}, {});
      in_range = false;
    }
    if (!in_range) continue;
    const Point3* p[4];
    bool finite = true;
    for (int k = 0; k < 4; ++k) {
      p[k] = &mesh.vertices[tet[k]];
      finite = finite && is_finite(*p[k]);
    }
    if (!finite) continue;  // the vertex is reported above
    auto corners = [&] {
      std::string s;
      for (int k = 0; k < 4; ++k)
        s += (k ? ", " : "") + std::to_string(tet[k]) + " " + format_point(*p[k]);
      return s;
    };
    std::vector<long> vertex_ids(tet.begin(), tet.end());
    std::vector<std::vector<double>> points;
    for (int k = 0; k < 4; ++k) points.push_back(coordinates(*p[k]));
    auto point = [&](int k) { return Kernel::Point_3((*p[k])[0], (*p[k])[1], (*p[k])[2]); };
    const CGAL::Orientation orientation = CGAL::orientation(point(0), point(1), point(2), point(3));
    if (orientation == CGAL::COPLANAR) {
      const bool repeated = std::set<long long>(tet.begin(), tet.end()).size() < 4;
      defects.add(DefectKind::DegenerateFacet,
                  where + " has zero volume (" +
                      (repeated ? "a repeated vertex" : "four coplanar corners") + "): vertices " +
                      corners() + base_note,
                  {static_cast<long>(t)}, std::move(vertex_ids), std::move(points));
      continue;
    }
    Tet out{static_cast<int>(tet[0]), static_cast<int>(tet[1]), static_cast<int>(tet[2]),
            static_cast<int>(tet[3])};
    if (orientation == CGAL::NEGATIVE) {
      std::swap(out[2], out[3]);
      ++result.reoriented;
    }
    mesh.tets.push_back(out);
    mesh.reference.push_back(t < raw.reference.size() ? raw.reference[t] : 0);
  }
  if (!defects.any() && (mesh.vertices.empty() || raw.tets.empty())) {
    defects.add(DefectKind::Empty, raw.tet_file + " contains no tet (" + std::to_string(n) +
                                       " vertices, " + std::to_string(raw.tets.size()) + " tets)");
  }
}

}  // namespace

bool is_tet_mesh_extension(const std::string& path) {
  return has_extension(path, {".veg", ".mesh", ".node", ".ele"});
}

TetReadResult read_tet_mesh(const std::string& path) {
  TetReadResult result;
  Defects defects;
  const std::string ext = lower_extension(path);
  RawMesh raw;
  raw.vertex_file = raw.tet_file = path;
  if (!is_tet_mesh_extension(path)) {
    defects.add(DefectKind::Unreadable, "cannot read '" + path + "': unknown tet mesh extension '" +
                                            ext + "' (expected .veg, .mesh, .node or .ele)");
  } else if (ext == ".node" || ext == ".ele") {
    // TetGen: the vertices and the tets are two files with the same stem.
    const std::filesystem::path stem = std::filesystem::path(path).replace_extension();
    raw.vertex_file = stem.string() +
                      (ext == ".node" ? std::filesystem::path(path).extension().string() : ".node");
    raw.tet_file =
        stem.string() + (ext == ".ele" ? std::filesystem::path(path).extension().string() : ".ele");
    const auto node = read_file(raw.vertex_file, defects);
    const auto ele = read_file(raw.tet_file, defects);
    if (node && ele) {
      parse_node(*node, raw, defects);
      if (!defects.any()) parse_ele(*ele, raw, defects);
    }
  } else if (const auto text = read_file(path, defects)) {
    if (ext == ".veg") {
      raw.index_base = 1;
      parse_veg(*text, raw, defects);
    } else {
      parse_medit(*text, raw, defects);
    }
  }
  if (!defects.any()) finish(raw, result, defects);
  result.report = defects.take();
  return result;
}

std::string format_medit_3d(const TetMesh& mesh) {
  return format_medit<3>(mesh.vertices, mesh.tets, mesh.reference);
}

std::string format_vtu(const TetMesh& mesh) {
  constexpr int kVtkTetra = 10;
  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <UnstructuredGrid>\n"
      "    <Piece NumberOfPoints=\"" +
      std::to_string(mesh.vertices.size()) + "\" NumberOfCells=\"" +
      std::to_string(mesh.tets.size()) + "\">\n";
  out.reserve(mesh.vertices.size() * 64 + mesh.tets.size() * 48);
  out +=
      "      <Points>\n"
      "        <DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" "
      "format=\"ascii\">\n";
  for (const Point3& p : mesh.vertices) {
    out += "          " + format_xyz(p) + '\n';
  }
  out +=
      "        </DataArray>\n"
      "      </Points>\n"
      "      <Cells>\n"
      "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const Tet& tet : mesh.tets) {
    out += "          " + std::to_string(tet[0]) + ' ' + std::to_string(tet[1]) + ' ' +
           std::to_string(tet[2]) + ' ' + std::to_string(tet[3]) + '\n';
  }
  out +=
      "        </DataArray>\n"
      "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) out += ' ' + std::to_string(4 * (t + 1));
  out +=
      "\n        </DataArray>\n"
      "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) out += ' ' + std::to_string(kVtkTetra);
  out +=
      "\n        </DataArray>\n"
      "      </Cells>\n"
      "      <CellData Scalars=\"reference\">\n"
      "        <DataArray type=\"Int32\" Name=\"reference\" format=\"ascii\">\n";
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    out += ' ' + std::to_string(t < mesh.reference.size() ? mesh.reference[t] : 0);
  out +=
      "\n        </DataArray>\n"
      "      </CellData>\n"
      "    </Piece>\n"
      "  </UnstructuredGrid>\n"
      "</VTKFile>\n";
  return out;
}

std::string format_veg(const TetMesh& mesh) {
  std::string out = "# Vega mesh file.\n# " + std::to_string(mesh.vertices.size()) + " vertices, " +
                    std::to_string(mesh.tets.size()) + " elements\n\n*VERTICES\n" +
                    std::to_string(mesh.vertices.size()) + " 3 0 0\n";
  out.reserve(mesh.vertices.size() * 64 + mesh.tets.size() * 40);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Point3& p = mesh.vertices[v];
    out += std::to_string(v + 1) + ' ' + format_xyz(p) + '\n';
  }
  out += "\n*ELEMENTS\nTET\n" + std::to_string(mesh.tets.size()) + " 4 0\n";
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const Tet& tet = mesh.tets[t];
    out += std::to_string(t + 1);
    for (int v : tet) out += ' ' + std::to_string(v + 1ll);
    out += '\n';
  }
  return out;
}

}  // namespace imm::dim3
