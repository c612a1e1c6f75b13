// `immerse deform` and `immerse weights` (paper §8): the unglued mesh of IN (or, with --glued,
// the naive glued baseline of the same background elements) deformed by ARAP or FEM under
// handles from a JSON file, or weighed by bounded biharmonic weights; the deformed input follows
// through the embedding. The same code for 2D curves (triangles) and 3D surfaces (tets).
#include "app/cli_deform.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>

#include "deform/arap.h"
#include "deform/convert.h"
#include "deform/fem.h"
#include "deform/vtu.h"
#include "deform/weights.h"
#include "dim2/complex2.h"
#include "dim2/curves.h"
#include "dim2/generators.h"
#include "dim2/mesh2.h"
#include "dim3/generators3.h"
#include "dim3/self_connecting.h"

namespace imm::cli {

namespace {

using deform::DeformableInput;
using deform::SimplexMesh;

/// One handle of the JSON file: a vertex selection and what happens to it.
struct HandleSpec {
  std::vector<double> box_min, box_max;  ///< empty: no box
  std::vector<long long> vertices;       ///< explicit vertex ids (of the mesh deformed)
  std::vector<double> displacement;      ///< empty: fixed
};

struct HandleFile {
  std::vector<HandleSpec> handles;
  deform::Material material;
  double time_step = 1.0 / 30.0;
  std::vector<double> gravity;
  std::vector<double> ground_normal;
  double ground_offset = 0.0;
  std::string error;  ///< non-empty: invalid file (exit 2)
};

std::vector<double> numbers(const Json& j, std::size_t dimension, const std::string& what, std::string& error) {
  std::vector<double> out;
  if (!j.is_array() || j.size() != dimension) {
    error = what + ": expected an array of " + std::to_string(dimension) + " numbers";
    return out;
  }
  for (const Json& x : j) {
    if (!x.is_number() || !std::isfinite(x.get<double>())) {
      error = what + ": expected finite numbers";
      return {};
    }
    out.push_back(x.get<double>());
  }
  return out;
}

/// Empty when every key of the object `j` is one of `known`, else the message naming the first
/// other key: a misspelt "displacment" left its handle fixed without a word.
std::string unknown_key(const Json& j, std::initializer_list<const char*> known, const std::string& where) {
  for (const auto& [key, value] : j.items()) {
    bool ok = false;
    for (const char* k : known) ok = ok || key == k;
    if (ok) continue;
    std::string list;
    for (const char* k : known) list += std::string(list.empty() ? "" : ", ") + '"' + k + '"';
    return where + ": unknown key \"" + key + "\" (expected " + list + ")";
  }
  return {};
}

HandleFile read_handles(const std::string& path, std::size_t dimension) {
  HandleFile file;
  std::ifstream in(path);
  if (!in) {
    file.error = "cannot read the handle file '" + path + "'";
    return file;
  }
  Json j;
  try {
    j = Json::parse(in);
  } catch (const std::exception& e) {
    file.error = "the handle file '" + path + "' is not valid JSON: " + e.what();
    return file;
  }
  std::string& error = file.error;
  if (!j.is_object() || !j.contains("handles") || !j["handles"].is_array() || j["handles"].empty()) {
    error = "the handle file '" + path + "' needs a non-empty array \"handles\"";
    return file;
  }
  error = unknown_key(j, {"handles", "material", "time_step", "gravity", "ground"}, "the handle file '" + path + "'");
  if (error.empty() && j.contains("material") && j["material"].is_object())
    error = unknown_key(j["material"], {"youngs_modulus", "poisson_ratio", "density"}, "material");
  if (error.empty() && j.contains("ground") && j["ground"].is_object())
    error = unknown_key(j["ground"], {"normal", "offset"}, "ground");
  if (!error.empty()) return file;
  for (std::size_t k = 0; k < j["handles"].size() && error.empty(); ++k) {
    const Json& h = j["handles"][k];
    const std::string where = "handle " + std::to_string(k);
    HandleSpec spec;
    if (!h.is_object()) {
      error = where + ": expected an object";
      break;
    }
    error = unknown_key(h, {"box", "vertices", "displacement", "fixed"}, where);
    if (error.empty() && h.contains("fixed") && (!h["fixed"].is_boolean() || (h["fixed"].get<bool>() && h.contains("displacement"))))
      error = where + ": \"fixed\" is true or false, and a fixed handle has no displacement";
    if (!error.empty()) break;
    if (h.contains("box")) {
      if (!h["box"].is_object() || !h["box"].contains("min") || !h["box"].contains("max")) {
        error = where + ": \"box\" needs \"min\" and \"max\"";
        break;
      }
      spec.box_min = numbers(h["box"]["min"], dimension, where + " box min", error);
      if (error.empty()) spec.box_max = numbers(h["box"]["max"], dimension, where + " box max", error);
    }
    if (h.contains("vertices")) {
      if (!h["vertices"].is_array()) error = where + ": \"vertices\" must be an array of vertex ids";
      else
        for (const Json& v : h["vertices"]) {
          if (!v.is_number_integer()) error = where + ": vertex ids must be integers";
          else if (v.is_number_unsigned() && v.get<unsigned long long>() > static_cast<unsigned long long>(std::numeric_limits<long long>::max()))
            error = where + ": vertex " + v.dump() + " is not a mesh vertex";  // read as a long long, it was -1
          else spec.vertices.push_back(v.get<long long>());
        }
    }
    if (error.empty() && spec.box_min.empty() && !h.contains("vertices"))
      error = where + ": select vertices with \"box\" or \"vertices\"";
    if (error.empty() && h.contains("displacement"))
      spec.displacement = numbers(h["displacement"], dimension, where + " displacement", error);
    file.handles.push_back(std::move(spec));
  }
  if (!error.empty()) return file;
  try {
    if (j.contains("material")) {
      const Json& m = j["material"];
      file.material.youngs_modulus = m.value("youngs_modulus", file.material.youngs_modulus);
      file.material.poisson_ratio = m.value("poisson_ratio", file.material.poisson_ratio);
      file.material.density = m.value("density", file.material.density);
      if (!(file.material.youngs_modulus > 0) || !(file.material.density > 0) || !(file.material.poisson_ratio > -1) ||
          !(file.material.poisson_ratio < 0.5))
        error = "material: need youngs_modulus > 0, density > 0, -1 < poisson_ratio < 0.5";
    }
    file.time_step = j.value("time_step", file.time_step);
    if (!(file.time_step > 0)) error = "time_step must be > 0";
    if (error.empty() && j.contains("gravity")) file.gravity = numbers(j["gravity"], dimension, "gravity", error);
    if (error.empty() && j.contains("ground")) {
      file.ground_normal = numbers(j["ground"].value("normal", Json()), dimension, "ground normal", error);
      file.ground_offset = j["ground"].value("offset", 0.0);
      if (error.empty() && std::all_of(file.ground_normal.begin(), file.ground_normal.end(), [](double x) { return x == 0.0; }))
        error = "ground: the normal is the zero vector (it gives the ground's up direction)";
      if (error.empty() && !std::isfinite(file.ground_offset)) error = "ground: the offset must be a finite number";
    }
  } catch (const std::exception& e) {
    error = std::string("the handle file has a value of the wrong type: ") + e.what();
  }
  return file;
}

/// The vertices each handle selects on `mesh`. Empty selections, ids out of range and vertices
/// selected twice are errors.
template <int D>
std::vector<std::vector<Eigen::Index>> select(const SimplexMesh<D>& mesh, const HandleFile& file, std::string& error) {
  std::vector<std::vector<Eigen::Index>> out(file.handles.size());
  std::vector<int> owner(static_cast<std::size_t>(mesh.vertex_count()), -1);
  for (std::size_t k = 0; k < file.handles.size() && error.empty(); ++k) {
    const HandleSpec& h = file.handles[k];
    std::vector<Eigen::Index> picked;
    for (long long v : h.vertices) {
      if (v < 0 || v >= mesh.vertex_count()) {
        error = "handle " + std::to_string(k) + ": vertex " + std::to_string(v) + " is not a mesh vertex (the mesh has " +
                std::to_string(mesh.vertex_count()) + ")";
        return out;
      }
      picked.push_back(static_cast<Eigen::Index>(v));
    }
    if (!h.box_min.empty())
      for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v) {
        bool inside = true;
        for (int a = 0; a < D; ++a)
          inside = inside && mesh.vertices(v, a) >= h.box_min[static_cast<std::size_t>(a)] &&
                   mesh.vertices(v, a) <= h.box_max[static_cast<std::size_t>(a)];
        if (inside) picked.push_back(v);
      }
    std::sort(picked.begin(), picked.end());
    picked.erase(std::unique(picked.begin(), picked.end()), picked.end());
    if (picked.empty()) error = "handle " + std::to_string(k) + " selects no mesh vertex";
    for (Eigen::Index v : picked) {
      if (owner[static_cast<std::size_t>(v)] >= 0) {
        error = "vertex " + std::to_string(v) + " is selected by handles " + std::to_string(owner[static_cast<std::size_t>(v)]) +
                " and " + std::to_string(k);
        return out;
      }
      owner[static_cast<std::size_t>(v)] = static_cast<int>(k);
    }
    out[k] = std::move(picked);
  }
  return out;
}

/// How a dimension writes and checks its deformed input.
struct InputOps {
  std::string extension;                                        ///< ".txt" / ".obj"
  std::function<std::string(const Eigen::MatrixXd&)> format;    ///< the deformed input file
  std::function<std::size_t(const Eigen::MatrixXd&)> crossings; ///< exact self-intersection count
  /// The coordinate range of the dimension's inputs: a deformed input beyond it (a displacement of
  /// 1e300) is refused instead of counted, since the exact checks take only valid inputs.
  double max_coordinate = 0.0;
};

std::string frame_name(const std::string& dir, const std::string& stem, int frame, const std::string& ext) {
  std::ostringstream os;
  os << dir << '/' << stem << '_' << std::setw(3) << std::setfill('0') << frame << ext;
  return os.str();
}

template <int D>
int run_deform(Session& s, const CommandLine& cl, const SimplexMesh<D>& mesh, const std::vector<deform::EmbeddedPoint>& embedding,
               const std::vector<int>& reference, const HandleFile& file, const InputOps& ops) {
  std::string error;
  const std::vector<std::vector<Eigen::Index>> selected = select<D>(mesh, file, error);
  if (!error.empty()) {
    s.err() << "immerse deform: " << error << '\n';
    return kExitInvalidInput;
  }
  std::vector<Eigen::Index> handles;
  std::vector<Eigen::Matrix<double, 1, D>> displacement;
  for (std::size_t k = 0; k < selected.size(); ++k)
    for (Eigen::Index v : selected[k]) {
      handles.push_back(v);
      Eigen::Matrix<double, 1, D> d = Eigen::Matrix<double, 1, D>::Zero();
      for (int a = 0; a < D && !file.handles[k].displacement.empty(); ++a) d(a) = file.handles[k].displacement[static_cast<std::size_t>(a)];
      displacement.push_back(d);
    }
  const std::string method = cl.value("--method").value_or("arap");
  const int frames = static_cast<int>(cl.integer("--frames").value_or(10));
  const std::string dir = *cl.value("-o");

  deform::ArapData<D> arap;
  deform::FemData<D> fem;
  deform::FemOptions fem_options;
  deform::FemSolver fem_solver;  // the analysis and the last factorization, kept from frame to frame
  if (method == "arap") {
    arap = s.timed("precompute", [&] { return deform::arap_precompute<D>(mesh, handles); });
    error = arap.error;
  } else {
    fem = s.timed("precompute", [&] { return deform::fem_precompute<D>(mesh, handles, file.material); });
    error = fem.error;
    // The Newton matrix's pattern and symbolic analysis, once, in the precompute stage: the
    // frames' "solve" times are the steps alone.
    if (error.empty()) s.timed("precompute", [&] { return deform::fem_prepare<D>(fem, fem_solver); });
    fem_options.material = file.material;
    fem_options.time_step = file.time_step;
    if (!file.gravity.empty()) fem_options.gravity = Eigen::Map<const Eigen::VectorXd>(file.gravity.data(), D);
    if (!file.ground_normal.empty()) {
      fem_options.ground_normal = Eigen::Map<const Eigen::VectorXd>(file.ground_normal.data(), D).normalized();
      fem_options.ground_offset = file.ground_offset;
    }
  }
  if (!error.empty()) {
    s.err() << "immerse deform: " << error << '\n';
    return kExitInvalidInput;
  }

  Json report = Json::object();
  report["method"] = method;
  report["dimension"] = D;
  report["vertices"] = mesh.vertex_count();
  report["elements"] = mesh.element_count();
  report["handle_vertices"] = handles.size();
  Json frame_reports = Json::array();
  Eigen::MatrixXd x = mesh.vertices;
  deform::FemState<D> state{mesh.vertices, Eigen::MatrixXd::Zero(mesh.vertex_count(), D)};
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(handles.size()), D);
  for (int f = 1; f <= frames; ++f) {
    const double t = static_cast<double>(f) / frames;
    for (std::size_t k = 0; k < handles.size(); ++k)
      targets.row(static_cast<Eigen::Index>(k)) = mesh.vertices.row(handles[k]) + t * displacement[k];
    Json fr = Json::object();
    fr["frame"] = f;
    if (method == "arap") {
      const deform::ArapOptions options{.max_iterations = static_cast<int>(cl.integer("--iterations").value_or(50))};
      const deform::ArapReport r = s.timed("solve", [&] { return deform::arap_solve<D>(arap, targets, x, options); });
      fr["iterations"] = r.iterations;
      fr["energy"] = r.energies.back();
    } else if (method == "fem") {
      const deform::FemReport r = s.timed("solve", [&] { return deform::fem_step<D>(fem, state, targets, fem_options, &fem_solver); });
      if (!r.error.empty()) {
        s.err() << "immerse deform: frame " << f << ": " << r.error << '\n';
        return kExitInvalidInput;
      }
      x = state.positions;
      fr["newton_iterations"] = r.newton_iterations;
      fr["converged"] = r.converged;
      fr["elastic_energy"] = deform::elastic_energy<D>(fem, x, file.material);
    } else {
      const deform::FemReport r = s.timed("solve", [&] { return deform::fem_static<D>(fem, x, targets, fem_options, &fem_solver); });
      if (!r.error.empty()) {
        s.err() << "immerse deform: " << r.error << '\n';
        return kExitInvalidInput;
      }
      fr["newton_iterations"] = r.newton_iterations;
      fr["converged"] = r.converged;
      fr["elastic_energy"] = deform::elastic_energy<D>(fem, x, file.material);
    }
    const Eigen::MatrixXd points = deform::embedded_positions(x, mesh.elements, embedding);
    if (!(points.allFinite() && points.cwiseAbs().maxCoeff() <= ops.max_coordinate) || !x.allFinite()) {
      s.err() << "immerse deform: frame " << f << ": the deformed input leaves the coordinate range of inputs (|x| <= "
              << ops.max_coordinate << "); the handles' displacements or forces are too large\n";
      return kExitInvalidInput;
    }
    const std::size_t inverted = deform::inverted_elements<D>(x, mesh.elements).size();
    const std::size_t crossings = s.timed("check", [&] { return ops.crossings(points); });
    fr["inverted_elements"] = inverted;
    fr["input_self_intersections"] = crossings;
    s.out() << "frame " << f << ": " << inverted << " inverted elements, " << crossings
            << " self-intersecting pairs in the deformed input\n";
    deform::VtuFields fields;
    fields.cell_integers.emplace_back("reference", reference);
    if (!s.write(frame_name(dir, "mesh", f, ".vtu"), deform::format_vtu(x, mesh.elements, fields), "deformed mesh") ||
        !s.write(frame_name(dir, "input", f, ops.extension), ops.format(points), "deformed input"))
      return kExitInternalError;
    frame_reports.push_back(fr);
  }
  report["frames"] = frame_reports;
  report["timings_ms"] = s.timings_json();
  if (auto path = cl.value("--json"); path && !s.write(*path, report.dump(2) + "\n", "report")) return kExitInternalError;
  s.set_counts(std::to_string(mesh.element_count()) + " elements, " + std::to_string(frames) + " frames");
  return kExitOk;
}

