// Shared plumbing of the figure programs: `--out DIR` and `--quick`, the 2D pipeline on a named
// generator, atomic output files and a self-check that fails the program (exit 1) when the
// reproduced fact differs from the paper's. Each fig_NN_<slug>.cpp states its paper item.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/graph_search.h"
#include "dim2/complex2.h"
#include "dim2/generators.h"
#include "dim2/mesh2.h"
#include "dim2/svg.h"

namespace imm::figures {

struct FigureArgs {
  std::string out;     ///< output directory
  bool quick = false;  ///< small sizes, for the CTest label "figures"
};

inline FigureArgs parse_args(int argc, char** argv, const std::string& name) {
  FigureArgs args{"out/figures/" + name, false};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      args.quick = true;
    } else if (a == "--out" && i + 1 < argc) {
      args.out = argv[++i];
    } else {
      std::cerr << "usage: " << name << " [--out DIR] [--quick]\n";
      std::exit(64);
    }
  }
  const WriteStatus dir = ensure_directory(args.out);
  if (!dir.ok()) throw std::runtime_error(dir.error);
  return args;
}

inline void write(const FigureArgs& args, const std::string& file, const std::string& content) {
  const WriteStatus status = write_file_atomic(args.out + "/" + file, content);
  if (!status.ok()) throw std::runtime_error(status.error);
  std::cout << "wrote " << args.out << "/" << file << '\n';
}

/// Fails the figure program when a reproduced fact differs from the paper's.
inline void expect(bool ok, const std::string& what) {
  if (!ok) throw std::runtime_error("figure check failed: " + what);
}

/// A named generator through the exact complex and the search (all immersions).
struct CurveRun {
  dim2::CurveSet curves;
  dim2::BuildResult built;
  SearchResult search;
};

inline CurveRun run_curve(const std::string& generator, const std::vector<std::string>& params = {}) {
  CurveRun run;
  const dim2::GenerateResult generated = dim2::generate(generator, params);
  if (!generated.ok()) throw std::runtime_error(generated.error);
  run.curves = generated.curves;
  run.built = dim2::build_complex(run.curves);
  if (!run.built.report.ok()) throw std::runtime_error(run.built.report.summary());
  if (run.built.complex && !run.built.inversion) {
    SearchOptions options;
    options.max_immersions = 0;
    run.search = find_immersions(run.built.complex->complex, options);
  }
  return run;
}

/// Meshes one immersion at `resolution` (fails the figure on any defect) and writes the mesh
/// pulled apart as `<stem>.svg` and the Medit file `<stem>.mesh`.
inline dim2::MeshResult mesh_and_write(const FigureArgs& args, const dim2::Complex2& complex,
                                       const Immersion& immersion, int resolution,
                                       const std::string& stem) {
  dim2::MeshOptions options;
  options.resolution = resolution;
  dim2::MeshResult mesh = dim2::mesh_immersion(complex, immersion, options);
  expect(mesh.report.ok(), mesh.report.summary());
  write(args, stem + ".svg", dim2::format_mesh_svg(complex, immersion, mesh));
  write(args, stem + ".mesh", dim2::format_medit_2d(mesh.mesh));
  return mesh;
}

/// Runs a figure's body, mapping failures to exit code 1 with the reason.
template <class Body>
int main_guard(Body&& body) {
  try {
    body();
    return 0;
  } catch (const std::exception& e) {
    std::cerr << e.what() << '\n';
    return 1;
  }
}

}  // namespace imm::figures
