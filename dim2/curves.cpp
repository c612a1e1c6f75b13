// Readers, writer and arrangement-free validation of 2D curve sets (DESIGN §3 file formats).
//
// Every reader only parses; geometric validity is decided by validate_curves() (here, exact
// rational arithmetic) and by build_complex() (the exact arrangement). Ids in messages are global
// 0-based vertex/segment ids of the resulting CurveSet, i.e. file order.
#include "dim2/curves.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string_view>

#include "core/atomic_file.h"
#include "core/rational.h"

namespace imm::dim2 {

std::size_t CurveSet::vertex_count() const {
  std::size_t n = 0;
  for (const Curve& c : curves) n += c.vertices.size();
  return n;
}

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  if (value == 0.0) return "0";  // also -0, which rounding of an exact 0 can produce
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

std::string format_point(const Point& p) {
  return "(" + format_number(p.x) + ", " + format_number(p.y) + ")";
}

namespace {

constexpr const char* kReadStage = "read";
constexpr const char* kValidateStage = "validate";

Defect read_error(std::string message) {
  return Defect{DefectKind::Unreadable, kReadStage, std::move(message), {}, {}, {}};
}

/// A line of the file for a message: at most 40 characters, anything but printable ASCII as
/// '?', so a binary file given by mistake cannot flood the terminal with raw bytes.
std::string excerpt(std::string_view line) {
  constexpr std::size_t kMax = 40;
  std::string s(line.substr(0, kMax));
  for (char& c : s) {
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  }
  return "'" + s + (line.size() > kMax ? "...'" : "'");
}

/// At most kMaxReadErrors messages about unreadable lines, then one "... and N more".
class LineErrors {
 public:
  void add(ValidationReport& report, std::string message) {
    if (++count_ <= kMaxReadErrors) report.add(read_error(std::move(message)));
  }
  void finish(ValidationReport& report) const {
    if (count_ > kMaxReadErrors)
      report.add(read_error("... and " + std::to_string(count_ - kMaxReadErrors) + " more unreadable lines"));
  }

 private:
  static constexpr std::size_t kMaxReadErrors = 20;
  std::size_t count_ = 0;
};

bool ends_with_ci(const std::string& s, std::string_view suffix) {
  if (s.size() < suffix.size()) return false;
  for (std::size_t i = 0; i < suffix.size(); ++i) {
    const char a = static_cast<char>(std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])));
    if (a != suffix[i]) return false;
  }
  return true;
}

/// A closed curve written with its first vertex repeated at the end is closed explicitly: the
/// repetition is notation, not a zero-length segment.
void drop_closing_repeat(Curve& curve) {
  if (curve.vertices.size() >= 2 && curve.vertices.front() == curve.vertices.back()) {
    curve.vertices.pop_back();
  }
}

/// strtod over a whole token (accepts nan/inf so that validation can name them).
std::optional<double> parse_double_token(const std::string& token) {
  if (token.empty()) return std::nullopt;
  const char* begin = token.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (end != begin + token.size()) return std::nullopt;
  return v;  // ERANGE overflow gives +-inf, reported as non-finite by validate_curves
}

std::size_t line_of_offset(const std::string& text, std::size_t offset) {
  return 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<long>(std::min(offset, text.size())), '\n'));
}

// ---- SVG ----------------------------------------------------------------------------------

/// Scanner for SVG number lists and path data (SVG 1.1 grammar: "1-2" and ".5.5" are two numbers).
class SvgScanner {
 public:
  explicit SvgScanner(std::string_view s) : s_(s) {}

