// Readers (OBJ, OFF, PLY, STL) and writers of 3D input surfaces (dim3/surface.h).
//
// Small hand-written parsers rather than CGAL::IO::read_polygon_soup: every error names the file
// and the line (text formats) or the record (binary formats), and the whole file is parsed from
// one buffer with std::from_chars (correctly rounded), which keeps a 4 MB OBJ well under 0.1 s.
// The tokenizer, number parsing and formatting are shared with dim3/tet_io.cpp (dim3/text_io.h).
// Every format is first read into a polygon soup; the common finish checks indices, reports
// non-finite coordinates and fan-triangulates polygons from their first vertex.
//
// Geometric and topological validity is not checked here: that is validate_surface().
#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <string_view>
#include <unordered_map>

#include "core/atomic_file.h"
#include "dim3/surface.h"
#include "dim3/text_io.h"

namespace imm::dim3 {
namespace {

using namespace text;  // the helpers shared with the other dim3 reader

constexpr const char* kReadStage = "read";

/// Read defects, at most kMaxDefectsPerKind messages per kind and then one "... and N more":
/// a broken file with a million faces must not produce a million lines.
class ReadDefects {
 public:
  void add(Defect d) {
    std::size_t& n = count_[d.kind];
    if (++n <= kMaxDefectsPerKind) defects_.push_back(std::move(d));
  }
  void add(DefectKind kind, std::string message, std::vector<long> facets = {},
           std::vector<long> vertices = {}, std::vector<std::vector<double>> points = {}) {
    add(Defect{kind, kReadStage, std::move(message), std::move(facets), std::move(vertices),
               std::move(points)});
  }
  [[nodiscard]] bool any() const { return !count_.empty(); }
  void finish(ValidationReport& report) {
    for (Defect& d : defects_) report.add(std::move(d));
    for (const auto& [kind, n] : count_) {
      if (n <= kMaxDefectsPerKind) continue;
      report.add(Defect{kind,
                        kReadStage,
                        "... and " + std::to_string(n - kMaxDefectsPerKind) + " more " +
                            to_string(kind) + " errors",
                        {},
                        {},
                        {}});
    }
  }

 private:
  std::vector<Defect> defects_;
  std::map<DefectKind, std::size_t> count_;
};

/// Polygons as written in the file, before the range check and the triangulation.
struct Soup {
  std::vector<Point3> vertices;
  std::vector<std::uint64_t> vertex_where;  ///< line (text) or record (binary) of each vertex
  std::vector<bool> vertex_unreadable;      ///< already reported; NaN placeholder (may be short)
  std::vector<std::int64_t> corners;        ///< 0-based, possibly out of range
  std::vector<std::size_t> polygon_start{0};
  std::vector<std::uint64_t> polygon_where;
  std::vector<bool> polygon_unreadable;  ///< already reported (kept as an empty polygon)
  int index_base = 0;  ///< how the file numbers vertices (OBJ: 1), for messages
  bool saw_polylines = false;

  /// Ends a polygon. An `unreadable` one (already reported) is kept empty so that the face
  /// numbering stays that of the file; an empty polygon that was read (OBJ 'f' alone, OFF and
  /// PLY count 0) is a face with 0 vertices, reported like one with 1 or 2.
  void add_polygon(std::uint64_t where, bool unreadable = false) {
    polygon_start.push_back(corners.size());
    polygon_where.push_back(where);
    polygon_unreadable.push_back(unreadable);
  }
  /// A vertex that could not be parsed: a NaN placeholder keeps the later vertex numbers right.
  void add_unreadable_vertex(std::uint64_t where) {
    vertex_unreadable.resize(vertices.size() + 1, false);
    vertex_unreadable.back() = true;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    vertices.push_back({nan, nan, nan});
    vertex_where.push_back(where);
  }
  [[nodiscard]] bool is_unreadable(std::size_t v) const {
    return v < vertex_unreadable.size() && vertex_unreadable[v];
  }
  [[nodiscard]] std::size_t polygon_count() const { return polygon_where.size(); }
};

/// "file:12: " for a line of a text file, "file: " in a binary one.
class Where {
 public:
  Where(std::string name, bool lines) : name_(std::move(name)), lines_(lines) {}
  [[nodiscard]] std::string line(std::uint64_t n) const { return at(name_, n); }
  /// Where a record starts: its line in a text file; in a binary file the message names the record.
  [[nodiscard]] std::string record(std::uint64_t n) const {
    return lines_ ? line(n) : name_ + ": ";
  }
  [[nodiscard]] const std::string& name() const { return name_; }
  void set_lines(bool lines) { lines_ = lines; }

