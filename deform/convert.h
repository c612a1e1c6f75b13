// From the meshes `immerse mesh` builds (dim2::MeshResult, dim3::MeshResult) to the Eigen
// matrices of the deformation library, and the glued baseline of the same result. Header-only
// and CGAL-free (the dim2/dim3 mesh headers are facades).
#pragma once

#include "deform/glued.h"
#include "deform/simplex_mesh.h"
#include "dim2/mesh2.h"
#include "dim3/conforming_mesh3.h"
#include "dim3/mesh3.h"

namespace imm::deform {

inline SimplexMesh<2> to_simplex_mesh(const dim2::TriangleMesh& mesh) {
  SimplexMesh<2> out;
  out.vertices.resize(static_cast<Eigen::Index>(mesh.vertices.size()), 2);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    out.vertices.row(static_cast<Eigen::Index>(v)) << mesh.vertices[v].x, mesh.vertices[v].y;
  out.elements.resize(static_cast<Eigen::Index>(mesh.triangles.size()), 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int i = 0; i < 3; ++i) out.elements(static_cast<Eigen::Index>(t), i) = mesh.triangles[t][static_cast<std::size_t>(i)];
  return out;
}

inline SimplexMesh<3> to_simplex_mesh(const dim3::TetMesh& mesh) {
  SimplexMesh<3> out;
  out.vertices.resize(static_cast<Eigen::Index>(mesh.vertices.size()), 3);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    for (int a = 0; a < 3; ++a) out.vertices(static_cast<Eigen::Index>(v), a) = mesh.vertices[v][static_cast<std::size_t>(a)];
  out.elements.resize(static_cast<Eigen::Index>(mesh.tets.size()), 4);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int i = 0; i < 4; ++i) out.elements(static_cast<Eigen::Index>(t), i) = mesh.tets[t][static_cast<std::size_t>(i)];
  return out;
}

template <class Embedded>
std::vector<EmbeddedPoint> to_embedding(const std::vector<Embedded>& embedding) {
  std::vector<EmbeddedPoint> out;
  out.reserve(embedding.size());
  for (const Embedded& e : embedding) out.push_back({e.element, std::vector<double>(e.weights.begin(), e.weights.end())});
  return out;
}

/// A meshed input ready for deformation: the unglued mesh, the glued baseline of the same
/// background elements, and the input's embedding into each.
template <int D>
struct DeformableInput {
  SimplexMesh<D> unglued;
  std::vector<EmbeddedPoint> unglued_embedding;
  GluedMesh<D> glued;
  std::vector<EmbeddedPoint> glued_embedding;
};

inline DeformableInput<2> deformable(const dim2::MeshResult& result) {
  DeformableInput<2> in;
  in.unglued = to_simplex_mesh(result.mesh);
  in.unglued_embedding = to_embedding(result.embedding);
  in.glued = glue_copies<2>(to_simplex_mesh(result.background), result.background_triangle);
  in.glued_embedding = deform::glued_embedding(in.unglued_embedding, in.glued.element_of_copy);
  return in;
}

inline DeformableInput<3> deformable(const dim3::MeshResult& result) {
  DeformableInput<3> in;
  in.unglued = to_simplex_mesh(result.mesh);
  in.unglued_embedding = to_embedding(result.embedding);
  in.glued = glue_copies<3>(to_simplex_mesh(result.background), result.background_tet);
  in.glued_embedding = deform::glued_embedding(in.unglued_embedding, in.glued.element_of_copy);
  return in;
}

/// A conforming 3D mesh (dim3/conforming_mesh3.h): the unglued copies, and as the glued baseline
/// TetGen's tets with every copy glued back.
inline DeformableInput<3> deformable(const dim3::ConformingResult& result) {
  DeformableInput<3> in;
  in.unglued = to_simplex_mesh(result.mesh);
  in.unglued_embedding = to_embedding(result.embedding);
  in.glued = glue_copies<3>(to_simplex_mesh(result.tetrahedralization), result.source_tet);
  in.glued_embedding = deform::glued_embedding(in.unglued_embedding, in.glued.element_of_copy);
  return in;
}

}  // namespace imm::deform