  void skip_separators() {
    while (pos_ < s_.size() && (std::isspace(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == ',')) ++pos_;
  }
  bool at_end() {
    skip_separators();
    return pos_ >= s_.size();
  }
  bool at_number() {
    skip_separators();
    if (pos_ >= s_.size()) return false;
    const char c = s_[pos_];
    return std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.';
  }
  char peek() {
    skip_separators();
    return pos_ < s_.size() ? s_[pos_] : '\0';
  }
  char take() { return s_[pos_++]; }

  std::optional<double> number() {
    skip_separators();
    const std::size_t start = pos_;
    std::size_t p = pos_;
    if (p < s_.size() && (s_[p] == '+' || s_[p] == '-')) ++p;
    std::size_t digits = 0;
    while (p < s_.size() && std::isdigit(static_cast<unsigned char>(s_[p]))) ++p, ++digits;
    if (p < s_.size() && s_[p] == '.') {
      ++p;
      while (p < s_.size() && std::isdigit(static_cast<unsigned char>(s_[p]))) ++p, ++digits;
    }
    if (digits == 0) return std::nullopt;
    if (p < s_.size() && (s_[p] == 'e' || s_[p] == 'E')) {
      std::size_t q = p + 1;
      if (q < s_.size() && (s_[q] == '+' || s_[q] == '-')) ++q;
      std::size_t exp_digits = 0;
      while (q < s_.size() && std::isdigit(static_cast<unsigned char>(s_[q]))) ++q, ++exp_digits;
      if (exp_digits > 0) p = q;
    }
    pos_ = p;
    return std::strtod(std::string(s_.substr(start, p - start)).c_str(), nullptr);
  }
  [[nodiscard]] std::size_t position() const { return pos_; }

 private:
  std::string_view s_;
  std::size_t pos_ = 0;
};

/// An affine map x' = a x + c y + e, y' = b x + d y + f (SVG's matrix(a b c d e f)).
struct SvgMatrix {
  double a = 1, b = 0, c = 0, d = 1, e = 0, f = 0;
  [[nodiscard]] bool is_identity() const { return a == 1 && b == 0 && c == 0 && d == 1 && e == 0 && f == 0; }
  /// this * m (m is applied first).
  [[nodiscard]] SvgMatrix then_inner(const SvgMatrix& m) const {
    return {a * m.a + c * m.b, b * m.a + d * m.b, a * m.c + c * m.d, b * m.c + d * m.d, a * m.e + c * m.f + e,
            b * m.e + d * m.f + f};
  }
  [[nodiscard]] Point apply(const Point& p) const { return {a * p.x + c * p.y + e, b * p.x + d * p.y + f}; }
};

struct SvgElement {
  std::string name;                            ///< local name, lower case ("polygon", ...)
  std::map<std::string, std::string> attributes;
  std::size_t line = 0;
  /// The element's own `transform` composed with its ancestors' (outermost applied last).
  SvgMatrix transform;
  /// Inside <defs>, <symbol>, <clipPath>, <mask>, <pattern> or <marker>: not drawn by itself.
  bool in_definitions = false;
  /// Why the transform of the element or an ancestor could not be read ("" when it could).
  std::string transform_error;
};

/// Parses an SVG transform list ("translate(10 20) rotate(30)", SVG 1.1 §7.6).
/// @return the composed matrix, or nullopt with `error` set.
std::optional<SvgMatrix> parse_svg_transform(const std::string& value, std::string& error) {
  SvgMatrix total;
  std::size_t p = 0;
  const auto skip = [&] {
    while (p < value.size() && (std::isspace(static_cast<unsigned char>(value[p])) || value[p] == ',')) ++p;
  };
  for (skip(); p < value.size(); skip()) {
    const std::size_t name_start = p;
    while (p < value.size() && std::isalpha(static_cast<unsigned char>(value[p]))) ++p;
    const std::string name = value.substr(name_start, p - name_start);
    while (p < value.size() && std::isspace(static_cast<unsigned char>(value[p]))) ++p;
    const std::size_t close = value.find(')', p);
    if (name.empty() || p >= value.size() || value[p] != '(' || close == std::string::npos) {
      error = "unreadable transform '" + value.substr(0, 60) + "'";
      return std::nullopt;
    }
    SvgScanner scan(std::string_view(value).substr(p + 1, close - p - 1));
    std::vector<double> args;
    while (!scan.at_end()) {
      const auto v = scan.number();
      if (!v) {
        error = "unreadable arguments of " + name + "() in transform '" + value.substr(0, 60) + "'";
        return std::nullopt;
      }
      args.push_back(*v);
    }
    p = close + 1;
    const auto n = args.size();
    const double kDegree = std::acos(-1.0) / 180;
    SvgMatrix m;
    if (name == "matrix" && n == 6) {
      m = {args[0], args[1], args[2], args[3], args[4], args[5]};
    } else if (name == "translate" && (n == 1 || n == 2)) {
      m.e = args[0];
      m.f = n == 2 ? args[1] : 0.0;
    } else if (name == "scale" && (n == 1 || n == 2)) {
      m.a = args[0];
      m.d = n == 2 ? args[1] : args[0];
    } else if (name == "rotate" && (n == 1 || n == 3)) {
      const double c = std::cos(args[0] * kDegree), s = std::sin(args[0] * kDegree);
      const SvgMatrix r{c, s, -s, c, 0, 0};
      if (n == 1) {
        m = r;
      } else {  // rotate(a cx cy) = translate(cx cy) rotate(a) translate(-cx -cy)
        m = SvgMatrix{1, 0, 0, 1, args[1], args[2]}.then_inner(r).then_inner(SvgMatrix{1, 0, 0, 1, -args[1], -args[2]});
      }
    } else if (name == "skewX" && n == 1) {
      m.c = std::tan(args[0] * kDegree);
    } else if (name == "skewY" && n == 1) {
      m.b = std::tan(args[0] * kDegree);
    } else {
      error = "unsupported transform " + name + "() with " + std::to_string(n) + " arguments";
      return std::nullopt;
    }
    total = total.then_inner(m);
  }
  for (double x : {total.a, total.b, total.c, total.d, total.e, total.f}) {
    if (!std::isfinite(x)) {
      error = "transform '" + value.substr(0, 60) + "' is not finite";
      return std::nullopt;
    }
  }
  return total;
}

/// Elements of an SVG document with their attributes, each with the transform of its ancestors
/// composed with its own (text content is irrelevant here).
bool scan_svg_elements(const std::string& text, std::vector<SvgElement>& out, std::string& error) {
  std::size_t pos = 0;
  // Open (not self-closed) elements: what their children inherit.
  struct Open {
    std::string name;
    SvgMatrix transform;
    bool in_definitions;
    std::string transform_error;
  };
  std::vector<Open> open;
  while (true) {
    pos = text.find('<', pos);
    if (pos == std::string::npos) return true;
    if (text.compare(pos, 4, "<!--") == 0) {
      const std::size_t end = text.find("-->", pos + 4);
      if (end == std::string::npos) {
        error = "line " + std::to_string(line_of_offset(text, pos)) + ": unterminated comment";
        return false;
      }
      pos = end + 3;
      continue;
    }
    if (text.compare(pos, 9, "<![CDATA[") == 0) {
      const std::size_t end = text.find("]]>", pos);
      if (end == std::string::npos) {
        error = "line " + std::to_string(line_of_offset(text, pos)) + ": unterminated CDATA";
        return false;
      }
      pos = end + 3;
      continue;
    }
    if (pos + 1 < text.size() && (text[pos + 1] == '?' || text[pos + 1] == '!' || text[pos + 1] == '/')) {
      const std::size_t end = text.find('>', pos);
      if (end == std::string::npos) break;
      if (text[pos + 1] == '/' && !open.empty()) open.pop_back();  // a closing tag
      pos = end + 1;
      continue;
    }
    SvgElement element;
    element.line = line_of_offset(text, pos);
    std::size_t p = pos + 1;
    const std::size_t name_start = p;
    while (p < text.size() && !std::isspace(static_cast<unsigned char>(text[p])) && text[p] != '>' && text[p] != '/') ++p;
    std::string name = text.substr(name_start, p - name_start);
    if (const std::size_t colon = name.find(':'); colon != std::string::npos) name = name.substr(colon + 1);
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    element.name = name;
    // Attributes: name = "value" | 'value'.
    bool self_closing = false;
    while (true) {
      while (p < text.size() && std::isspace(static_cast<unsigned char>(text[p]))) ++p;
      if (p >= text.size()) {
        error = "line " + std::to_string(element.line) + ": unterminated <" + name + "> tag";
        return false;
      }
      if (text[p] == '>') {
        ++p;
        break;
      }
      if (text[p] == '/') {
        self_closing = p + 1 < text.size() && text[p + 1] == '>';
        ++p;
        continue;
      }
      const std::size_t attr_start = p;
      while (p < text.size() && text[p] != '=' && !std::isspace(static_cast<unsigned char>(text[p])) && text[p] != '>') ++p;
      std::string attr = text.substr(attr_start, p - attr_start);
      while (p < text.size() && std::isspace(static_cast<unsigned char>(text[p]))) ++p;
      if (p < text.size() && text[p] == '=') {
        ++p;
        while (p < text.size() && std::isspace(static_cast<unsigned char>(text[p]))) ++p;
        if (p >= text.size() || (text[p] != '"' && text[p] != '\'')) {
          error = "line " + std::to_string(line_of_offset(text, p)) + ": attribute '" + attr +
                  "' of <" + name + "> has no quoted value";
          return false;
        }
        const char quote = text[p];
        const std::size_t value_end = text.find(quote, p + 1);
        if (value_end == std::string::npos) {
          error = "line " + std::to_string(line_of_offset(text, p)) + ": unterminated value of attribute '" + attr + "'";
          return false;
        }
        element.attributes[attr] = text.substr(p + 1, value_end - p - 1);
        p = value_end + 1;
      }
    }
    if (!open.empty()) {
      element.transform = open.back().transform;
      element.in_definitions = open.back().in_definitions;
      element.transform_error = open.back().transform_error;
    }
    if (auto it = element.attributes.find("transform"); it != element.attributes.end() && element.transform_error.empty()) {
      std::string why;
      if (const auto own = parse_svg_transform(it->second, why)) {
        element.transform = element.transform.then_inner(*own);
      } else {
        element.transform_error = "<" + name + "> at line " + std::to_string(element.line) + ": " + why;
      }
    }
    element.in_definitions = element.in_definitions || name == "defs" || name == "symbol" || name == "clippath" ||
                             name == "mask" || name == "pattern" || name == "marker";
    if (!self_closing) open.push_back({name, element.transform, element.in_definitions, element.transform_error});
    out.push_back(std::move(element));
    pos = p;
  }
  return true;
}

/// A length attribute of <rect>: a plain number in user units (a trailing "px" is the same).
/// Percentages and absolute units (mm, cm, in, pt, pc, em, ex) depend on the viewport or the
/// font and are refused. @return the value, or nullopt with `error` naming the attribute.
std::optional<double> svg_length(const std::string& value, const char* name, std::string& error) {
  SvgScanner scan(value);
  const auto number = scan.number();
  std::string rest = value.substr(scan.position());
  rest.erase(std::remove_if(rest.begin(), rest.end(), [](char c) { return std::isspace(static_cast<unsigned char>(c)); }),
             rest.end());
  if (number && (rest.empty() || rest == "px")) return number;
  error = "unsupported length " + std::string(name) + "=" + excerpt(value) +
          " (only plain numbers in user units, or px)";
  return std::nullopt;
}

std::string describe_element(const SvgElement& e, std::size_t index) {
  std::string s = "<" + e.name + "> element " + std::to_string(index);
  if (auto it = e.attributes.find("id"); it != e.attributes.end()) s += " (id \"" + it->second + "\")";
  s += " at line " + std::to_string(e.line);
  return s;
}

/// Parses `points` of <polygon>/<polyline>.
bool parse_svg_points(const std::string& value, Curve& curve, std::string& error) {
  SvgScanner scan(value);
  std::vector<double> numbers;
  while (!scan.at_end()) {
    const auto v = scan.number();
    if (!v) {
      error = "unexpected character '" + std::string(1, value[scan.position()]) + "' in points";
      return false;
    }
    numbers.push_back(*v);
  }
  if (numbers.size() % 2 != 0) {
    error = "odd number of coordinates (" + std::to_string(numbers.size()) + ") in points";
    return false;
  }
  for (std::size_t i = 0; i < numbers.size(); i += 2) curve.vertices.push_back({numbers[i], numbers[i + 1]});
  return true;
}

/// Parses path data with straight commands only (M, L, H, V, Z, absolute and relative). Every
/// subpath is a closed curve (an unclosed subpath is closed implicitly, as SVG fills it).
bool parse_svg_path(const std::string& d, std::vector<Curve>& curves, std::string& error) {
  SvgScanner scan(d);
  Point current{};
  Point subpath_start{};
  bool have_current = false;
  bool subpath_open = false;
  char command = '\0';
  auto start_subpath = [&](Point p) {
    curves.emplace_back();
    curves.back().vertices.push_back(p);
    subpath_start = p;
    subpath_open = true;
  };
  auto line_to = [&](Point p) {
    if (!subpath_open) start_subpath(current);  // a drawing command right after Z
    curves.back().vertices.push_back(p);
  };
  while (!scan.at_end()) {
    if (!scan.at_number()) {
      command = scan.take();
      const char upper = static_cast<char>(std::toupper(static_cast<unsigned char>(command)));
      if (std::strchr("CSQTA", upper) != nullptr) {
        error = std::string("curved path command '") + command +
                "' is not supported (straight segments only: M, L, H, V, Z)";
        return false;
      }
      if (std::strchr("MLHVZ", upper) == nullptr) {
        error = std::string("unknown path command '") + command + "'";
        return false;
      }
      if (upper != 'M' && !have_current) {
        error = std::string("path data must start with M, found '") + command + "'";
        return false;
      }
      if (upper == 'Z') {
        current = subpath_start;
        subpath_open = false;
        continue;
      }
    } else if (command == '\0' || command == 'Z' || command == 'z') {
      error = "number without a command in path data";
      return false;
    }
    const bool relative = std::islower(static_cast<unsigned char>(command)) != 0;
    const char upper = static_cast<char>(std::toupper(static_cast<unsigned char>(command)));
    auto need = [&]() -> std::optional<double> {
      auto v = scan.number();
      if (!v) error = std::string("missing coordinate after '") + command + "'";
      return v;
    };
    if (upper == 'M' || upper == 'L') {
      const auto x = need();
      if (!x) return false;
      const auto y = need();
      if (!y) return false;
      Point p{*x, *y};
      if (relative && have_current) p = {current.x + *x, current.y + *y};
      if (upper == 'M') {
        start_subpath(p);
        command = relative ? 'l' : 'L';  // implicit repeats of M are line-tos
      } else {
        line_to(p);
      }
      current = p;
      have_current = true;
    } else if (upper == 'H') {
      const auto x = need();
      if (!x) return false;
      const Point p{relative ? current.x + *x : *x, current.y};
      line_to(p);
      current = p;
    } else {  // 'V'
      const auto y = need();
      if (!y) return false;
      const Point p{current.x, relative ? current.y + *y : *y};
      line_to(p);
      current = p;
    }
  }
  return true;
}

ReadResult parse_svg(const std::string& text) {
  ReadResult result;
  std::vector<SvgElement> elements;
  std::string error;
  if (!scan_svg_elements(text, elements, error)) {
    result.report.add(read_error("SVG: " + error));
    return result;
  }
  std::size_t index = 0;
  for (const SvgElement& e : elements) {
    if (e.name == "use" && !e.in_definitions) {
      result.report.add(read_error("SVG <use> at line " + std::to_string(e.line) +
                                   " draws a copy of another element; clones are not supported (unlink them)"));
      continue;
    }
    const bool shape = e.name == "polygon" || e.name == "polyline" || e.name == "path" ||
                       e.name == "rect" || e.name == "circle" || e.name == "ellipse" || e.name == "line";
    if (!shape || e.in_definitions) continue;
    const std::string where = describe_element(e, index++);
    if (!e.transform_error.empty()) {
      result.report.add(read_error("SVG " + where + ": " + e.transform_error));
      continue;
    }
    // The element's coordinates are in its own user space: map them to the document's.
    const std::size_t first_curve = result.curves.curves.size();
    struct ApplyTransform {
      ReadResult& result;
      std::size_t first;
      const SvgMatrix& m;
      ~ApplyTransform() {
        if (m.is_identity()) return;
        for (std::size_t c = first; c < result.curves.curves.size(); ++c)
          for (Point& p : result.curves.curves[c].vertices) p = m.apply(p);
      }
    } apply_transform{result, first_curve, e.transform};
    auto attribute = [&](const char* name) -> const std::string* {
      auto it = e.attributes.find(name);
      return it == e.attributes.end() ? nullptr : &it->second;
    };
    if (e.name == "circle" || e.name == "ellipse") {
      result.report.add(read_error("SVG " + where + " is curved; only straight segments are supported"));
    } else if (e.name == "line") {
      Defect d{DefectKind::NotClosed, kReadStage,
               "SVG " + where + " is a single open segment, not a closed curve", {}, {}, {}};
      result.report.add(std::move(d));
    } else if (e.name == "rect") {
      if (attribute("rx") != nullptr || attribute("ry") != nullptr) {
        result.report.add(read_error("SVG " + where + " has rounded (curved) corners"));
        continue;
      }
      std::string why;
      auto number = [&](const char* name) -> std::optional<double> {
        const std::string* v = attribute(name);
        if (v == nullptr) return 0.0;
        return svg_length(*v, name, why);
      };
      const auto x = number("x"), y = number("y"), w = number("width"), h = number("height");
      if (!x || !y || !w || !h) {
        result.report.add(read_error("SVG " + where + ": " + why));
        continue;
      }
      Curve c;
      c.vertices = {{*x, *y}, {*x + *w, *y}, {*x + *w, *y + *h}, {*x, *y + *h}};
      result.curves.curves.push_back(std::move(c));
    } else if (e.name == "path") {
      const std::string* d = attribute("d");
      if (d == nullptr) {
        result.report.add(read_error("SVG " + where + " has no 'd' attribute"));
        continue;
      }
      std::vector<Curve> curves;
      if (!parse_svg_path(*d, curves, error)) {
        result.report.add(read_error("SVG " + where + ": " + error));
        continue;
      }
      for (Curve& c : curves) {
        drop_closing_repeat(c);
        result.curves.curves.push_back(std::move(c));
      }
    } else {  // polygon, polyline (a polyline is taken as closed)
      const std::string* points = attribute("points");
      Curve c;
      if (points == nullptr) {
        result.report.add(read_error("SVG " + where + " has no 'points' attribute"));
        continue;
      }
      if (!parse_svg_points(*points, c, error)) {
        result.report.add(read_error("SVG " + where + ": " + error));
        continue;
      }
      drop_closing_repeat(c);
      result.curves.curves.push_back(std::move(c));
    }
  }
  return result;
}

// ---- OBJ ----------------------------------------------------------------------------------

ReadResult parse_obj(const std::string& text) {
  ReadResult result;
  std::vector<Point> positions;
  struct ObjSegment {
    std::size_t from, to;  // 0-based OBJ vertex indices
    std::size_t line;
  };
  std::vector<ObjSegment> segments;
  bool saw_faces = false;
  LineErrors line_errors;
  std::istringstream in(text);
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    std::string tag;
    if (!(fields >> tag)) continue;
    if (tag == "v") {
      std::vector<std::string> tokens;
      std::string t;
      while (fields >> t) tokens.push_back(t);
      std::optional<double> x, y;
      if (tokens.size() >= 2) {
        x = parse_double_token(tokens[0]);
        y = parse_double_token(tokens[1]);
      }
      if (!x || !y || tokens.size() > 4) {
        line_errors.add(result.report, "OBJ line " + std::to_string(line_number) +
                                           ": expected 'v x y [z]', found " + excerpt(line));
        positions.push_back({});
        continue;
      }
      positions.push_back({*x, *y});  // z (a drawing plane offset) is ignored
    } else if (tag == "l") {
      std::vector<std::size_t> refs;
      std::string t;
      bool ok = true;
      while (fields >> t) {
        const std::string head = t.substr(0, t.find('/'));
        long value = 0;
        const auto parsed = std::from_chars(head.data(), head.data() + head.size(), value);
        const long count = static_cast<long>(positions.size());
        const long index = value < 0 ? count + value : value - 1;
        if (parsed.ec != std::errc() || parsed.ptr != head.data() + head.size() || value == 0 ||
            index < 0 || index >= count) {
          line_errors.add(result.report, "OBJ line " + std::to_string(line_number) + ": bad vertex reference " +
                                             excerpt(t) + " (" + std::to_string(count) +
                                             " vertices defined so far)");
          ok = false;
          break;
        }
        refs.push_back(static_cast<std::size_t>(index));
      }
      if (!ok) continue;
      if (refs.size() < 2) {
        result.report.add(read_error("OBJ line " + std::to_string(line_number) + ": an 'l' element needs at least two vertices"));
        continue;
      }
      for (std::size_t i = 0; i + 1 < refs.size(); ++i) {
        if (refs[i] == refs[i + 1]) {
          Defect d{DefectKind::DuplicateVertex, kReadStage,
                   "OBJ line " + std::to_string(line_number) + ": vertex " + std::to_string(refs[i] + 1) +
                       " " + format_point(positions[refs[i]]) +
                       " is repeated consecutively (zero-length segment)",
                   {}, {static_cast<long>(refs[i])}, {{positions[refs[i]].x, positions[refs[i]].y}}};
          result.report.add(std::move(d));
          continue;
        }
        segments.push_back({refs[i], refs[i + 1], line_number});
      }
    } else if (tag == "f") {
      saw_faces = true;
    }
  }
  line_errors.finish(result.report);
  if (!result.report.ok()) return result;