 private:
  std::string name_;
  bool lines_;
};

// ---- OBJ -----------------------------------------------------------------------------------

/// What follows the vertex number of a face corner: "", "/vt", "/vt/vn" or "//vn", where vt and vn
/// are non-zero integers. Anything else ('1/x/1', '1/2/3/4') is not OBJ and is refused, as the
/// vertex number itself is.
bool is_obj_reference_tail(std::string_view tail) {
  if (tail.empty()) return true;
  if (tail.front() != '/') return false;
  tail.remove_prefix(1);
  const auto is_number = [](std::string_view part) {
    const auto value = parse_integer(part);
    return value.has_value() && *value != 0;
  };
  const std::size_t slash = tail.find('/');
  if (slash == std::string_view::npos) return is_number(tail);                  // v/vt
  const std::string_view texture = tail.substr(0, slash), normal = tail.substr(slash + 1);
  return (texture.empty() || is_number(texture)) && is_number(normal);           // v/vt/vn, v//vn
}

void parse_obj(std::string_view text, const Where& at, Soup& soup, ReadDefects& defects) {
  soup.index_base = 1;
  std::vector<std::string_view> tokens;
  std::size_t pos = 0;
  std::uint64_t line_number = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    tokens.clear();
    for (std::size_t i = 0; i < line.size();) {
      while (i < line.size() && is_space(line[i])) ++i;
      const std::size_t start = i;
      while (i < line.size() && !is_space(line[i])) ++i;
      if (i > start) tokens.push_back(line.substr(start, i - start));
    }
    if (tokens.empty()) continue;
    const std::string_view tag = tokens[0];
    if (tag == "v") {
      Point3 p{};
      bool ok = tokens.size() >= 4;
      for (int k = 0; k < 3 && ok; ++k) {
        const auto value = parse_double(tokens[1 + k]);
        ok = value.has_value();
        if (ok) p[k] = *value;
      }
      if (!ok) {
        defects.add(DefectKind::Unreadable,
                    at.line(line_number) + "expected 'v x y z' with three numbers");
        soup.add_unreadable_vertex(line_number);
        continue;
      }
      soup.vertices.push_back(p);
      soup.vertex_where.push_back(line_number);
    } else if (tag == "f" || tag == "fo") {
      const std::size_t first = soup.corners.size();
      bool ok = true;
      for (std::size_t k = 1; k < tokens.size() && ok; ++k) {
        const std::string_view ref =
            tokens[k].substr(0, tokens[k].find('/'));  // "v/vt/vn": the vertex
        const auto value = parse_integer(ref);
        if (!value || *value == 0 || !is_obj_reference_tail(tokens[k].substr(ref.size()))) {
          defects.add(DefectKind::Unreadable,
                      at.line(line_number) + "bad vertex reference " + quoted(tokens[k]) +
                          " in a face (OBJ vertex numbers start at 1; negative ones count back)");
          ok = false;
        } else if (*value < 0) {
          const long long resolved = static_cast<long long>(soup.vertices.size()) + *value;
          if (resolved < 0) {
            defects.add(DefectKind::Unreadable,
                        at.line(line_number) + "relative vertex reference " +
                            std::to_string(*value) + " points before the first vertex (only " +
                            std::to_string(soup.vertices.size()) + " vertices precede it)");
            ok = false;
          } else {
            soup.corners.push_back(resolved);
          }
        } else {
          soup.corners.push_back(*value - 1);
        }
      }
      if (ok) {
        soup.add_polygon(line_number);
      } else {
        soup.corners.resize(first);
      }
    } else if (tag == "l") {
      soup.saw_polylines = true;
    }
    // mtllib, usemtl, vt, vn, vp, g, o, s, p, ... carry nothing a solid needs.
  }
}

// ---- OFF -----------------------------------------------------------------------------------

void parse_off(std::string_view text, const Where& at, Soup& soup, ReadDefects& defects) {
  Tokens tokens(text, {TokenRules::Hash::Comment}, 0, 1, /*first_token_line=*/0);
  const auto header = tokens.next();
  const std::string_view h = header.value_or("");
  const bool off = h.size() >= 3 && h.substr(h.size() - 3) == "OFF" &&
                   h.find_first_of("n4") == std::string_view::npos;
  if (!off) {
    defects.add(
        DefectKind::Unreadable,
        at.line(tokens.line()) + "expected an OFF header ('OFF', 'COFF', 'NOFF', ...), found " +
            quoted(h) +
            (h.find_first_of("n4") != std::string_view::npos ? " (only 3D OFF is supported)" : ""));
    return;
  }
  auto counts_line = tokens.next();
  if (counts_line == "BINARY") {
    defects.add(DefectKind::Unreadable, at.line(tokens.line()) + "binary OFF is not supported");
    return;
  }
  const auto vertex_count = counts_line ? parse_integer(*counts_line) : std::nullopt;
  const auto nf_token = tokens.next_on_line();
  const auto face_count = nf_token ? parse_integer(*nf_token) : std::nullopt;
  if (!vertex_count || !face_count || *vertex_count < 0 || *face_count < 0) {
    defects.add(DefectKind::Unreadable,
                at.line(tokens.line()) + "expected the counts 'vertices faces edges'");
    return;
  }
  tokens.skip_line();
  const std::uint64_t counts_at = tokens.line();
  auto truncated = [&](const char* what, long long i, long long n) {
    defects.add(DefectKind::Unreadable, truncated_message(at.name(), what, i, n, counts_at));
  };
  soup.vertices.reserve(  // a vertex line has at least 6 characters: a wrong count costs nothing
      static_cast<std::size_t>(
          std::min<long long>(*vertex_count, static_cast<long long>(text.size() / 6))));
  for (long long i = 0; i < *vertex_count; ++i) {
    const auto x = tokens.next();
    if (!x) return truncated("vertices", i, *vertex_count);
    const auto y = tokens.next_on_line();
    const auto z = y ? tokens.next_on_line() : std::nullopt;
    const auto px = parse_double(*x);
    const auto py = y ? parse_double(*y) : std::nullopt;
    const auto pz = z ? parse_double(*z) : std::nullopt;
    if (px && py && pz) {
      soup.vertices.push_back({*px, *py, *pz});
      soup.vertex_where.push_back(tokens.line());
    } else {
      defects.add(DefectKind::Unreadable, at.line(tokens.line()) +
                                              "expected three coordinates 'x y z' for vertex " +
                                              std::to_string(i));
      soup.add_unreadable_vertex(tokens.line());
    }
    tokens.skip_line();
  }
  for (long long f = 0; f < *face_count; ++f) {
    const auto n_token = tokens.next();
    if (!n_token) return truncated("faces", f, *face_count);
    const std::uint64_t line = tokens.line();
    const auto n = parse_integer(*n_token);
    const std::size_t first = soup.corners.size();
    bool ok = n.has_value() && *n >= 0;
    for (long long k = 0; ok && k < *n; ++k) {
      const auto token = tokens.next_on_line();
      const auto index = token ? parse_integer(*token) : std::nullopt;
      ok = index.has_value();
      if (ok) soup.corners.push_back(*index);
    }
    if (ok) {
      soup.add_polygon(line);
    } else {
      soup.corners.resize(first);
      defects.add(DefectKind::Unreadable,
                  at.line(line) + "expected face " + std::to_string(f) +
                      " as 'n i_1 ... i_n' (vertex count, then n vertex indices)");
      // Keep the face numbering: an unreadable face is an empty polygon, reported once.
      soup.add_polygon(line, /*unreadable=*/true);
    }
    tokens.skip_line();
  }
}

// ---- PLY -----------------------------------------------------------------------------------

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64, Invalid };

