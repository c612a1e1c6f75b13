// Runs the pipeline (complex, first immersion, unglued mesh) on a procedural input and hands
// the result to the deformation library with its glued baseline.
#pragma once

#include <gtest/gtest.h>

#include "core/graph_search.h"
#include "deform/convert.h"
#include "dim2/complex2.h"
#include "dim2/mesh2.h"
#include "dim3/mesh3.h"
#include "dim3/self_connecting.h"

namespace imm::deform::test {

struct Meshed2 {
  dim2::CurveSet curves;
  DeformableInput<2> input;
};

inline Meshed2 mesh_curves(const dim2::CurveSet& curves, int resolution) {
  Meshed2 m{curves, {}};
  const dim2::BuildResult built = dim2::build_complex(curves);
  EXPECT_TRUE(built.report.ok() && built.complex && !built.inversion);
  if (!built.complex) return m;
  const SearchResult search = find_immersions(built.complex->complex, {});
  EXPECT_FALSE(search.immersions.empty());
  if (search.immersions.empty()) return m;
  dim2::MeshOptions options;
  options.resolution = resolution;
  const dim2::MeshResult result = dim2::mesh_immersion(*built.complex, search.immersions[0], options);
  EXPECT_TRUE(result.report.ok()) << result.report.summary();
  m.input = deformable(result);
  return m;
}

struct Meshed3 {
  dim3::Surface surface;
  DeformableInput<3> input;
};

inline Meshed3 mesh_surface(const dim3::Surface& surface, int resolution) {
  Meshed3 m{surface, {}};
  dim3::ImmerseOptions io;
  io.build.exact_volumes = false;
  const dim3::Immersed im = dim3::immerse_surface(surface, io);
  EXPECT_TRUE(im.build.report.ok() && im.build.complex && !im.search.immersions.empty());
  if (!im.build.complex || im.search.immersions.empty()) return m;
  dim3::MeshOptions options;
  options.resolution = resolution;
  options.threads = 1;
  const dim3::MeshResult result =
      dim3::mesh_immersion(*im.build.complex, im.search.immersions[0], options, im.input_vertices, im.input_triangles);
  EXPECT_TRUE(result.report.ok()) << result.report.summary();
  m.input = deformable(result);
  return m;
}

}  // namespace imm::deform::test