template <int D>
int run_weights(Session& s, const CommandLine& cl, const SimplexMesh<D>& mesh, const std::vector<int>& reference,
                const HandleFile& file) {
  std::string error;
  const std::vector<std::vector<Eigen::Index>> selected = select<D>(mesh, file, error);
  if (!error.empty()) {
    s.err() << "immerse weights: " << error << '\n';
    return kExitInvalidInput;
  }
  const deform::WeightsResult w = s.timed("weights", [&] { return deform::bounded_biharmonic_weights<D>(mesh, selected); });
  if (!w.ok()) {
    s.err() << "immerse weights: " << w.error << '\n';
    return kExitInvalidInput;
  }
  deform::VtuFields fields;
  for (Eigen::Index k = 0; k < w.weights.cols(); ++k) fields.point_scalars.emplace_back("weight_" + std::to_string(k), w.weights.col(k));
  const Eigen::VectorXd distance = s.timed("geodesic", [&] { return deform::heat_geodesic<D>(mesh, selected[0]); });
  fields.point_scalars.emplace_back("distance_0", distance);
  fields.cell_integers.emplace_back("reference", reference);
  if (!s.write(*cl.value("-o"), deform::format_vtu(mesh.vertices, mesh.elements, fields), "weights and distance"))
    return kExitInternalError;
  s.out() << w.weights.cols() << " weights on " << mesh.vertex_count() << " vertices (active-set iterations:";
  for (int i : w.active_set_iterations) s.out() << ' ' << i;
  s.out() << ")\n";
  s.set_counts(std::to_string(mesh.element_count()) + " elements, " + std::to_string(w.weights.cols()) + " handles");
  return kExitOk;
}