PlyType ply_type(std::string_view name) {
  if (name == "char" || name == "int8") return PlyType::Int8;
  if (name == "uchar" || name == "uint8") return PlyType::UInt8;
  if (name == "short" || name == "int16") return PlyType::Int16;
  if (name == "ushort" || name == "uint16") return PlyType::UInt16;
  if (name == "int" || name == "int32") return PlyType::Int32;
  if (name == "uint" || name == "uint32") return PlyType::UInt32;
  if (name == "float" || name == "float32") return PlyType::Float32;
  if (name == "double" || name == "float64") return PlyType::Float64;
  return PlyType::Invalid;
}

std::size_t ply_size(PlyType t) {
  switch (t) {
    case PlyType::Int8:
    case PlyType::UInt8:
      return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
      return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
    case PlyType::Invalid:
      return 0;
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Invalid;        ///< scalar type, or item type of a list
  PlyType count_type = PlyType::Invalid;  ///< Invalid for a scalar
  [[nodiscard]] bool is_list() const { return count_type != PlyType::Invalid; }
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
  std::uint64_t line = 0;
};

/// Binary PLY values, bounds-checked, in the file's byte order.
class BinaryReader {
 public:
  BinaryReader(std::string_view data, std::size_t pos, bool big_endian)
      : data_(data), pos_(pos), swap_(big_endian != (std::endian::native == std::endian::big)) {}

  /// The value as a double (every PLY scalar type converts exactly); nullopt past the end.
  std::optional<double> read(PlyType type) {
    const std::size_t size = ply_size(type);
    if (pos_ + size > data_.size()) return std::nullopt;
    unsigned char bytes[8];
    std::memcpy(bytes, data_.data() + pos_, size);
    pos_ += size;
    if (swap_) std::reverse(bytes, bytes + size);
    switch (type) {
      case PlyType::Int8:
        return static_cast<double>(static_cast<std::int8_t>(bytes[0]));
      case PlyType::UInt8:
        return static_cast<double>(bytes[0]);
      case PlyType::Int16:
        return static_cast<double>(load<std::int16_t>(bytes));
      case PlyType::UInt16:
        return static_cast<double>(load<std::uint16_t>(bytes));
      case PlyType::Int32:
        return static_cast<double>(load<std::int32_t>(bytes));
      case PlyType::UInt32:
        return static_cast<double>(load<std::uint32_t>(bytes));
      case PlyType::Float32:
        return static_cast<double>(load<float>(bytes));
      case PlyType::Float64:
        return load<double>(bytes);
      case PlyType::Invalid:
        return std::nullopt;
    }
    return std::nullopt;
  }
  [[nodiscard]] std::size_t position() const { return pos_; }

 private:
  template <class T>
  static T load(const unsigned char* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
  }
  std::string_view data_;
  std::size_t pos_;
  bool swap_;
};

/// An index read as a double (from any PLY type) as an integer, nullopt when not integral.
std::optional<std::int64_t> as_index(double value) {
  if (!(std::abs(value) < 9.0e15) || value != std::floor(value)) return std::nullopt;
  return static_cast<std::int64_t>(value);
}

void parse_ply(std::string_view text, Where& at, Soup& soup, ReadDefects& defects) {
  // Header: line-based text up to "end_header".
  std::vector<PlyElement> elements;
  std::string format;
  std::size_t pos = 0;
  std::uint64_t line_number = 0;
  bool ended = false;
  while (pos < text.size() && !ended) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_number;
    std::vector<std::string_view> words;
    for (std::size_t i = 0; i < line.size();) {
      while (i < line.size() && is_space(line[i])) ++i;
      const std::size_t start = i;
      while (i < line.size() && !is_space(line[i])) ++i;
      if (i > start) words.push_back(line.substr(start, i - start));
    }
    auto bad = [&](const std::string& what) {
      defects.add(DefectKind::Unreadable, at.line(line_number) + what);
    };
    if (line_number == 1) {
      if (words.size() != 1 || words[0] != "ply") return bad("expected the PLY magic line 'ply'");
      continue;
    }
    if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
    if (words[0] == "format") {
      if (words.size() < 2)
        return bad("expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      format = std::string(words[1]);
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian") {
        return bad("unknown PLY format " + quoted(words[1]));
      }
    } else if (words[0] == "element") {
      const auto count = words.size() == 3 ? parse_integer(words[2]) : std::nullopt;
      if (!count || *count < 0) return bad("expected 'element <name> <count>'");
      elements.push_back(PlyElement{std::string(words[1]), *count, {}, line_number});
    } else if (words[0] == "property") {
      if (elements.empty()) return bad("'property' before any 'element'");
      PlyProperty p;
      if (words.size() == 5 && words[1] == "list") {
        p.count_type = ply_type(words[2]);
        p.type = ply_type(words[3]);
        p.name = std::string(words[4]);
        if (p.count_type == PlyType::Invalid || p.type == PlyType::Invalid ||
            p.count_type == PlyType::Float32 || p.count_type == PlyType::Float64) {
          return bad("unsupported list types in " + quoted(line));
        }
      } else if (words.size() == 3) {
        p.type = ply_type(words[1]);
        p.name = std::string(words[2]);
        if (p.type == PlyType::Invalid) return bad("unknown property type " + quoted(words[1]));
      } else {
        return bad(
            "expected 'property <type> <name>' or 'property list <count type> <item type> <name>'");
      }
      elements.back().properties.push_back(std::move(p));
    } else if (words[0] == "end_header") {
      ended = true;
    } else {
      return bad("unknown PLY header keyword " + quoted(words[0]));
    }
  }
  if (!ended) {
    defects.add(DefectKind::Unreadable, at.name() + ": the PLY header has no 'end_header' line");
    return;
  }
  if (format.empty()) {
    defects.add(DefectKind::Unreadable, at.name() + ": the PLY header has no 'format' line");
    return;
  }

  // Which properties carry the geometry.
  const PlyElement* vertex_element = nullptr;
  const PlyElement* face_element = nullptr;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") vertex_element = &e;
    if (e.name == "face") face_element = &e;
  }
  std::array<int, 3> xyz{-1, -1, -1};
  if (vertex_element != nullptr) {
    for (std::size_t i = 0; i < vertex_element->properties.size(); ++i) {
      const PlyProperty& p = vertex_element->properties[i];
      for (int k = 0; k < 3; ++k) {
        if (!p.is_list() && p.name == std::string(1, static_cast<char>('x' + k)))
          xyz[k] = static_cast<int>(i);
      }
    }
    if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) {
      defects.add(DefectKind::Unreadable,
                  at.line(vertex_element->line) +
                      "the 'vertex' element needs scalar properties x, y and z");
      return;
    }
  }
  int face_list = -1;
  if (face_element != nullptr) {
    int lists = 0, any_list = -1;
    for (std::size_t i = 0; i < face_element->properties.size(); ++i) {
      const PlyProperty& p = face_element->properties[i];
      if (!p.is_list()) continue;
      ++lists;
      any_list = static_cast<int>(i);
      if (p.name == "vertex_indices" || p.name == "vertex_index") face_list = static_cast<int>(i);
    }
    if (face_list < 0 && lists == 1) face_list = any_list;
    if (face_list < 0) {
      defects.add(DefectKind::Unreadable,
                  at.line(face_element->line) +
                      "the 'face' element needs a list property 'vertex_indices'");
      return;
    }
  }

  const bool ascii = format == "ascii";
  at.set_lines(ascii);
  Tokens tokens(text, {}, pos, line_number + 1, /*first_token_line=*/0);
  BinaryReader binary(text, pos, format == "binary_big_endian");
  std::vector<double> list;
  for (const PlyElement& e : elements) {
    const bool is_vertex = &e == vertex_element;
    const bool is_face = &e == face_element;
    for (long long i = 0; i < e.count; ++i) {
      Point3 p{};
      std::uint64_t where = static_cast<std::uint64_t>(i);
      bool truncated = false, malformed = false;
      for (std::size_t k = 0; k < e.properties.size() && !truncated && !malformed; ++k) {
        const PlyProperty& prop = e.properties[k];
        // One value at a time: ASCII tokens on the instance's line, or binary bytes.
        auto value = [&](PlyType type, bool first_of_instance) -> std::optional<double> {
          if (!ascii) {
            auto v = binary.read(type);
            truncated = !v;
            return v;
          }
          auto token = first_of_instance ? tokens.next() : tokens.next_on_line();
          if (first_of_instance && token) where = tokens.line();
          if (!token) {
            if (first_of_instance) {
              truncated = true;
            } else {
              malformed = true;
            }
            return std::nullopt;
          }
          auto v = parse_double(*token);
          malformed = !v;
          return v;
        };
        if (!prop.is_list()) {
          const auto v = value(prop.type, k == 0);
          if (!v) break;
          if (is_vertex) {
            for (int c = 0; c < 3; ++c) {
              if (xyz[c] == static_cast<int>(k)) p[c] = *v;
            }
          }
          continue;
        }
        const auto n = value(prop.count_type, k == 0);
        if (!n) break;
        const auto count = as_index(*n);
        if (!count || *count < 0) {
          malformed = true;
          break;
        }
        list.clear();
        for (std::int64_t j = 0; j < *count; ++j) {
          const auto v = value(prop.type, false);
          if (!v) break;
          list.push_back(*v);
        }
        if (truncated || malformed) break;
        if (is_face && static_cast<int>(k) == face_list) {
          const std::size_t first = soup.corners.size();
          for (double v : list) {
            const auto index = as_index(v);
            if (!index) {
              malformed = true;
              break;
            }
            soup.corners.push_back(*index);
          }
          if (malformed) soup.corners.resize(first);
        }
      }
      if (truncated) {
        defects.add(DefectKind::Unreadable, at.name() + ": the file ends inside '" + e.name + "' " +
                                                std::to_string(i) + " of the " +
                                                std::to_string(e.count) + " announced on line " +
                                                std::to_string(e.line));
        return;
      }
      if (malformed) {
        defects.add(DefectKind::Unreadable, at.record(where) + "malformed '" + e.name + "' " +
                                                std::to_string(i) +
                                                " (expected the properties declared on line " +
                                                std::to_string(e.line) + ")");
        if (!ascii) return;  // a bad list count loses the record boundaries
      }
      if (is_vertex && malformed) soup.add_unreadable_vertex(where);
      if (is_vertex && !malformed) {
        soup.vertices.push_back(p);
        soup.vertex_where.push_back(where);
      }
      if (is_face)
        soup.add_polygon(where, malformed);  // a malformed face stays as an empty polygon (numbering)
      if (ascii) tokens.skip_line();
    }
  }
}

