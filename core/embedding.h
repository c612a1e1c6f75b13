// Where the input vertices sit in an output mesh (the .emb file, DESIGN §3), for the triangles
// of 2D meshing and the tets of 3D meshing alike.
#pragma once

#include <array>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace imm {

/// Where an input vertex sits in the output: element (0-based, output order; -1 when in none)
/// and the barycentric weights of its background element that reproduce its position.
template <int D>
struct EmbeddedVertex {
  int element = -1;
  std::array<double, D + 1> weights{};
};

/// .emb text: the number of input vertices, then `element w0 .. wD` per vertex (max_digits10).
template <int D>
std::string format_embedding(const std::vector<EmbeddedVertex<D>>& embedding) {
  std::ostringstream os;
  os << std::setprecision(std::numeric_limits<double>::max_digits10);
  os << embedding.size() << '\n';
  for (const EmbeddedVertex<D>& e : embedding) {
    os << e.element;
    for (double w : e.weights) os << ' ' << w;
    os << '\n';
  }
  return os.str();
}

}  // namespace imm