/// The mesh deformed: the unglued mesh, or with --glued the baseline (references: -1).
template <int D>
int on_mesh(Session& s, const CommandLine& cl, const std::string& command, const DeformableInput<D>& in,
            const std::vector<int>& unglued_reference, const InputOps& ops, const HandleFile& file) {
  const bool glued = cl.has("--glued");
  const SimplexMesh<D>& mesh = glued ? in.glued.mesh : in.unglued;
  const std::vector<int> reference = glued ? std::vector<int>(static_cast<std::size_t>(mesh.element_count()), -1) : unglued_reference;
  if (command == "weights") return run_weights<D>(s, cl, mesh, reference, file);
  return run_deform<D>(s, cl, mesh, glued ? in.glued_embedding : in.unglued_embedding, reference, file, ops);
}

int no_immersion(Session& s, const std::string& command, const std::string& path, const SearchResult& r, std::size_t k) {
  // Immersible, with fewer immersions than --immersion K asks for: the usage error of `mesh` (it
  // said "has no immersion to mesh (immersible)", exit 3).
  if (r.status == ImmersionStatus::Immersible)
    return usage_error(s.env(), command, immersion_index_message(k, path, r.immersions.size(), r.complete, kProgramOptions));
  s.err() << "immerse " << command << ": '" << path << "' has no immersion to mesh (" << to_string(r.status)
          << "); 'immerse immersions' explains why\n";
  return kExitNotImmersible;
}

}  // namespace