// ---- STL -----------------------------------------------------------------------------------

std::uint32_t byteswap32(std::uint32_t x) {
  return (x >> 24) | ((x >> 8) & 0xFF00u) | ((x << 8) & 0xFF0000u) | (x << 24);
}

/// Exact-coordinate welding (-0 and +0 are the same coordinate).
struct PointHash {
  std::size_t operator()(const Point3& p) const {
    std::uint64_t h = 0;
    for (double c : p) h = (h ^ std::bit_cast<std::uint64_t>(c + 0.0)) * 0x9E3779B97F4A7C15ull;
    return static_cast<std::size_t>(h ^ (h >> 31));
  }
};

class Welder {
 public:
  Welder(Soup& soup) : soup_(soup) {}
  void add_corner(const Point3& p, std::uint64_t where) {
    auto [it, inserted] = ids_.try_emplace(p, soup_.vertices.size());
    if (inserted) {
      soup_.vertices.push_back(p);
      soup_.vertex_where.push_back(where);
    }
    soup_.corners.push_back(static_cast<std::int64_t>(it->second));
  }

 private:
  Soup& soup_;
  std::unordered_map<Point3, std::size_t, PointHash> ids_;
};

void parse_stl_binary(std::string_view data, const Where& at, Soup& soup, ReadDefects& defects) {
  std::uint32_t count = 0;
  std::memcpy(&count, data.data() + 80, 4);
  if constexpr (std::endian::native == std::endian::big) count = byteswap32(count);
  const std::uint64_t needed = 84 + 50ull * count;
  if (data.size() < needed) {
    defects.add(DefectKind::Unreadable, at.name() + ": binary STL announces " +
                                            std::to_string(count) + " facets (" +
                                            std::to_string(needed) + " bytes) but the file has " +
                                            std::to_string(data.size()) + " bytes");
    count = static_cast<std::uint32_t>((data.size() - 84) / 50);
  } else if (data.size() - needed >= 50) {
    // Room for more facets than the header counts: a wrong count would drop them silently and
    // the surface then looked open. A few bytes of padding (less than a record) are tolerated.
    defects.add(DefectKind::Unreadable, at.name() + ": binary STL announces " +
                                            std::to_string(count) + " facets (" +
                                            std::to_string(needed) + " bytes) but the file has " +
                                            std::to_string(data.size()) + " bytes, room for " +
                                            std::to_string((data.size() - 84) / 50) +
                                            " facets: the facet count does not match the size");
  }
  Welder welder(soup);
  for (std::uint32_t f = 0; f < count; ++f) {
    const char* record = data.data() + 84 + 50ull * f;
    for (int k = 0; k < 3; ++k) {
      Point3 p;
      for (int c = 0; c < 3; ++c) {
        std::uint32_t bits;
        std::memcpy(&bits, record + 12 + 12 * k + 4 * c, 4);
        if constexpr (std::endian::native == std::endian::big) bits = byteswap32(bits);
        p[c] = static_cast<double>(std::bit_cast<float>(bits));
      }
      welder.add_corner(p, f);
    }
    soup.add_polygon(f);
  }
}

