#include "deform/glued.h"

#include <algorithm>

namespace imm::deform {

template <int D>
GluedMesh<D> glue_copies(const SimplexMesh<D>& background, const std::vector<int>& background_element) {
  std::vector<int> used(background_element);
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  GluedMesh<D> glued;
  std::vector<Eigen::Index> glued_of_background(static_cast<std::size_t>(background.element_count()), -1);
  std::vector<Eigen::Index> vertex_of(static_cast<std::size_t>(background.vertex_count()), -1);
  glued.mesh.elements.resize(static_cast<Eigen::Index>(used.size()), D + 1);
  for (std::size_t g = 0; g < used.size(); ++g) {
    glued_of_background[static_cast<std::size_t>(used[g])] = static_cast<Eigen::Index>(g);
    for (int i = 0; i < D + 1; ++i) {
      Eigen::Index& v = vertex_of[static_cast<std::size_t>(background.elements(used[g], i))];
      if (v < 0) {
        v = static_cast<Eigen::Index>(glued.background_vertex.size());
        glued.background_vertex.push_back(background.elements(used[g], i));
      }
      glued.mesh.elements(static_cast<Eigen::Index>(g), i) = static_cast<int>(v);
    }
  }
  glued.mesh.vertices.resize(static_cast<Eigen::Index>(glued.background_vertex.size()), D);
  for (std::size_t v = 0; v < glued.background_vertex.size(); ++v)
    glued.mesh.vertices.row(static_cast<Eigen::Index>(v)) = background.vertices.row(glued.background_vertex[v]);
  glued.element_of_copy.reserve(background_element.size());
  for (int b : background_element) glued.element_of_copy.push_back(glued_of_background[static_cast<std::size_t>(b)]);
  return glued;
}

std::vector<EmbeddedPoint> glued_embedding(const std::vector<EmbeddedPoint>& points,
                                           const std::vector<Eigen::Index>& element_of_copy) {
  std::vector<EmbeddedPoint> out = points;
  for (EmbeddedPoint& p : out) p.element = element_of_copy[static_cast<std::size_t>(p.element)];
  return out;
}

template GluedMesh<2> glue_copies<2>(const SimplexMesh<2>&, const std::vector<int>&);
template GluedMesh<3> glue_copies<3>(const SimplexMesh<3>&, const std::vector<int>&);

}  // namespace imm::deform