int command_deform_or_weights(Session& s, const CommandLine& cl, const std::string& command) {
  if (!cl.has("--handles")) return usage_error(s.env(), command, "--handles H.json is required");
  if (!cl.has("-o")) return usage_error(s.env(), command, "-o is required");
  const std::string& path = cl.positional[0];
  const std::size_t k = static_cast<std::size_t>(cl.integer("--immersion").value_or(0));
  if (command == "deform") {
    const std::string method = cl.value("--method").value_or("arap");
    if (method != "arap" && method != "fem" && method != "fem-static")
      return usage_error(s.env(), command, "--method expects 'arap', 'fem' or 'fem-static', got '" + method + "'");
  }
  SearchOptions search;
  search.max_immersions = k + 1;
  const bool surface = is_surface_file(path);
  MeshChoice choice;  // the options and checks of `immerse mesh`
  if (const std::string error = parse_mesh_choice(cl, surface, choice); !error.empty())
    return usage_error(s.env(), command, error);
  // The handle file is read before meshing (a typo in it costs no meshing time).
  const HandleFile file = read_handles(*cl.value("--handles"), surface ? 3 : 2);
  if (!file.error.empty()) {
    s.err() << "immerse " << command << ": " << file.error << '\n';
    return kExitInvalidInput;
  }
  if (surface) {
    dim3::SurfaceReadResult read = s.timed("read", [&] { return dim3::read_surface(path); });
    if (!read.report.ok()) {
      print_defects(s, path, read.report);
      return kExitInvalidInput;
    }
    dim3::ImmerseOptions io;
    io.build.exact_volumes = false;
    io.search = search;
    const dim3::Immersed im = s.timed("immerse", [&] { return dim3::immerse_surface(read.surface, io); });
    if (!im.build.report.ok()) {
      print_defects(s, path, im.build.report);
      return kExitInvalidInput;
    }
    if (im.build.inversion || im.search.immersions.size() <= k) return no_immersion(s, command, path, im.search, k);
    const dim3::MeshOptions options = choice.options3();
    DeformableInput<3> in;
    std::vector<int> reference;
    if (choice.conforming) {
      dim3::ConformingOptions conforming_options = choice.conforming3;
      if (const std::string error = default_edge_length(read.surface, options.resolution, conforming_options); !error.empty())
        return usage_error(s.env(), command, error);
      const dim3::ConformingResult m = s.timed("mesh", [&] {
        return dim3::mesh_conforming(*im.build.complex, im.search.immersions[k], conforming_options, im.input_vertices,
                                      im.input_triangles);
      });
      if (!m.report.ok()) {
        print_defects(s, path, m.report);
        return kExitInvalidInput;
      }
      in = deform::deformable(m);
      reference = m.mesh.reference;
    } else {
      const dim3::MeshResult m = s.timed("mesh", [&] {
        return dim3::mesh_immersion(*im.build.complex, im.search.immersions[k], options, im.input_vertices, im.input_triangles);
      });
      if (!m.report.ok()) {
        print_defects(s, path, m.report);
        return kExitInvalidInput;
      }
      in = deform::deformable(m);
      reference = m.mesh.reference;
    }
    dim3::Surface surface = read.surface;
    InputOps ops;
    ops.extension = ".obj";
    ops.max_coordinate = dim3::kMaxCoordinate3;
    const auto moved = [surface](const Eigen::MatrixXd& p) {
      dim3::Surface out = surface;
      for (std::size_t v = 0; v < out.vertices.size(); ++v)
        for (int a = 0; a < 3; ++a) out.vertices[v][static_cast<std::size_t>(a)] = p(static_cast<Eigen::Index>(v), a);
      return out;
    };
    ops.format = [moved](const Eigen::MatrixXd& p) { return dim3::format_obj(moved(p)); };
    ops.crossings = [moved](const Eigen::MatrixXd& p) { return dim3::check_generic_surface(moved(p)).intersecting_pairs; };
    return on_mesh<3>(s, cl, command, in, reference, ops, file);
  }
  dim2::ReadResult read = s.timed("read", [&] { return dim2::read_curves(path); });
  if (!read.report.ok()) {
    print_defects(s, path, read.report);
    return kExitInvalidInput;
  }
  const dim2::BuildResult built = s.timed("complex", [&] { return dim2::build_complex(read.curves); });
  if (!built.report.ok()) {
    print_defects(s, path, built.report);
    return kExitInvalidInput;
  }
  SearchResult r;
  if (!built.inversion) r = s.timed("search", [&] { return find_immersions(built.complex->complex, search); });
  if (built.inversion || r.immersions.size() <= k) return no_immersion(s, command, path, r, k);
  const dim2::MeshOptions options = choice.options2();
  const dim2::MeshResult m = s.timed("mesh", [&] { return dim2::mesh_immersion(*built.complex, r.immersions[k], options); });
  if (!m.report.ok()) {
    print_defects(s, path, m.report);
    return kExitInvalidInput;
  }
  const DeformableInput<2> in = deform::deformable(m);
  const dim2::CurveSet curves = read.curves;
  const auto moved = [curves](const Eigen::MatrixXd& p) {
    dim2::CurveSet out = curves;
    Eigen::Index i = 0;
    for (dim2::Curve& c : out.curves)
      for (dim2::Point& q : c.vertices) q = {p(i, 0), p(i, 1)}, ++i;
    return out;
  };
  InputOps ops;
  ops.extension = ".txt";
  ops.max_coordinate = dim2::kMaxCoordinate2;
  ops.format = [moved](const Eigen::MatrixXd& p) { return dim2::format_curves_text(moved(p)); };
  ops.crossings = [moved](const Eigen::MatrixXd& p) { return dim2::check_generic(moved(p)).crossings; };
  return on_mesh<2>(s, cl, command, in, m.mesh.reference, ops, file);
}