void parse_stl_ascii(std::string_view text, const Where& at, Soup& soup, ReadDefects& defects) {
  Tokens tokens(text, {}, 0, 1, /*first_token_line=*/0);
  Welder welder(soup);
  bool in_facet = false;
  std::uint64_t facet_line = 0;
  std::size_t first_corner = 0;
  while (auto token = tokens.next()) {
    if (*token == "facet") {
      if (in_facet) {
        defects.add(DefectKind::Unreadable, at.line(facet_line) + "facet without 'endfacet'");
        soup.corners.resize(first_corner);
      }
      in_facet = true;
      facet_line = tokens.line();
      first_corner = soup.corners.size();
      tokens.skip_line();  // "normal nx ny nz": recomputed from the corners when needed
    } else if (*token == "vertex") {
      const std::uint64_t line = tokens.line();
      Point3 p{};
      bool ok = in_facet;
      for (int c = 0; c < 3 && ok; ++c) {
        const auto t = tokens.next_on_line();
        const auto v = t ? parse_double(*t) : std::nullopt;
        ok = v.has_value();
        if (ok) p[c] = *v;
      }
      if (!ok) {
        defects.add(
            DefectKind::Unreadable,
            at.line(line) + (in_facet ? "expected 'vertex x y z'" : "'vertex' outside a facet"));
        tokens.skip_line();
        continue;
      }
      welder.add_corner(p, line);
    } else if (*token == "endfacet") {
      if (!in_facet) {
        defects.add(DefectKind::Unreadable, at.line(tokens.line()) + "'endfacet' without 'facet'");
        continue;
      }
      soup.add_polygon(facet_line);
      in_facet = false;
    } else if (*token == "solid" || *token == "endsolid") {
      tokens.skip_line();  // the solid's name
    }
    // "outer loop", "endloop": structure only.
  }
  if (in_facet) {
    defects.add(DefectKind::Unreadable,
                at.line(facet_line) + "facet without 'endfacet' at the end of the file");
    soup.corners.resize(first_corner);
  }
}