  // Chain the segments into closed loops: every used vertex needs one incoming and one outgoing
  // segment (OBJ vertex numbers in messages are 1-based, as in the file).
  const std::size_t n = positions.size();
  std::vector<std::vector<std::size_t>> outgoing(n), incoming(n);
  for (std::size_t s = 0; s < segments.size(); ++s) {
    outgoing[segments[s].from].push_back(s);
    incoming[segments[s].to].push_back(s);
  }
  for (std::size_t v = 0; v < n; ++v) {
    const std::size_t in_count = incoming[v].size(), out_count = outgoing[v].size();
    if (in_count == 1 && out_count == 1) continue;
    if (in_count == 0 && out_count == 0) continue;
    const std::string at = "OBJ vertex " + std::to_string(v + 1) + " " + format_point(positions[v]);
    Defect d{DefectKind::NotClosed, kReadStage, "", {}, {static_cast<long>(v)}, {{positions[v].x, positions[v].y}}};
    if (in_count + out_count == 1) {
      d.message = at + " is an end of an open curve (only " + (in_count == 1 ? "an incoming" : "an outgoing") +
                  " segment)";
    } else if (in_count + out_count == 2) {
      d.kind = DefectKind::InconsistentOrientation;
      d.message = at + " joins two segments that both " + (in_count == 2 ? "end" : "start") +
                  " there (inconsistent orientation)";
    } else {
      d.kind = DefectKind::Touching;
      d.message = at + " is used by " + std::to_string(in_count + out_count) +
                  " segments (the curve passes through it more than once)";
    }
    result.report.add(std::move(d));
  }
  if (!result.report.ok()) return result;
  std::vector<bool> used(segments.size(), false);
  for (std::size_t s = 0; s < segments.size(); ++s) {
    if (used[s]) continue;
    Curve c;
    std::size_t cur = s;
    while (!used[cur]) {
      used[cur] = true;
      c.vertices.push_back(positions[segments[cur].from]);
      cur = outgoing[segments[cur].to].front();
    }
    result.curves.curves.push_back(std::move(c));
  }
  if (result.curves.curves.empty() && saw_faces) {
    result.report.add(Defect{DefectKind::Empty, kReadStage,
                             "OBJ file has faces ('f') but no curve ('l' lines); 2D input is read from 'l' elements",
                             {}, {}, {}});
  }
  return result;
}

