#include "core/medit.h"

#include <optional>
#include <utility>

#include "core/text_io.h"

namespace imm {
namespace {

using namespace text;  // NOLINT(google-build-using-namespace): the shared text helpers

/// "x y ref", "x y z ref": a vertex record.
template <int D>
std::string vertex_record() {
  std::string out;
  for (int k = 0; k < D; ++k) {
    out += "xyz"[k];
    out += ' ';
  }
  return out + "ref";
}

/// "v0 v1 v2 ref", "v0 v1 v2 v3 ref": an element record.
template <int D>
std::string element_record() {
  std::string out;
  for (int k = 0; k <= D; ++k) {
    out += 'v';
    out += std::to_string(k);
    out += ' ';
  }
  return out + "ref";
}

}  // namespace

template <int D>
std::string parse_medit(std::string_view text, const std::string& file, MeditMesh<D>& mesh) {
  const std::string elements_keyword(DimTraits<D>::kMeditElements);
  const std::string element(DimTraits<D>::kElementName);
  Tokens tokens(text, {TokenRules::Hash::CommentAnywhere});
  const auto count = [&](std::string_view keyword, const std::string& what) {
    const auto n = parse_count(tokens.next());
    return std::pair{n, n ? std::string() : at(file, tokens.line()) + "expected the " + what +
                                                " count after '" + std::string(keyword) + "'"};
  };
  std::optional<std::string_view> token = tokens.next();
  while (token) {
    const std::uint64_t keyword_line = tokens.line();
    if (!starts_with_letter(*token)) {
      return at(file, keyword_line) + "expected a Medit keyword ('Vertices', '" +
             elements_keyword + "', ...), found " + quoted(*token);
    }
    const std::string_view keyword = *token;
    if (keyword == "End") break;
    if (keyword == "MeshVersionFormatted") {
      tokens.next();
    } else if (keyword == "Dimension") {
      const auto dimension = tokens.next();
      if (!dimension || parse_integer(*dimension) != D) {
        return at(file, tokens.line()) + "expected 'Dimension " + std::to_string(D) +
               "', found " + quoted(dimension.value_or("end of file")) + " (a " +
               std::to_string(D) + "D mesh is needed here)";
      }
    } else if (keyword == "Vertices") {
      const auto [n, error] = count(keyword, "vertex");
      if (!n) return error;
      reserve_records(mesh.vertices, *n, text, 2 * D + 2);
      for (long long i = 0; i < *n; ++i) {
        std::optional<std::string_view> t = tokens.next();
        if (!t) return truncated_message(file, "vertices", i, *n, keyword_line);
        const std::uint64_t line = tokens.line();
        std::array<double, D> p{};
        bool ok = true;
        for (int k = 0; k < D && ok; ++k) {
          if (k > 0) t = tokens.next();
          const auto v = t ? parse_double(*t) : std::nullopt;
          ok = v.has_value();
          if (ok) p[k] = *v;
        }
        const auto ref = ok ? tokens.next() : std::nullopt;
        if (!ok || !ref || !parse_integer(*ref)) {
          return at(file, line) + "expected vertex " + std::to_string(i + 1) + " as '" +
                 vertex_record<D>() + "'";
        }
        mesh.vertices.push_back(p);
        mesh.vertex_line.push_back(line);
      }
    } else if (keyword == elements_keyword) {
      const auto [m, error] = count(keyword, element);
      if (!m) return error;
      reserve_records(mesh.elements, *m, text, 2 * D + 4);
      for (long long e = 0; e < *m; ++e) {
        std::array<long long, D + 2> values{};
        std::uint64_t line = 0;
        for (int k = 0; k < D + 2; ++k) {
          const auto t = tokens.next();
          if (!t) return truncated_message(file, (element + "s").c_str(), e, *m, keyword_line);
          if (k == 0) line = tokens.line();
          const auto v = parse_integer(*t);
          if (!v) {
            return at(file, tokens.line()) + "expected " + element + " " + std::to_string(e + 1) +
                   " as '" + element_record<D>() + "' (integers), found " + quoted(*t);
          }
          values[k] = *v;
        }
        std::array<long long, D + 1> vertices{};
        for (int k = 0; k <= D; ++k) vertices[k] = values[k] - 1;
        mesh.elements.push_back(vertices);
        mesh.reference.push_back(static_cast<int>(values[D + 1]));
        mesh.element_line.push_back(line);
      }
    } else {
      // Every other section holds records of numbers only: it ends at the next keyword,
      // whatever its record size.
      do {
        token = tokens.next();
      } while (token && !starts_with_letter(*token));
      continue;
    }
    token = tokens.next();
  }
  return {};
}

template <int D>
std::string format_medit(const std::vector<std::array<double, D>>& vertices,
                         const std::vector<std::array<int, D + 1>>& elements,
                         const std::vector<int>& reference) {
  std::string out = "MeshVersionFormatted 2\nDimension " + std::to_string(D) + "\nVertices\n" +
                    std::to_string(vertices.size()) + "\n";
  out.reserve(vertices.size() * (22 * D + 4) + elements.size() * (10 * D + 12));
  for (const std::array<double, D>& p : vertices) {
    for (int k = 0; k < D; ++k) out += format_number(p[k]) + ' ';
    out += "0\n";
  }
  out += std::string(DimTraits<D>::kMeditElements) + "\n" + std::to_string(elements.size()) + "\n";
  for (std::size_t e = 0; e < elements.size(); ++e) {
    for (int v : elements[e]) out += std::to_string(v + 1ll) + ' ';
    out += std::to_string(e < reference.size() ? reference[e] : 0) + '\n';
  }
  out += "End\n";
  return out;
}

template std::string parse_medit<2>(std::string_view, const std::string&, MeditMesh<2>&);
template std::string parse_medit<3>(std::string_view, const std::string&, MeditMesh<3>&);
template std::string format_medit<2>(const std::vector<std::array<double, 2>>&,
                                     const std::vector<std::array<int, 3>>&,
                                     const std::vector<int>&);
template std::string format_medit<3>(const std::vector<std::array<double, 3>>&,
                                     const std::vector<std::array<int, 4>>&,
                                     const std::vector<int>&);

}  // namespace imm