void parse_stl(std::string_view data, Where& at, Soup& soup, ReadDefects& defects) {
  // "solid" starts an ASCII STL, but some binary writers put it in the 80-byte header too: a size
  // that matches the binary facet count decides.
  std::size_t start = 0;
  while (start < data.size() && std::isspace(static_cast<unsigned char>(data[start]))) ++start;
  const bool solid = data.substr(start, 5) == "solid";
  bool binary_size = false;
  if (data.size() >= 84) {
    std::uint32_t count = 0;
    std::memcpy(&count, data.data() + 80, 4);
    if constexpr (std::endian::native == std::endian::big) count = byteswap32(count);
    binary_size = data.size() == 84 + 50ull * count;
  }
  if (binary_size || (!solid && data.size() >= 84)) {
    at.set_lines(false);
    return parse_stl_binary(data, at, soup, defects);
  }
  if (!solid) {
    defects.add(DefectKind::Unreadable,
                at.name() + ": neither an ASCII STL ('solid ...') nor a binary STL (" +
                    std::to_string(data.size()) + " bytes, fewer than the 84-byte header)");
    return;
  }
  parse_stl_ascii(data, at, soup, defects);
}

// ---- common ----------------------------------------------------------------------------------

/// Range check, non-finite coordinates, fan triangulation.
Surface finish(Soup& soup, const Where& at, ReadDefects& defects) {
  const bool parsed = !defects.any();  // "no face" after a parse error would only repeat it
  Surface s;
  s.vertices = std::move(soup.vertices);
  for (std::size_t v = 0; v < s.vertices.size(); ++v) {
    const Point3& p = s.vertices[v];
    if (soup.is_unreadable(v) || is_finite(p)) continue;
    defects.add(DefectKind::NonFinite,
                at.record(soup.vertex_where[v]) + "vertex " + std::to_string(v) +
                    " has a non-finite coordinate " + format_point(p),
                {}, {static_cast<long>(v)}, {coordinates(p)});
  }
  const auto n = static_cast<std::int64_t>(s.vertices.size());
  s.triangles.reserve(soup.corners.size() / 3 + 1);
  s.source_face.reserve(soup.corners.size() / 3 + 1);
  for (std::size_t f = 0; f < soup.polygon_count(); ++f) {
    const std::size_t begin = soup.polygon_start[f], end = soup.polygon_start[f + 1];
    auto where = [&] { return at.record(soup.polygon_where[f]) + "face " + std::to_string(f); };
    if (soup.polygon_unreadable[f]) continue;  // already reported
    if (end - begin < 3) {
      defects.add(
          DefectKind::DegenerateFacet,
          where() + " has " + std::to_string(end - begin) + " vertices; a face needs at least 3",
          {static_cast<long>(f)}, {}, {});
      continue;
    }
    bool ok = true;
    for (std::size_t k = begin; k < end; ++k) {
      const std::int64_t index = soup.corners[k];
      if (index >= 0 && index < n) continue;
      defects.add(DefectKind::Unreadable,
                  where() + " refers to vertex " + std::to_string(index + soup.index_base) +
                      ", but the file has " + std::to_string(n) + " vertices" +
                      (soup.index_base == 1 ? " (numbered 1.." + std::to_string(n) + ")" : ""),
                  {static_cast<long>(f)}, {}, {});
      ok = false;
    }
    if (!ok) continue;
    for (std::size_t k = begin + 1; k + 1 < end; ++k) {
      s.triangles.push_back({static_cast<std::uint32_t>(soup.corners[begin]),
                             static_cast<std::uint32_t>(soup.corners[k]),
                             static_cast<std::uint32_t>(soup.corners[k + 1])});
      s.source_face.push_back(static_cast<std::uint32_t>(f));
    }
  }
  if (soup.polygon_count() == 0 && parsed) {
    std::string message =
        at.name() + " contains no face (" + std::to_string(n) + " vertices, 0 triangles)";
    if (soup.saw_polylines) message += "; it has 'l' polylines: a 2D curve input, not a surface";
    defects.add(DefectKind::Empty, std::move(message));
  }
  return s;
}