ReadResult with_validation(ReadResult result) {
  if (!result.report.ok()) return result;
  result.report = validate_curves(result.curves);
  return result;
}

// Exact orientation of three double points (doubles are rationals).
int orientation_sign(const Point& a, const Point& b, const Point& c) {
  const Rational ax(a.x), ay(a.y), bx(b.x), by(b.y), cx(c.x), cy(c.y);
  const Rational det = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
  return sgn(det);
}

}  // namespace

ReadResult parse_curves_text(const std::string& text) {
  ReadResult result;
  Curve current;
  auto finish = [&]() {
    if (current.vertices.empty()) return;
    drop_closing_repeat(current);
    result.curves.curves.push_back(std::move(current));
    current = Curve{};
  };
  LineErrors line_errors;
  std::istringstream in(text);
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const bool blank = std::all_of(line.begin(), line.end(), [](char c) { return std::isspace(static_cast<unsigned char>(c)); });
    if (blank) {
      finish();
      continue;
    }
    std::string content = line.substr(0, line.find('#'));
    for (char& c : content) {
      if (c == ',' || c == ';') c = ' ';
    }
    std::istringstream fields(content);
    std::vector<std::string> tokens;
    std::string t;
    while (fields >> t) tokens.push_back(t);
    if (tokens.empty()) continue;  // comment-only line: does not end a curve
    std::optional<double> x, y;
    if (tokens.size() == 2) {
      x = parse_double_token(tokens[0]);
      y = parse_double_token(tokens[1]);
    }
    if (!x || !y) {
      line_errors.add(result.report,
                      "line " + std::to_string(line_number) + ": expected two numbers 'x y', found " + excerpt(line));
      continue;
    }
    current.vertices.push_back({*x, *y});
  }
  line_errors.finish(result.report);
  finish();
  return with_validation(std::move(result));
}

