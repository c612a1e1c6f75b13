// Readers (Vega .veg, Medit .mesh, TetGen .node/.ele, Gmsh .msh 4.1) and writers (.mesh, .vtu,
// .veg, .msh, .node/.ele) of
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
// Large Vega and TetGen sections are parsed on several threads, chunk by chunk of lines, with the
// same result and messages as one record at a time (read_records_in_parallel).
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
#include "core/parallel.h"
#include "core/union_find.h"
#include "dim3/background_limits.h"
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

/// Records of at least this many lines are read on several threads (read_records_in_parallel).
constexpr long long kParallelRecords = 1 << 12;

/// Reads the `n` one-line records that follow `tokens` (just past a section header) on `threads`
/// threads, as a loop calling read_one(tokens, i) for i = 0 .. n - 1 would: the rest of the text
/// is cut into chunks at line ends, the lines holding a token (the records: blank lines and
/// comment lines are skipped as Tokens::next skips them) are counted per chunk, and each chunk
/// then reads its records with a Tokens of its own, started at its first byte and line.
/// read_one(chunk_tokens, i) reads record i from its first token to its line's end (skip_line)
/// and returns false on anything unexpected. On success `tokens` goes on after record n - 1.
/// @return false when the text has fewer than n records or a record failed: nothing is reported
/// then, and the caller reads the section one record at a time, for its messages.
template <class ReadOne>
bool read_records_in_parallel(std::string_view text, Tokens& tokens, TokenRules rules, long long n,
                              unsigned threads, const ReadOne& read_one) {
  const std::size_t start = tokens.position();
  const std::uint64_t start_line = tokens.line();
  constexpr std::size_t kChunk = 1 << 16;  // bytes
  std::vector<std::size_t> begin{start};
  for (std::size_t at = start + kChunk; at < text.size(); at += kChunk) {
    const std::size_t end_of_line = text.find('\n', std::max(at, begin.back()));
    if (end_of_line == std::string_view::npos) break;
    if (end_of_line + 1 < text.size() && end_of_line + 1 > begin.back()) begin.push_back(end_of_line + 1);
    at = begin.back();
  }
  const std::size_t chunks = begin.size();
  begin.push_back(text.size());
  const auto separator = [&](char c) { return is_space(c) || (rules.comma_separates && c == ','); };
  // Per chunk: its records and line breaks; then, by prefix sums, its first record and line.
  std::vector<long long> records(chunks + 1, 0);
  std::vector<std::uint64_t> breaks(chunks + 1, 0);
  parallel_for(threads, chunks, [&](std::size_t c, unsigned) {
    long long r = 0;
    std::uint64_t b = 0;
    for (std::size_t at = begin[c]; at < begin[c + 1];) {
      std::size_t first = at;
      while (first < begin[c + 1] && text[first] != '\n' && separator(text[first])) ++first;
      if (first < begin[c + 1] && text[first] != '\n' && (text[first] != '#' || rules.hash == TokenRules::Hash::Text))
        ++r;
      const std::size_t end_of_line = text.find('\n', first);
      if (end_of_line == std::string_view::npos || end_of_line >= begin[c + 1]) break;
      ++b;
      at = end_of_line + 1;
    }
    records[c + 1] = r;
    breaks[c + 1] = b;
  }, /*grain=*/1);
  for (std::size_t c = 0; c < chunks; ++c) {
    records[c + 1] += records[c];
    breaks[c + 1] += breaks[c];
  }
  if (records[chunks] < n) return false;  // truncated: the message comes from the serial reading
  std::atomic<bool> ok{true};
  std::size_t end_position = start;
  std::uint64_t end_line = start_line;
  parallel_for(threads, chunks, [&](std::size_t c, unsigned) {
    if (records[c] >= n || !ok.load(std::memory_order_relaxed)) return;
    Tokens chunk(text, rules, begin[c], start_line + breaks[c], start_line + breaks[c]);
    const long long last = std::min(records[c + 1], n);
    for (long long i = records[c]; i < last; ++i) {
      if (!read_one(chunk, i)) {
        ok = false;
        return;
      }
    }
    if (last == n) {  // the chunk of the last record: where the caller's reading goes on
      end_position = chunk.position();
      end_line = chunk.line();
    }
  }, /*grain=*/1);
  if (!ok) return false;
  tokens = Tokens(text, rules, end_position, end_line, end_line);
  return true;
}