/// OBJ and OFF after their header: a line `vertex_tag` x y z per vertex, then a line `face_tag`
/// a b c per triangle, its vertices numbered from `first_index`.
std::string format_lines(const Surface& surface, std::string header, const char* vertex_tag,
                         const char* face_tag, unsigned long long first_index) {
  std::string out = std::move(header);
  out.reserve(surface.vertex_count() * 40 + surface.triangle_count() * 24);
  for (const Point3& p : surface.vertices) out += vertex_tag + format_xyz(p) + '\n';
  for (const Triangle& t : surface.triangles) {
    out += face_tag + std::to_string(t[0] + first_index) + ' ' +
           std::to_string(t[1] + first_index) + ' ' + std::to_string(t[2] + first_index) + '\n';
  }
  return out;
}

}  // namespace

bool is_surface_extension(const std::string& path) {
  return has_extension(path, {".obj", ".off", ".ply", ".stl"});
}

SurfaceReadResult read_surface(const std::string& path) {
  SurfaceReadResult result;
  auto unreadable = [&](std::string message) {
    result.report.add(Defect{DefectKind::Unreadable, kReadStage, std::move(message), {}, {}, {}});
    return result;
  };
  const std::string ext = lower_extension(path);
  if (!is_surface_extension(path)) {
    return unreadable("cannot read '" + path + "': unknown surface extension '" + ext +
                      "' (expected .obj, .off, .ply or .stl)");
  }
  // /dev/zero or /dev/urandom: no size to read, and reading would never end.
  if (const std::string kind = unreadable_file_kind(path); !kind.empty())
    return unreadable("cannot read '" + path + "': it is " + kind + ", not a regular file");
  std::string error;
  const std::optional<std::string> file = read_file(path, error);
  if (!file) return unreadable(std::move(error));
  const std::string_view data = *file;

  Where at(path, true);
  Soup soup;
  ReadDefects defects;
  if (ext == ".obj") {
    parse_obj(data, at, soup, defects);
  } else if (ext == ".off") {
    parse_off(data, at, soup, defects);
  } else if (ext == ".ply") {
    parse_ply(data, at, soup, defects);
  } else {
    parse_stl(data, at, soup, defects);
  }
  if (soup.vertex_where.size() != soup.vertices.size())
    soup.vertex_where.resize(soup.vertices.size(), 0);
  result.surface = finish(soup, at, defects);
  defects.finish(result.report);
  return result;
}