ReadResult read_curves(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    ReadResult result;
    result.report.add(read_error("cannot read '" + path + "': it is a directory"));
    return result;
  }
  const auto refuse = [&](std::string message) {
    ReadResult result;
    result.report.add(read_error(std::move(message)));
    return result;
  };
  // /dev/zero or /dev/urandom would be read forever: only regular files and FIFOs are inputs.
  if (const std::string kind = unreadable_file_kind(path); !kind.empty())
    return refuse("cannot read '" + path + "': it is " + kind + ", not a regular file");
  std::ifstream file(path, std::ios::binary);
  if (!file) return refuse("cannot open '" + path + "': " + std::strerror(errno));
  // Read in chunks, checking as it comes that it is text: a NUL byte (no text, SVG or OBJ file
  // holds one) or a line longer than kMaxLineBytes ends the read at once, so a binary stream
  // (a FIFO fed from /dev/urandom) or a file without line breaks is refused, not loaded whole.
  constexpr std::size_t kMaxLineBytes = std::size_t{1} << 26;
  std::string text;
  std::vector<char> chunk(1 << 16);
  std::size_t line_start = 0, line_number = 1;
  while (file) {
    file.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const auto n = static_cast<std::size_t>(file.gcount());
    if (n == 0) break;
    const std::size_t base = text.size();
    text.append(chunk.data(), n);
    for (std::size_t i = base; i < text.size(); ++i) {
      if (text[i] == '\0')
        return refuse("cannot read '" + path + "': a NUL byte at byte " + std::to_string(i) + " (line " +
                      std::to_string(line_number) + "): not a text file");
      if (text[i] == '\n') {
        line_start = i + 1;
        ++line_number;
      }
    }
    if (text.size() - line_start > kMaxLineBytes)
      return refuse("cannot read '" + path + "': line " + std::to_string(line_number) + " is longer than " +
                    std::to_string(kMaxLineBytes >> 20) + " MiB: not a curve file");
  }
  if (file.bad()) return refuse("cannot read '" + path + "'");
  if (ends_with_ci(path, ".svg")) return with_validation(parse_svg(text));
  if (ends_with_ci(path, ".obj")) return with_validation(parse_obj(text));
  return parse_curves_text(text);
}