CommandSpec deform_command_spec() {
  CommandSpec spec;
  spec.name = "deform";
  spec.usage =
      "deform IN --handles H.json -o DIR [--method arap|fem|fem-static] [--frames N] [--iterations N]\n"
      "                   [--glued] [--resolution N [--surface-resolution M [--gap-resolution G]] | --background FILE\n"
      "                   | --conforming] [--immersion K] [--json OUT]";
  spec.positional_help = "a 2D curve file or a 3D surface (as for 'immerse mesh')";
  spec.description =
      "Meshes immersion K of IN as 'immerse mesh' does, then deforms the unglued mesh (paper §8): ARAP\n"
      "(local/global), FEM (co-rotational, implicit Euler per frame) or FEM statics, with the handles of\n"
      "H.json moved by their displacement, ramped over the frames. --glued deforms the naive glued mesh of\n"
      "the same background elements instead, for comparison. Per frame DIR/mesh_NNN.vtu and the deformed\n"
      "input DIR/input_NNN.txt (2D) or .obj (3D); stdout reports inverted elements and the exact count of\n"
      "self-intersecting pairs of the deformed input.\n"
      "H.json: {\"handles\": [{\"box\": {\"min\": [..], \"max\": [..]}, \"displacement\": [..]},\n"
      "                      {\"vertices\": [ids], \"fixed\": true}, ...],\n"
      "         \"material\": {\"youngs_modulus\", \"poisson_ratio\", \"density\"}, \"time_step\",\n"
      "         \"gravity\": [..], \"ground\": {\"normal\": [..], \"offset\": h}}  (a handle without\n"
      "displacement stays fixed; the last four keys are for FEM).\n";
  spec.options = {
      {"--handles", ValueKind::Text, "H.json", "the handles (required)"},
      {"-o", ValueKind::Text, "DIR", "the output directory (required)"},
      {"--method", ValueKind::Text, "arap|fem|fem-static", "the solver (default arap)"},
      {"--frames", ValueKind::Integer, "N", "frames (default 10): the displacements ramp over them", 1, 100'000},
      {"--iterations", ValueKind::Integer, "N", "ARAP local/global iterations per frame (default 50)", 1, 1'000'000},
      {"--glued", ValueKind::Flag, "", "deform the glued baseline instead of the unglued mesh"},
      {"--immersion", ValueKind::Integer, "K", "which immersion (default 0)", 0, 1'000'000},
      {"--json", ValueKind::Text, "OUT", "per frame: energy or Newton iterations, inverted elements, self-intersections; timings"},
  };
  const std::vector<OptionSpec> mesher = mesh_choice_options(false);
  spec.options.insert(spec.options.end() - 2, mesher.begin(), mesher.end());
  spec.footer =
      "Exit codes: 0 ok, 2 invalid input or handle file (bad JSON, empty selection, a vertex in two\n"
      "handles, a part of the mesh without handle for statics), 3 not immersible, 64 bad command line.\n";
  return spec;
}

CommandSpec weights_command_spec() {
  CommandSpec spec;
  spec.name = "weights";
  spec.usage = "weights IN --handles H.json -o OUT.vtu [--glued]\n"
               "                   [--resolution N [--surface-resolution M [--gap-resolution G]] | --background FILE | --conforming]\n"
               "                   [--immersion K]";
  spec.positional_help = "a 2D curve file or a 3D surface (as for 'immerse mesh')";
  spec.description =
      "Bounded biharmonic weights (Jacobson et al. 2011) of the handles of H.json (their selections; see\n"
      "'immerse deform --help') on the unglued mesh of IN (--glued: the glued baseline), and the\n"
      "heat-method geodesic distance from handle 0, as point data weight_K and distance_0 of OUT.vtu.\n";
  spec.options = {
      {"--handles", ValueKind::Text, "H.json", "the handles (required)"},
      {"-o", ValueKind::Text, "OUT.vtu", "the mesh with the weights (required)"},
      {"--glued", ValueKind::Flag, "", "the glued baseline instead of the unglued mesh"},
      {"--immersion", ValueKind::Integer, "K", "which immersion (default 0)", 0, 1'000'000},
  };
  const std::vector<OptionSpec> mesher = mesh_choice_options(false);
  spec.options.insert(spec.options.end() - 1, mesher.begin(), mesher.end());
  spec.footer = "Exit codes: 0 ok, 2 invalid input or handle file, 3 not immersible, 64 bad command line.\n";
  return spec;
}

}  // namespace imm::cli