std::string format_point(const Point3& p) {
  std::string out = "(";  // appended piecewise: GCC 12 warns (-Wrestrict) on a + chain here
  for (int k = 0; k < 3; ++k) {
    out += format_number(p[k]);
    out += k < 2 ? ", " : ")";
  }
  return out;
}

std::string format_obj(const Surface& surface) {
  return format_lines(surface,
                      "# " + std::to_string(surface.vertex_count()) + " vertices, " +
                          std::to_string(surface.triangle_count()) + " triangles\n",
                      "v ", "f ", 1);
}

std::string format_off(const Surface& surface) {
  return format_lines(surface,
                      "OFF\n" + std::to_string(surface.vertex_count()) + ' ' +
                          std::to_string(surface.triangle_count()) + " 0\n",
                      "", "3 ", 0);
}

double signed_volume(const Surface& surface) {
  double six_volume = 0;
  const std::size_t n = surface.vertices.size();
  for (const Triangle& t : surface.triangles) {
    if (t[0] >= n || t[1] >= n || t[2] >= n) continue;
    const Point3& a = surface.vertices[t[0]];
    const Point3& b = surface.vertices[t[1]];
    const Point3& c = surface.vertices[t[2]];
    six_volume += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                  a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  return six_volume / 6.0;
}

Surface merge(const Surface& a, const Surface& b) {
  // A hand-built surface may leave source_face empty: its triangles are then their own faces.
  auto faces = [](const Surface& s) {
    if (s.source_face.size() == s.triangles.size()) return s.source_face;
    std::vector<std::uint32_t> ids(s.triangles.size());
    for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<std::uint32_t>(i);
    return ids;
  };
  Surface out = a;
  out.source_face = faces(a);
  std::uint32_t face_shift = 0;
  for (std::uint32_t f : out.source_face) face_shift = std::max(face_shift, f + 1);
  const auto vertex_shift = static_cast<std::uint32_t>(a.vertices.size());
  out.vertices.insert(out.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const Triangle& t : b.triangles)
    out.triangles.push_back({t[0] + vertex_shift, t[1] + vertex_shift, t[2] + vertex_shift});
  for (std::uint32_t f : faces(b)) out.source_face.push_back(f + face_shift);
  return out;
}

}  // namespace imm::dim3