std::string format_curves_text(const CurveSet& curves) {
  std::string out;
  for (const Curve& c : curves.curves) {
    for (const Point& p : c.vertices) {
      out += format_number(p.x);
      out += ' ';
      out += format_number(p.y);
      out += '\n';
    }
    out += '\n';
  }
  return out;
}

ValidationReport validate_curves(const CurveSet& curves) {
  ValidationReport report;
  if (curves.vertex_count() == 0) {
    report.add(Defect{DefectKind::Empty, kValidateStage, "the input contains no curve", {}, {}, {}});
    return report;
  }
  std::size_t offset = 0;
  // Vertices beyond kMaxCoordinate2: the first few are listed, then one count.
  constexpr std::size_t kMaxRangeMessages = 10;
  std::size_t out_of_range = 0;
  for (std::size_t ci = 0; ci < curves.curves.size(); ++ci) {
    const std::vector<Point>& v = curves.curves[ci].vertices;
    const std::size_t n = v.size();
    const std::string curve_name = "curve " + std::to_string(ci);
    auto global = [&](std::size_t local) { return static_cast<long>(offset + local); };
    auto coords = [&](std::size_t local) { return std::vector<double>{v[local].x, v[local].y}; };
    bool finite = true;
    for (std::size_t i = 0; i < n; ++i) {
      if (std::isfinite(v[i].x) && std::isfinite(v[i].y)) {
        if (std::abs(v[i].x) <= kMaxCoordinate2 && std::abs(v[i].y) <= kMaxCoordinate2) continue;
        finite = false;
        if (++out_of_range > kMaxRangeMessages) continue;
        report.add(Defect{DefectKind::OutOfRange, kValidateStage,
                          curve_name + ": vertex " + std::to_string(global(i)) + " " + format_point(v[i]) +
                              " lies beyond the coordinate range of 2D inputs, |x|, |y| <= 1e75 (the interval "
                              "filters of the exact arithmetic overflow beyond it; scale the input)",
                          {}, {global(i)}, {coords(i)}});
        continue;
      }
      finite = false;
      report.add(Defect{DefectKind::NonFinite, kValidateStage,
                        curve_name + ": vertex " + std::to_string(global(i)) + " has a non-finite coordinate " +
                            format_point(v[i]),
                        {}, {global(i)}, {coords(i)}});
    }
    if (n < 3) {
      std::string ids;
      for (std::size_t i = 0; i < n; ++i) ids += (i ? ", " : "") + std::to_string(global(i)) + " " + format_point(v[i]);
      report.add(Defect{DefectKind::TooShort, kValidateStage,
                        curve_name + " has " + std::to_string(n) + " vertices" + (n ? " (" + ids + ")" : "") +
                            "; a closed curve needs at least 3",
                        {}, {}, {}});
      for (std::size_t i = 0; i < n; ++i) {
        report.defects.back().vertices.push_back(global(i));
        report.defects.back().points.push_back(coords(i));
      }
      offset += n;
      continue;
    }
    bool repeated = false;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = (i + 1) % n;
      if (!(v[i] == v[j])) continue;
      repeated = true;
      report.add(Defect{DefectKind::DuplicateVertex, kValidateStage,
                        curve_name + ": vertices " + std::to_string(global(i)) + " and " + std::to_string(global(j)) +
                            " are the same point " + format_point(v[i]) + ": segment " + std::to_string(global(i)) +
                            " has zero length",
                        {global(i)}, {global(i), global(j)}, {coords(i)}});
    }
    if (finite && !repeated) {
      bool collinear = true;
      for (std::size_t i = 2; i < n && collinear; ++i) collinear = orientation_sign(v[0], v[1], v[i]) == 0;
      if (collinear) {
        report.add(Defect{DefectKind::DegenerateFacet, kValidateStage,
                          curve_name + " (vertices " + std::to_string(global(0)) + ".." + std::to_string(global(n - 1)) +
                              ") is degenerate: all its vertices are collinear, on the line through " +
                              format_point(v[0]) + " and " + format_point(v[1]) + ", so it encloses no area",
                          {}, {global(0), global(1)}, {coords(0), coords(1)}});
      }
    }
    offset += n;
  }
  if (out_of_range > kMaxRangeMessages)
    report.add(Defect{DefectKind::OutOfRange, kValidateStage,
                      "... and " + std::to_string(out_of_range - kMaxRangeMessages) + " more vertices beyond 1e75",
                      {}, {}, {}});
  return report;
}

}  // namespace imm::dim2