/// Vertex i's fields after its index token: the index (i + base) and 'x y z'.
bool read_vertex_fields(Tokens& tokens, std::string_view index_token, long long i, int base, Point3& p) {
  const auto index = parse_integer(index_token);
  return index && *index == i + base && read_point(tokens, p);
}

/// Reads a vertex section of Vega or TetGen (.node): the header 'N 3 ...' (the rest of its line is
/// skipped), then N lines 'index x y z ...'. The first index numbers the vertices from 0 or 1
/// (raw.index_base); the others must follow consecutively. `bad_header` is the message for a
/// header that is not 'N 3', `numbering` says in a message how the format numbers vertices.
/// Large sections are read on `threads` threads (read_records_in_parallel).
/// @return false when it reported an Unreadable defect (the reading stops)
bool read_vertex_section(std::string_view text, Tokens& tokens, TokenRules rules, const std::string& file,
                         const char* bad_header, const char* numbering, RawMesh& raw, unsigned threads,
                         Defects& defects) {
  const auto n = parse_count(tokens.next());
  const std::uint64_t header_line = tokens.line();
  const auto dimension = tokens.next_on_line();
  if (!n || !dimension || parse_integer(*dimension) != 3) {
    defects.add(DefectKind::Unreadable, at(file, header_line) + bad_header);
    return false;
  }
  tokens.skip_line();
  // The first index says how the file numbers its vertices.
  if (Tokens peek = tokens; const auto first = peek.next()) {
    const auto index = parse_integer(*first);
    if (index && (*index == 0 || *index == 1)) raw.index_base = static_cast<int>(*index);
  }
  if (*n >= kParallelRecords && resolve_threads(threads) > 1 &&
      static_cast<unsigned long long>(*n) <= text.size() / 8) {  // as reserve_records
    raw.vertices.resize(static_cast<std::size_t>(*n));
    raw.vertex_line.resize(static_cast<std::size_t>(*n));
    if (read_records_in_parallel(text, tokens, rules, *n, resolve_threads(threads), [&](Tokens& t, long long i) {
          const auto index_token = t.next();
          Point3 p{};
          if (!index_token || !read_vertex_fields(t, *index_token, i, raw.index_base, p)) return false;
          raw.vertices[static_cast<std::size_t>(i)] = p;
          raw.vertex_line[static_cast<std::size_t>(i)] = t.line();
          t.skip_line();  // TetGen: attributes, boundary marker
          return true;
        }))
      return true;
    raw.vertices.clear();
    raw.vertex_line.clear();
  }
  reserve_records(raw.vertices, *n, text, 8);
  for (long long i = 0; i < *n; ++i) {
    const auto index_token = tokens.next();
    if (!index_token) {
      truncated(defects, file, "vertices", i, *n, header_line);
      return false;
    }
    const std::uint64_t line = tokens.line();
    Point3 p{};
    if (!read_vertex_fields(tokens, *index_token, i, raw.index_base, p)) {
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

/// A tet's fields after its index token (an integer): `corners` vertex numbers, the first four
/// kept in `tet`, then, when `attributes` > 0, the first attribute as `reference` if it is an
/// integer (else 0). False when the index or a vertex number is not an integer.
bool read_tet_fields(Tokens& tokens, std::string_view index_token, long long corners, long long attributes,
                     std::array<long long, 4>& tet, int& reference) {
  bool ok = parse_integer(index_token).has_value();
  for (long long k = 0; k < corners && ok; ++k) {
    const auto t = tokens.next_on_line();
    const auto v = t ? parse_integer(*t) : std::nullopt;
    ok = v.has_value();
    if (ok && k < 4) tet[k] = *v;
  }
  if (!ok) return false;
  reference = 0;
  if (attributes > 0) {
    if (const auto t = tokens.next_on_line()) {
      if (const auto value = parse_double(*t);
          value && std::isfinite(*value) && *value == std::trunc(*value) && std::abs(*value) < 2e9)
        reference = static_cast<int>(*value);
    }
  }
  return true;
}

/// Reads the `m` tet lines of Vega or TetGen (.ele) after their header on line `header_line`:
/// 'index v0 v1 ... [attributes]' with `corners` vertex numbers (4, or 10 for a quadratic tet
/// whose corners come first), kept as numbered in the file. When `attributes` > 0, the first one
/// (TetGen's region number) becomes the reference if it is an integer; otherwise it is 0.
/// `record` is the expected line for a message ("'index v0 v1 v2 v3'"). Many tets are read on
/// `threads` threads (read_records_in_parallel).
/// @return false when it reported an Unreadable defect (the reading stops)
bool read_tet_records(std::string_view text, Tokens& tokens, TokenRules rules, const std::string& file,
                      long long m, std::uint64_t header_line, long long corners, long long attributes,
                      const char* record, RawMesh& raw, unsigned threads, Defects& defects) {
  if (static_cast<unsigned long long>(m) > kMaxBackgroundTets) {
    defects.add(DefectKind::Unreadable, at(file, header_line) + "the header announces " + std::to_string(m) +
                                            " tets, more than the " + std::to_string(kMaxBackgroundTets) +
                                            " a background mesh may have");
    return false;
  }
  if (m >= kParallelRecords && resolve_threads(threads) > 1 &&
      static_cast<unsigned long long>(m) <= text.size() / 10) {  // as reserve_records
    const auto size = static_cast<std::size_t>(m);
    raw.tets.resize(size);
    raw.reference.resize(size);
    raw.tet_line.resize(size);
    if (read_records_in_parallel(text, tokens, rules, m, resolve_threads(threads), [&](Tokens& t, long long e) {
          const auto index_token = t.next();
          const auto k = static_cast<std::size_t>(e);
          if (!index_token || !read_tet_fields(t, *index_token, corners, attributes, raw.tets[k], raw.reference[k]))
            return false;
          raw.tet_line[k] = t.line();
          t.skip_line();
          return true;
        }))
      return true;
    raw.tets.clear();
    raw.reference.clear();
    raw.tet_line.clear();
  }
  reserve_records(raw.tets, m, text, 10);
  for (long long e = 0; e < m; ++e) {
    const auto index_token = tokens.next();
    if (!index_token) {
      truncated(defects, file, "tets", e, m, header_line);
      return false;
    }
    const std::uint64_t line = tokens.line();
    std::array<long long, 4> tet{};
    int reference = 0;
    if (!read_tet_fields(tokens, *index_token, corners, attributes, tet, reference)) {
      defects.add(DefectKind::Unreadable, at(file, line) + "expected tet " + std::to_string(e) +
                                              " as " + record + " (integers)");
      return false;
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

void parse_veg(std::string_view text, RawMesh& raw, unsigned threads, Defects& defects) {
  const std::string& file = raw.vertex_file;
  const TokenRules rules{TokenRules::Hash::CommentAnywhere, /*comma_separates=*/true};
  Tokens tokens(text, rules);
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
      if (!read_vertex_section(text, tokens, rules, file,
                               "expected the vertex header 'N 3 0 0' (N vertices in 3D)", "1", raw,
                               threads, defects))
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
      if (!read_tet_records(text, tokens, rules, file, *m, header_line, /*corners=*/4, /*attributes=*/0,
                            "'index v0 v1 v2 v3'", raw, threads, defects))
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

void parse_node(std::string_view text, RawMesh& raw, unsigned threads, Defects& defects) {
  const TokenRules rules{TokenRules::Hash::CommentAnywhere};
  Tokens tokens(text, rules);
  read_vertex_section(text, tokens, rules, raw.vertex_file,
                      "expected the header 'N 3 attributes boundary_marker'", "0 or 1", raw,
                      threads, defects);
}

void parse_ele(std::string_view text, RawMesh& raw, unsigned threads, Defects& defects) {
  const std::string& file = raw.tet_file;
  const TokenRules rules{TokenRules::Hash::CommentAnywhere};
  Tokens tokens(text, rules);
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
  if (read_tet_records(text, tokens, rules, file, *m, header_line, corners, *attributes,
                       "'index v0 v1 v2 v3 [attributes]'", raw, threads, defects))
    to_zero_based(raw);  // numbered like the .node file
}

// ---- Gmsh .msh 4.1 (ASCII) ---------------------------------------------------------------------

/// Gmsh's 4-node tetrahedron and 10-node (second order) tetrahedron, whose corners come first.
constexpr long long kGmshTet = 4;
constexpr long long kGmshTet10 = 11;

struct GmshNode {
  long long tag = 0;
  Point3 point{};
  std::uint64_t line = 0;
};
struct GmshTet {
  long long tag = 0;
  std::array<long long, 4> nodes{};  ///< node tags
  long long entity = 0;
  std::uint64_t line = 0;
};

void parse_gmsh(std::string_view text, RawMesh& raw, Defects& defects) {
  const std::string& file = raw.vertex_file;
  Tokens tokens(text, {TokenRules::Hash::Text});
  auto bad = [&](std::uint64_t line, const std::string& message) {
    defects.add(DefectKind::Unreadable, at(file, line) + message);
  };
  auto integer = [&](long long& value) {
    const auto t = tokens.next();
    const auto v = t ? parse_integer(*t) : std::nullopt;
    if (v) value = *v;
    return v.has_value();
  };
  auto real = [&](double& value) {
    const auto t = tokens.next();
    const auto v = t ? parse_double(*t) : std::nullopt;
    if (v) value = *v;
    return v.has_value();
  };
  bool saw_format = false;
  bool saw_nodes = false;
  bool saw_elements = false;
  std::map<long long, long long> volume_physical;  // volume entity tag -> first physical tag
  std::vector<GmshNode> nodes;
  std::vector<GmshTet> tets;
  while (const auto token = tokens.next()) {
    const std::uint64_t line = tokens.line();
    if (token->front() != '$') {
      bad(line, "expected a section ('$MeshFormat', '$Nodes', '$Elements', ...), found " +
                    quoted(*token));
      return;
    }
    const std::string section(token->substr(1));
    if (!saw_format && section != "MeshFormat") {
      bad(line, "expected '$MeshFormat' first, found " + quoted(*token));
      return;
    }
    if (section == "MeshFormat") {
      const auto version = tokens.next();
      long long file_type = -1;
      long long data_size = 0;
      if (!version || !integer(file_type) || !integer(data_size)) {
        bad(line, "expected 'version file-type data-size' after '$MeshFormat'");
        return;
      }
      if (*version != "4.1") {
        bad(tokens.line(), "only Gmsh .msh version 4.1 is read, found version " +
                               quoted(*version) + " (in Gmsh: Mesh.MshFileVersion = 4.1)");
        return;
      }
      if (file_type != 0) {
        bad(tokens.line(), "a binary .msh is not read: save it as ASCII (in Gmsh: Mesh.Binary = 0)");
        return;
      }
      saw_format = true;
    } else if (section == "Entities") {
      long long counts[4] = {};
      for (long long& c : counts) {
        if (!integer(c) || c < 0) {
          bad(tokens.line(), "expected 'numPoints numCurves numSurfaces numVolumes' after '$Entities'");
          return;
        }
      }
      for (int dim = 0; dim < 4; ++dim) {
        for (long long i = 0; i < counts[dim]; ++i) {
          long long tag = 0;
          long long physical_count = 0;
          double ignored = 0;
          bool ok = integer(tag);
          for (int k = 0; k < (dim == 0 ? 3 : 6) && ok; ++k) ok = real(ignored);
          ok = ok && integer(physical_count) && physical_count >= 0;
          std::optional<long long> first_physical;
          for (long long k = 0; k < physical_count && ok; ++k) {
            long long physical = 0;
            ok = integer(physical);
            if (ok && k == 0) first_physical = physical;
          }
          long long bounding = 0;
          if (ok && dim > 0) ok = integer(bounding) && bounding >= 0;
          for (long long k = 0, bounding_tag = 0; k < bounding && ok; ++k) ok = integer(bounding_tag);
          if (!ok) {
            bad(tokens.line(), "expected entity " + std::to_string(i) + " of dimension " +
                                   std::to_string(dim) + " in '$Entities' (tag, bounding box, physical tags" +
                                   (dim > 0 ? ", bounding entities)" : ")"));
            return;
          }
          if (dim == 3 && first_physical) volume_physical[tag] = *first_physical;
        }
      }
    } else if (section == "PartitionedEntities") {
      bad(line, "a partitioned .msh is not read: save the mesh unpartitioned");
      return;
    } else if (section == "Nodes") {
      if (saw_nodes) return bad(line, "a second '$Nodes' section");
      saw_nodes = true;
      long long blocks = 0, count = 0, min_tag = 0, max_tag = 0;
      if (!integer(blocks) || !integer(count) || !integer(min_tag) || !integer(max_tag) ||
          blocks < 0 || count < 0) {
        bad(line, "expected 'numEntityBlocks numNodes minNodeTag maxNodeTag' after '$Nodes'");
        return;
      }
      reserve_records(nodes, count, text, 8);
      for (long long b = 0; b < blocks; ++b) {
        long long dim = 0, entity = 0, parametric = 0, n = 0;
        if (!integer(dim) || !integer(entity) || !integer(parametric) || !integer(n) || n < 0) {
          bad(tokens.line(), "expected node block " + std::to_string(b) +
                                 " as 'entityDim entityTag parametric numNodesInBlock'");
          return;
        }
        const std::size_t first = nodes.size();
        for (long long i = 0; i < n; ++i) {
          GmshNode node;
          if (!integer(node.tag)) {
            bad(tokens.line(), "expected " + std::to_string(n) + " node tags in node block " +
                                   std::to_string(b));
            return;
          }
          nodes.push_back(node);
        }
        for (long long i = 0; i < n; ++i) {
          GmshNode& node = nodes[first + static_cast<std::size_t>(i)];
          const auto x = tokens.next();
          node.line = tokens.line();
          const auto value = x ? parse_double(*x) : std::nullopt;
          if (!value) {
            if (!x) return truncated(defects, file, "nodes", static_cast<long long>(first) + i, count, line);
            bad(node.line, "expected the coordinates 'x y z' of node tag " + std::to_string(node.tag) +
                               ", found " + quoted(*x));
            return;
          }
          node.point[0] = *value;
          bool ok = true;
          for (int k = 1; k < 3 && ok; ++k) {
            const auto c = tokens.next_on_line();
            const auto v = c ? parse_double(*c) : std::nullopt;
            ok = v.has_value();
            if (ok) node.point[k] = *v;
          }
          if (!ok) {
            bad(node.line, "expected the coordinates 'x y z' of node tag " + std::to_string(node.tag));
            return;
          }
          tokens.skip_line();  // parametric coordinates
        }
      }
      if (static_cast<long long>(nodes.size()) != count) {
        bad(line, "'$Nodes' announces " + std::to_string(count) + " nodes, its blocks hold " +
                      std::to_string(nodes.size()));
        return;
      }
    } else if (section == "Elements") {
      if (saw_elements) return bad(line, "a second '$Elements' section");
      saw_elements = true;
      long long blocks = 0, count = 0, min_tag = 0, max_tag = 0;
      if (!integer(blocks) || !integer(count) || !integer(min_tag) || !integer(max_tag) ||
          blocks < 0 || count < 0) {
        bad(line, "expected 'numEntityBlocks numElements minElementTag maxElementTag' after '$Elements'");
        return;
      }
      long long seen = 0;
      for (long long b = 0; b < blocks; ++b) {
        long long dim = 0, entity = 0, type = 0, n = 0;
        if (!integer(dim) || !integer(entity) || !integer(type) || !integer(n) || n < 0) {
          bad(tokens.line(), "expected element block " + std::to_string(b) +
                                 " as 'entityDim entityTag elementType numElementsInBlock'");
          return;
        }
        const bool tet = type == kGmshTet || type == kGmshTet10;
        if (tet) reserve_records(tets, n, text, 10);
        tokens.skip_line();
        for (long long e = 0; e < n; ++e, ++seen) {
          GmshTet t;
          const auto tag_token = tokens.next();
          if (!tag_token) return truncated(defects, file, "elements", seen, count, line);
          t.line = tokens.line();
          const auto tag = parse_integer(*tag_token);
          if (!tag) {
            bad(t.line, "expected an element tag in element block " + std::to_string(b) +
                            ", found " + quoted(*tag_token));
            return;
          }
          t.tag = *tag;
          t.entity = entity;
          bool ok = true;
          for (int k = 0; k < 4 && tet && ok; ++k) {
            const auto v = tokens.next_on_line();
            const auto node = v ? parse_integer(*v) : std::nullopt;
            ok = node.has_value();
            if (ok) t.nodes[k] = *node;
          }
          if (!ok) {
            bad(t.line, "expected element tag " + std::to_string(t.tag) +
                            " as 'elementTag n0 n1 n2 n3' (node tags)");
            return;
          }
          if (tet) tets.push_back(t);
          tokens.skip_line();  // the rest of a 10-node tet, or an element of another type
        }
      }
      if (seen != count) {
        bad(line, "'$Elements' announces " + std::to_string(count) + " elements, its blocks hold " +
                      std::to_string(seen));
        return;
      }
    } else {
      // $PhysicalNames, $Periodic, $NodeData, $Comments, ...: nothing a tet mesh needs.
      const std::string end = "$End" + section;
      auto t = tokens.next();
      while (t && *t != end) t = tokens.next();
      if (!t) return bad(line, "'" + std::string(*token) + "' has no '" + end + "'");
      continue;
    }
    const auto end = tokens.next();
    if (!end || *end != "$End" + section) {
      bad(end ? tokens.line() : line, "expected '$End" + section + "', found " +
                                          quoted(end.value_or("end of file")));
      return;
    }
  }
  if (!saw_nodes || !saw_elements) {
    defects.add(DefectKind::Empty,
                file + " has no '" + std::string(saw_nodes ? "$Elements" : "$Nodes") + "' section");
    return;
  }
  // Vertices in node-tag order, tets in element-tag order (the writer's output order).
  std::stable_sort(nodes.begin(), nodes.end(),
                   [](const GmshNode& a, const GmshNode& b) { return a.tag < b.tag; });
  std::stable_sort(tets.begin(), tets.end(),
                   [](const GmshTet& a, const GmshTet& b) { return a.tag < b.tag; });
  for (std::size_t i = 1; i < nodes.size(); ++i) {
    if (nodes[i].tag == nodes[i - 1].tag)
      return bad(nodes[i].line, "node tag " + std::to_string(nodes[i].tag) +
                                    " is also defined on line " + std::to_string(nodes[i - 1].line));
  }
  for (std::size_t i = 1; i < tets.size(); ++i) {
    if (tets[i].tag == tets[i - 1].tag)
      return bad(tets[i].line, "element tag " + std::to_string(tets[i].tag) +
                                   " is also used on line " + std::to_string(tets[i - 1].line));
  }
  const bool one_based = !nodes.empty() && nodes.front().tag == 1 &&
                         nodes.back().tag == static_cast<long long>(nodes.size());
  raw.index_base = one_based ? 1 : 0;
  for (const GmshNode& node : nodes) {
    raw.vertices.push_back(node.point);
    raw.vertex_line.push_back(node.line);
  }
  for (const GmshTet& t : tets) {
    std::array<long long, 4> tet{};
    for (int k = 0; k < 4; ++k) {
      const auto it = std::lower_bound(
          nodes.begin(), nodes.end(), t.nodes[k],
          [](const GmshNode& node, long long tag) { return node.tag < tag; });
      if (it == nodes.end() || it->tag != t.nodes[k]) {
        defects.add(DefectKind::OutOfRange,
                    at(file, t.line) + "tet element tag " + std::to_string(t.tag) +
                        " refers to node tag " + std::to_string(t.nodes[k]) +
                        ", which '$Nodes' does not define",
                    {static_cast<long>(&t - tets.data())}, {}, {});
        return;
      }
      // 0-based indices as finish() expects them after to_zero_based().
      tet[k] = (it - nodes.begin()) + raw.index_base;
    }
    const auto physical = volume_physical.find(t.entity);
    raw.tets.push_back(tet);
    raw.reference.push_back(physical == volume_physical.end()
                                ? -1
                                : static_cast<int>(physical->second - 1));
    raw.tet_line.push_back(t.line);
  }
  to_zero_based(raw);
}

// ---- common ------------------------------------------------------------------------------------

std::optional<std::string> read_file(const std::string& path, Defects& defects) {
  std::string error;
  auto data = text::read_file(path, error);
  if (!data) defects.add(DefectKind::Unreadable, std::move(error));
  return data;
}

/// Index range, non-finite coordinates, exact orientation: the raw mesh becomes a TetMesh whose
/// tets are all positively oriented. The orientations are found on `threads` threads.
void finish(RawMesh& raw, TetReadResult& result, unsigned threads, Defects& defects) {
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
  if (raw.tets.size() > kMaxBackgroundTets) {  // Medit and Gmsh, whose counts are not checked at a header
    defects.add(DefectKind::Unreadable, raw.tet_file + " has " + std::to_string(raw.tets.size()) +
                                            " tets, more than the " + std::to_string(kMaxBackgroundTets) +
                                            " a background mesh may have");
    return;
  }
  const auto point = [&](long long v) {
    const Point3& p = mesh.vertices[static_cast<std::size_t>(v)];
    return Kernel::Point_3(p[0], p[1], p[2]);
  };
  // The orientation of every tet whose corners are in range and finite (0 for the others, which
  // are reported below); on several threads, exact (Epick's filtered predicate).
  std::vector<std::int8_t> orientation(raw.tets.size(), 0);
  parallel_blocks(threads, raw.tets.size(), 1 << 13, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      const auto& tet = raw.tets[t];
      bool usable = true;
      for (long long v : tet) usable = usable && v >= 0 && v < n && is_finite(mesh.vertices[static_cast<std::size_t>(v)]);
      if (usable)
        orientation[t] = static_cast<std::int8_t>(CGAL::orientation(point(tet[0]), point(tet[1]), point(tet[2]), point(tet[3])));
    }
  });
  mesh.tets.reserve(raw.tets.size());
  mesh.reference.reserve(raw.tets.size());
  for (std::size_t t = 0; t < raw.tets.size(); ++t) {
    const auto& tet = raw.tets[t];
    // Messages are only made for a defect: most tets have none, and formatting them for every
    // tet was half of the read's time (quintuple torus .veg: 20 -> 9 ms).
    const auto where = [&] { return at(raw.tet_file, raw.tet_line[t]) + "tet " + std::to_string(t); };
    bool in_range = true;
    for (long long v : tet) {
      if (v >= 0 && v < n) continue;
      defects.add(DefectKind::OutOfRange,
                  where() + " refers to vertex " + std::to_string(v + raw.index_base) +
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
    if (orientation[t] == CGAL::COPLANAR) {
      std::vector<long> vertex_ids(tet.begin(), tet.end());
      std::vector<std::vector<double>> points;
      for (int k = 0; k < 4; ++k) points.push_back(coordinates(*p[k]));
      const bool repeated = std::set<long long>(tet.begin(), tet.end()).size() < 4;
      defects.add(DefectKind::DegenerateFacet,
                  where() + " has zero volume (" +
                      (repeated ? "a repeated vertex" : "four coplanar corners") + "): vertices " +
                      corners() + base_note,
                  {static_cast<long>(t)}, std::move(vertex_ids), std::move(points));
      continue;
    }
    Tet out{static_cast<int>(tet[0]), static_cast<int>(tet[1]), static_cast<int>(tet[2]),
            static_cast<int>(tet[3])};
    if (orientation[t] == CGAL::NEGATIVE) {
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

std::array<std::string, 2> tetgen_paths(const std::string& path) {
  const std::string ext = lower_extension(path);
  const std::string given = std::filesystem::path(path).extension().string();
  const std::string stem = std::filesystem::path(path).replace_extension().string();
  return {stem + (ext == ".node" ? given : ".node"), stem + (ext == ".ele" ? given : ".ele")};
}

bool is_tet_mesh_extension(const std::string& path) {
  return has_extension(path, {".veg", ".mesh", ".node", ".ele", ".msh"});
}

TetReadResult read_tet_mesh(const std::string& path, unsigned threads) {
  TetReadResult result;
  Defects defects;
  const std::string ext = lower_extension(path);
  RawMesh raw;
  raw.vertex_file = raw.tet_file = path;
  if (!is_tet_mesh_extension(path)) {
    defects.add(DefectKind::Unreadable, "cannot read '" + path + "': unknown tet mesh extension '" +
                                            ext + "' (expected .veg, .mesh, .node, .ele or .msh)");
  } else if (ext == ".node" || ext == ".ele") {
    // TetGen: the vertices and the tets are two files with the same stem.
    const auto [node_path, ele_path] = tetgen_paths(path);
    raw.vertex_file = node_path;
    raw.tet_file = ele_path;
    const auto node = read_file(raw.vertex_file, defects);
    const auto ele = read_file(raw.tet_file, defects);
    if (node && ele) {
      parse_node(*node, raw, threads, defects);
      if (!defects.any()) parse_ele(*ele, raw, threads, defects);
    }
  } else if (const auto text = read_file(path, defects)) {
    if (ext == ".veg") {
      raw.index_base = 1;
      parse_veg(*text, raw, threads, defects);
    } else if (ext == ".msh") {
      parse_gmsh(*text, raw, defects);
    } else {
      parse_medit(*text, raw, defects);
    }
  }
  if (!defects.any()) finish(raw, result, resolve_threads(threads), defects);
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

std::string format_gmsh(const TetMesh& mesh) {
  auto reference = [&](std::size_t t) { return t < mesh.reference.size() ? mesh.reference[t] : 0; };
  // One volume entity per distinct reference (entity tag = its rank + 1), with its box.
  std::map<int, std::vector<std::size_t>> tets_of;  // reference -> tets, in output order
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) tets_of[reference(t)].push_back(t);
  if (tets_of.empty() && !mesh.vertices.empty()) tets_of[0];  // an entity to classify nodes on
  std::string out = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  out.reserve(mesh.vertices.size() * 64 + mesh.tets.size() * 48);
  std::size_t named = 0;
  for (const auto& entry : tets_of) named += entry.first >= 0;
  out += "$PhysicalNames\n" + std::to_string(named) + "\n";
  for (const auto& entry : tets_of) {
    if (entry.first < 0) continue;
    out += "3 " + std::to_string(entry.first + 1ll) + " \"node " + std::to_string(entry.first) + "\"\n";
  }
  out += "$EndPhysicalNames\n$Entities\n0 0 0 " + std::to_string(tets_of.size()) + "\n";
  std::size_t entity = 0;
  for (const auto& [ref, tets] : tets_of) {
    Point3 lo{0, 0, 0}, hi{0, 0, 0};
    bool first = true;
    for (std::size_t t : tets) {
      for (int v : mesh.tets[t]) {
        const Point3& p = mesh.vertices[v];
        for (int k = 0; k < 3; ++k) {
          lo[k] = first ? p[k] : std::min(lo[k], p[k]);
          hi[k] = first ? p[k] : std::max(hi[k], p[k]);
        }
        first = false;
      }
    }
    out += std::to_string(++entity) + ' ' + format_xyz(lo) + ' ' + format_xyz(hi) +
           (ref >= 0 ? " 1 " + std::to_string(ref + 1ll) : std::string(" 0")) + " 0\n";
  }
  out += "$EndEntities\n$Nodes\n";
  const std::size_t n = mesh.vertices.size();
  out += n == 0 ? std::string("0 0 0 0\n")
                : "1 " + std::to_string(n) + " 1 " + std::to_string(n) + "\n3 1 0 " +
                      std::to_string(n) + "\n";
  for (std::size_t v = 0; v < n; ++v) out += std::to_string(v + 1) + '\n';
  for (const Point3& p : mesh.vertices) out += format_xyz(p) + '\n';
  out += "$EndNodes\n$Elements\n";
  const std::size_t m = mesh.tets.size();
  std::size_t blocks = 0;
  for (const auto& entry : tets_of) blocks += !entry.second.empty();
  out += std::to_string(blocks) + ' ' + std::to_string(m) + ' ' + std::to_string(m ? 1 : 0) + ' ' +
         std::to_string(m) + '\n';
  entity = 0;
  for (const auto& entry : tets_of) {
    ++entity;
    if (entry.second.empty()) continue;
    out += "3 " + std::to_string(entity) + " 4 " + std::to_string(entry.second.size()) + '\n';
    for (std::size_t t : entry.second) {
      out += std::to_string(t + 1);
      for (int v : mesh.tets[t]) out += ' ' + std::to_string(v + 1ll);
      out += '\n';
    }
  }
  out += "$EndElements\n";
  return out;
}

TetGenTexts format_tetgen(const TetMesh& mesh) {
  TetGenTexts out;
  out.node = "# " + std::to_string(mesh.vertices.size()) + " vertices (TetGen .node, 1-based)\n" +
             std::to_string(mesh.vertices.size()) + " 3 0 0\n";
  out.node.reserve(mesh.vertices.size() * 64);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    out.node += std::to_string(v + 1) + ' ' + format_xyz(mesh.vertices[v]) + '\n';
  out.ele = "# " + std::to_string(mesh.tets.size()) +
            " tets (TetGen .ele, 1-based; region attribute = reference)\n" +
            std::to_string(mesh.tets.size()) + " 4 1\n";
  out.ele.reserve(mesh.tets.size() * 48);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    out.ele += std::to_string(t + 1);
    for (int v : mesh.tets[t]) out.ele += ' ' + std::to_string(v + 1ll);
    out.ele += ' ' + std::to_string(t < mesh.reference.size() ? mesh.reference[t] : 0) + '\n';
  }
  return out;
}

std::size_t face_connected_components(const TetMesh& mesh) {
  UnionFind uf(mesh.tets.size());
  std::map<std::array<int, 3>, std::size_t> first;  // face -> first tet seen with it
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> f{};
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != skip) f[static_cast<std::size_t>(j++)] = mesh.tets[t][static_cast<std::size_t>(k)];
      std::sort(f.begin(), f.end());
      const auto [it, inserted] = first.emplace(f, t);
      if (!inserted) uf.unite(it->second, t);
    }
  std::size_t n = 0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) n += uf.find(t) == t ? 1 : 0;
  return n;
}

}  // namespace imm::dim3
