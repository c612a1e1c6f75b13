// The 3D commands of `immerse` (app/cli.h): check, cells, immersions and generate on closed
// triangle meshes (OBJ, OFF, PLY, STL). The 2D commands dispatch here when the input is a
// surface (is_surface_file); messages, exit codes, JSON shapes and the summary line follow the
// 2D ones (app/cli.cpp), with triangles where 2D has segments and volumes where it has areas.
//
// Library results map to exit codes as in 2D: a ValidationReport with defects (the reader's, the
// validator's, or the exact intersection's non-generic contacts) -> 2; an inversion, a proven
// non-immersible input, a self-connecting cell left uncut, an exhausted budget -> 3.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli_common.h"
#include "dim3/complex3.h"
#include "dim3/generators3.h"
#include "dim3/mesh3.h"
#include "dim3/self_connecting.h"
#include "dim3/surface.h"

namespace imm::cli {

ObjElements scan_obj_elements(const std::string& path) {
  ObjElements found;
  if (!unreadable_file_kind(path).empty()) return found;  // a device: the reader refuses it
  std::ifstream in(path, std::ios::binary);
  if (!in) return found;  // the reader reports it
  // A state machine over fixed-size chunks, never a whole line in memory: a file without line
  // breaks (or an endless stream) costs no more than its bytes read. Stops at a NUL byte, which
  // no OBJ text holds (the reader then says what the file is).
  enum class State { LineStart, Tag, Rest } state = State::LineStart;
  char tag = 0;
  std::vector<char> buffer(1 << 16);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const std::streamsize n = in.gcount();
    if (n <= 0) break;
    for (std::streamsize i = 0; i < n; ++i) {
      const char c = buffer[static_cast<std::size_t>(i)];
      if (c == '\0') return found;
      if (c == '\n') {
        state = State::LineStart;
        continue;
      }
      switch (state) {
        case State::LineStart:
          if (c == ' ' || c == '\t') break;
          tag = c;
          state = State::Tag;
          break;
        case State::Tag:
          if (c == ' ' || c == '\t') {
            found.faces += tag == 'f' ? 1 : 0;
            found.lines += tag == 'l' ? 1 : 0;
          }
          state = State::Rest;
          break;
        case State::Rest:
          break;
      }
    }
  }
  return found;
}

bool is_surface_file(const std::string& path) {
  const std::string ext = extension_of(path);
  if (ext == ".off" || ext == ".ply" || ext == ".stl") return true;
  if (ext != ".obj") return false;
  // Faces make a surface; 'l' lines beside them are loose edges (exporters write them for
  // seams, normals, wireframes) and the surface reader ignores them (read_input notes it).
  return scan_obj_elements(path).faces > 0;
}

std::string numbered_output(const std::string& path, std::size_t k) {
  if (is_stream_output(path)) return path;  // /dev/null_0 would be a new regular file
  const std::string ext = extension_of(path);
  return path.substr(0, path.size() - ext.size()) + "_" + std::to_string(k) + ext;
}

namespace {

using dim3::Box3;
using dim3::Complex;
using dim3::Point3;

/// Everything read and built from one surface file.
struct PreparedSurface {
  static constexpr const char* kFacetKey = "triangles";
  std::string path;
  dim3::Surface surface;
  ValidationReport report;                    ///< defects: exit 2
  std::optional<dim3::Inversion> inversion;  ///< set: exit 3 (check: a note)
  std::shared_ptr<Complex> complex;
  std::optional<dim3::Contacts> contacts;    ///< exact contacts (resolved unless --strict)
  ValidationReport folds;                     ///< local folds: exit 3 (check: a note)
  std::optional<dim3::FoldRepair> repair;     ///< --repair-folds was given and the input had folds
  std::optional<double> repair_max;           ///< the --repair-folds budget
  bool list_contacts = false;                 ///< print every contact (check)
};

ContactsView contacts_view(const dim3::Contacts& c) {
  return {&c.found, &c.counts, c.perturbation ? &*c.perturbation : nullptr};
}

Json point_json(const Point3& p) { return cli::point_json(p); }

Json box_json(const Box3& b) {
  Json j = Json::object();
  j["lo"] = point_json(b.lo);
  j["hi"] = point_json(b.hi);
  return j;
}

/// What --repair-folds did (the JSON twin of fold_repair_note): every moved vertex with its old
/// and new position and the distance, or why the folds were not repaired.
Json fold_repair_json(const dim3::FoldRepair& r, std::optional<double> max_allowed) {
  Json j = Json::object();
  j["repaired"] = r.ok;
  j["max_allowed"] = max_allowed ? Json(*max_allowed) : Json();
  j["max_displacement"] = r.max_displacement;
  Json& moved = (j["moved"] = Json::array());
  for (const dim3::MovedVertex& m : r.moved) {
    Json& o = moved.emplace_back(Json::object());
    o["vertex"] = m.vertex;
    o["from"] = point_json(m.from);
    o["to"] = point_json(m.to);
    o["displacement"] = m.distance;
  }
  if (!r.ok) j["failure"] = r.failure;
  return j;
}

Json input_json(const PreparedSurface& p) {
  Json j = Json::object();
  j["path"] = p.path;
  j["dimension"] = 3;
  j["triangles"] = p.surface.triangle_count();
  j["vertices"] = p.surface.vertex_count();
  j["reversed"] = p.complex ? Json(p.complex->reversed) : Json();
  if (p.contacts) j["contacts"] = contacts_json(contacts_view(*p.contacts), "triangles");
  if (p.repair) j["fold_repair"] = fold_repair_json(*p.repair, p.repair_max);
  return j;
}

std::string describe_input(const PreparedSurface& p) {
  return cli::describe_input(p.path, 3, plural(p.surface.triangle_count(), "triangle") + ", " +
                                            plural(p.surface.vertex_count(), "vertex", "vertices"));
}

Json inversion_json(const PreparedSurface& p) {
  const dim3::Inversion& inv = *p.inversion;
  Json j = Json::object();
  j["region"] = inv.region.value();
  j["winding"] = inv.winding_number;
  Json& triangles = (j["triangles"] = Json::array());
  for (long t : inv.triangles) triangles.emplace_back(t);
  j["message"] = inv.message;
  return j;
}

/// A local fold: two triangles of one vertex star cross beyond the vertex (DESIGN §5).
void print_folds(Session& s, const PreparedSurface& p) {
  s.err() << "immerse: " << local_folds_message(p.path, p.folds) << '\n';
  s.set_counts("local fold, not immersible");
}

void print_repair_note(Session& s, const dim3::FoldRepair& repair) {
  s.err() << "immerse: note: " << dim3::fold_repair_note(repair, s.repair_folds().value_or(0.0)) << '\n';
}

void print_reversed_note(Session& s, const PreparedSurface& p) {
  s.err() << "immerse: note: every winding number of '" << p.path
          << "' is <= 0 (inside-out surface): the input was reversed; winding numbers and patch "
             "normals refer to the reversed surface, vertex and triangle ids keep the file order\n";
}

/// Reads the file. @return kExitOk, or kExitInvalidInput after printing every read defect.
int read_input(Session& s, PreparedSurface& p) {
  dim3::SurfaceReadResult read = s.timed("read", [&] { return dim3::read_surface(p.path); });
  p.surface = std::move(read.surface);
  p.report = std::move(read.report);
  if (!p.report.ok()) {
    print_defects(s, p.path, p.report);
    return kExitInvalidInput;
  }
  if (extension_of(p.path) == ".obj") {
    if (const std::size_t lines = scan_obj_elements(p.path).lines; lines > 0)
      s.err() << "immerse: note: '" << p.path << "': " << plural(lines, "'l' line") << " (loose edges) ignored: "
              << "an OBJ with faces is a 3D surface, read from its faces\n";
  }
  return kExitOk;
}

/// Reads, validates and builds the cell complex. @return kExitOk, kExitInvalidInput after
/// printing every defect, or kExitNotImmersible after printing local folds (p.folds). An
/// inversion is left in p.inversion for the caller.
int prepare_surface(Session& s, PreparedSurface& p, bool exact_volumes) {
  if (const int code = read_input(s, p); code != kExitOk) return code;
  dim3::BuildOptions options;
  options.exact_volumes = exact_volumes;
  options.progress = s.progress("");  // the library's messages name their stages
  options.strict = s.strict();
  options.repair_folds = s.repair_folds();
  dim3::BuildResult built =
      s.timed("complex", [&] { return dim3::build_complex(p.surface, options); });
  if (built.repair) print_repair_note(s, *built.repair);
  p.repair = std::move(built.repair);
  p.repair_max = s.repair_folds();
  p.contacts = std::move(built.contacts);
  if (p.contacts) print_contacts_note(s, p.path, contacts_view(*p.contacts), p.list_contacts);
  if (!built.folds.ok()) {
    p.folds = std::move(built.folds);
    print_folds(s, p);
    return kExitNotImmersible;
  }
  if (!built.report.ok()) {
    p.report = std::move(built.report);
    print_defects(s, p.path, p.report);
    return kExitInvalidInput;
  }
  p.inversion = std::move(built.inversion);
  p.complex = std::move(built.complex);
  if (p.complex && p.complex->reversed) print_reversed_note(s, p);
  if (p.inversion) {
    s.set_counts("inverted region, not immersible");
  } else if (p.complex) {
    s.set_counts(complex_counts(p.complex->complex));
  } else {
    throw InvariantError("build_complex returned neither defects, an inversion nor a complex");
  }
  return kExitOk;
}

// ---- cells ------------------------------------------------------------------------------------

Json counts_json(const PreparedSurface& p) {
  const Complex& c3 = *p.complex;
  const CellComplex<3>& complex = c3.complex;
  Json j = complex_counts_json(complex);
  j["triangles"] = p.surface.triangle_count();
  j["vertices"] = p.surface.vertex_count();
  j["components"] = c3.components;
  j["groups"] = c3.groups;
  j["intersecting_pairs"] = c3.intersecting_pairs;
  j["intersection_points"] = c3.intersection_points;
  j["triple_points"] = c3.triple_points;
  j["cut_edges"] = c3.cut_edges;
  j["cut_vertices"] = c3.cut_vertices.size();
  j["cut_triangles"] = c3.cut_triangles.size();
  return j;
}

/// The complex with the 3D geometry: counts, volumes (exact when computed), genus, boxes, curves.
void add_complex_report(Json& j, const PreparedSurface& p) {
  const Complex& c3 = *p.complex;
  const CellComplex<3>& complex = c3.complex;
  j["counts"] = counts_json(p);
  j["volumes_exact"] = c3.exact_volumes;
  Rational total = 0;
  for (RegionId r : ids<RegionId>(complex.region_count()))
    total += complex.measure(r) * complex.winding_number(r);
  // Invariant 1 (DESIGN §4): equals the signed volume enclosed by the input.
  j["winding_weighted_volume"] = to_double(total);
  j["winding_weighted_volume_exact"] = c3.exact_volumes ? Json(to_string(total)) : Json();
  ComplexJsonHooks hooks;
  hooks.region = [&](Json& o, RegionId r) {
    // The unbounded region has no volume (the complex stores 0 for it).
    const bool bounded = r != kOutsideRegion;
    o["volume"] = bounded ? Json(to_double(complex.measure(r))) : Json();
    o["volume_exact"] = bounded && c3.exact_volumes ? Json(to_string(complex.measure(r))) : Json();
    o["genus"] = c3.region_genus[r];
    o["box"] = r == kOutsideRegion ? Json() : box_json(c3.region_box[r]);
  };
  hooks.patch = [&](Json& o, PatchId q) { (o["triangles"] = c3.patch_triangle_count[q]); };
  hooks.arc = [&](Json& o, ArcId a) {
    const std::vector<std::uint32_t>& points = c3.arc_points[a];
    o["closed"] = points.size() > 1 && points.front() == points.back();
    o["point_count"] = points.size();  // a closed loop repeats its first point
    o["sample"] = points.empty() ? Json() : point_json(c3.points[points[points.size() / 2]]);
  };
  hooks.junction_key = "junction_patches";
  add_complex_json(j, complex, hooks);
}

void print_cell_table(Session& s, const PreparedSurface& p) {
  const Complex& c3 = *p.complex;
  const std::string detail = plural(c3.components, "component") + ", " +
                             plural(c3.intersecting_pairs, "intersecting triangle pair") + ", " +
                             plural(c3.intersection_points, "intersection point") + ", " +
                             plural(c3.triple_points, "triple point") + ", " +
                             plural(c3.cut_triangles.size(), "cut triangle") + "\n";
  cli::print_cell_table(s, c3.complex, "intersection curves", detail, "volume",
                        CellTableColumn{"genus", [&](RegionId r) { return std::to_string(c3.region_genus[r]); }});
}

// ---- immersions ------------------------------------------------------------------------------

/// The helper boxes' part of a report (empty when none were needed).
Json helper_boxes_json(const dim3::Immersed& im) {
  Json boxes = Json::array();
  for (const Box3& b : im.helper_boxes) boxes.emplace_back(box_json(b));
  return boxes;
}

std::string box_text(const Box3& b) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, "[%.6g, %.6g] x [%.6g, %.6g] x [%.6g, %.6g]", b.lo[0],
                b.hi[0], b.lo[1], b.hi[1], b.lo[2], b.hi[2]);
  return buffer;
}

/// The defects of a rebuild with helper boxes may name box triangles: say which ids those are.
}  // namespace

int check_surface(Session& s, const std::string& path) {
  PreparedSurface p;
  p.path = path;
  p.list_contacts = true;
  if (const int code = prepare_surface(s, p, /*exact_volumes=*/false); code != kExitOk) {
    if (code != kExitNotImmersible || p.folds.ok()) return code;
    s.out() << describe_input(p) << ": valid\nnote: " << plural(p.folds.total(), "local fold")
            << " (above)\n(the input is valid but not immersible: 'immerse immersions' exits with code 3)\n";
    return kExitOk;
  }
  s.out() << describe_input(p) << ": valid";
  if (p.inversion) {
    s.out()
        << "\nnote: " << p.inversion->message
        << "\n(the input is valid but not immersible: 'immerse immersions' exits with code 3)\n";
    return kExitOk;
  }
  const Complex& c3 = *p.complex;
  const CellComplex<3>& c = c3.complex;
  s.out() << " (" << plural(c3.components, "component") << ", "
          << plural(c3.intersecting_pairs, "intersecting triangle pair") << ", "
          << plural(c.cell_count(), "cell") << ", max winding number " << c.max_winding_number()
          << (c3.reversed ? ", reversed" : "") << ")\n";
  return kExitOk;
}

int cells_surface(Session& s, const CommandLine& cl) {
  PreparedSurface p;
  p.path = cl.positional[0];
  const auto json_path = cl.value("--json");
  const auto prepare = [&] { return prepare_surface(s, p, /*exact_volumes=*/true); };
  if (const int code = prepare_complex_or_report(s, p, json_path, prepare); code != kExitOk) return code;
  s.out() << describe_input(p) << (p.complex->reversed ? " (reversed)" : "") << '\n';
  print_cell_table(s, p);
  if (json_path &&
      !s.write(*json_path, cells_report_json(p, s).dump(2) + "\n", "the cell complex (JSON)")) {
    return kExitInternalError;
  }
  if (auto path = cl.value("--cut-mesh");
      path && !s.write(*path, dim3::format_cut_mesh_obj(*p.complex),
                       "the cut mesh (OBJ, one group per patch)")) {
    return kExitInternalError;
  }
  print_written(s);
  return kExitOk;
}

namespace {

/// Reads the surface, builds the complex and searches, cutting self-connecting cells with helper
/// boxes when allowed. On invalid input or an inversion prints the verdict, writes the early JSON
/// when asked, and @return its exit code; otherwise kExitOk with p.complex set (the search's
/// verdict is in im.search).
int immerse_or_report(Session& s, PreparedSurface& p, const CommandLine& cl, const SearchRequest& request,
                      dim3::Immersed& im) {
  const auto json_path = cl.value("--json");
  const auto fail_early = [&](int code) {
    if (json_path && !s.write(*json_path, early_json(p, s).dump(2) + "\n", "report"))
      return kExitInternalError;
    print_written(s);
    return code;
  };
  if (const int code = read_input(s, p); code != kExitOk) return fail_early(code);

  dim3::ImmerseOptions options;
  options.build.exact_volumes = false;      // the search reads no volume
  options.build.progress = s.progress("");  // the library's messages name their stages
  options.search = search_options(s, request);
  options.build.strict = s.strict();
  options.build.repair_folds = s.repair_folds();
  // --threads bounds the whole run, the complex's triangulations included (0 = all cores).
  if (auto n = cl.integer("--threads")) options.build.threads = static_cast<unsigned>(*n);
  if (cl.has("--no-helper-boxes")) options.max_boxes = 0;
  im = dim3::immerse_surface(p.surface, options);
  s.add_time("complex", im.build_seconds);
  if (im.repair) print_repair_note(s, *im.repair);
  p.repair = im.repair;
  p.repair_max = s.repair_folds();
  p.contacts = im.contacts;
  if (p.contacts) print_contacts_note(s, p.path, contacts_view(*p.contacts), false);
  for (const std::string& note : im.notes) s.err() << "immerse: note: " << note << '\n';
  if (!im.build.folds.ok()) {
    p.folds = im.build.folds;
    print_folds(s, p);
    return fail_early(kExitNotImmersible);
  }

  if (!im.build.report.ok()) {
    p.report = im.build.report;
    print_defects(s, p.path, p.report);
    if (const std::string note = dim3::helper_box_defect_note(im); !note.empty())
      s.err() << "immerse: note: " << note << '\n';
    return fail_early(kExitInvalidInput);
  }
  p.inversion = im.build.inversion;
  if (p.inversion) {
    s.set_counts("inverted region, not immersible");
    print_inversion(s, p);
    return fail_early(kExitNotImmersible);
  }
  if (!im.build.complex)
    throw InvariantError("immerse_surface returned neither defects, an inversion nor a complex");
  p.complex = im.build.complex;
  if (p.complex->reversed) print_reversed_note(s, p);
  s.add_time("search", im.search_seconds);
  return kExitOk;
}


}  // namespace

int immersions_surface(Session& s, const CommandLine& cl, const SearchRequest& request) {
  PreparedSurface p;
  p.path = cl.positional[0];
  const auto json_path = cl.value("--json");
  const bool boxes_allowed = !cl.has("--no-helper-boxes");
  dim3::Immersed im;
  if (const int code = immerse_or_report(s, p, cl, request, im); code != kExitOk) return code;

  const SearchResult& r = im.search;
  const CellComplex<3>& complex = p.complex->complex;
  const std::size_t boxes = im.helper_boxes.size();
  s.set_counts(complex_counts(complex) + ", " + immersion_counts(r) +
               (boxes > 0 ? ", " + plural(boxes, "helper box", "helper boxes") : ""));
  if (r.status != ImmersionStatus::Immersible) {
    print_no_immersion(s, p.path, r, dim3::helper_box_hint(im, boxes_allowed));
  } else {
    std::string description = describe_input(p) + (p.complex->reversed ? " (reversed)" : "");
    if (boxes > 0) description += " with " + plural(boxes, "helper box", "helper boxes");
    print_immersion_list(s, description, r, request);
    std::size_t first = im.input_triangles;
    for (std::size_t k = 0; k < boxes; ++k) {
      const std::size_t count = dim3::box_surface(im.helper_boxes[k]).triangle_count();
      s.out() << "  helper box " << k << ": " << box_text(im.helper_boxes[k]) << " (triangles "
              << first << ".." << first + count - 1
              << "; cuts a self-connecting cell, paper §6.2)\n";
      first += count;
    }
  }
  if (json_path) {
    Json input = input_json(p);
    input["input_triangles"] = im.input_triangles;
    input["input_vertices"] = im.input_vertices;
    Json j = search_json(std::move(input), r, s);
    Json& counts = (j["counts"] = Json::object());
    counts["regions"] = complex.region_count();
    counts["cells"] = complex.cell_count();
    counts["patches"] = complex.patch_count();
    counts["arcs"] = complex.arc_count();
    counts["max_winding"] = complex.max_winding_number();
    j["helper_boxes"] = helper_boxes_json(im);
    Json& notes = (j["notes"] = Json::array());
    for (const std::string& note : im.notes) notes.emplace_back(note);
    j["timings_ms"] = s.timings_json();
    if (!s.write(*json_path, j.dump(2) + "\n", "the immersions (JSON)")) return kExitInternalError;
  }
  print_written(s);
  return r.status == ImmersionStatus::Immersible ? kExitOk : kExitNotImmersible;
}

// ---- mesh --------------------------------------------------------------------------------------

namespace {

std::string format_tet_mesh(const std::string& path, const dim3::TetMesh& mesh) {
  const std::string ext = extension_of(path);
  if (ext == ".vtu") return dim3::format_vtu(mesh);
  if (ext == ".veg") return dim3::format_veg(mesh);
  if (ext == ".msh") return dim3::format_gmsh(mesh);
  return dim3::format_medit_3d(mesh);
}

/// ", graded: cubes S at the surface, G at gaps, F far, min dihedral D deg" for the summary line.
std::string graded_summary(const dim3::GradedStats& g) {
  if (g.tets == 0) return {};
  std::ostringstream os;
  os << std::setprecision(4) << ", graded: cubes " << g.surface_size << " at the surface";
  if (g.gap_size < g.surface_size) os << ", " << g.gap_size << " at gaps";
  os << ", " << g.far_size << " far, min dihedral " << g.min_dihedral_deg << " deg";
  return os.str();
}

Json mesh3_json(const dim3::MeshResult& m, std::size_t k, const Immersion& immersion) {
  Json j = Json::object();
  j["immersion"] = k;
  Json& c = (j["counts"] = Json::object());
  c["background_tets"] = m.stats.background_tets;
  c["candidate_pairs"] = m.stats.candidate_pairs;
  c["clipped_polygons"] = m.stats.polygons;
  c["pieces"] = m.stats.pieces;
  c["cut_tets"] = m.stats.cut_tets;
  c["side_tests"] = m.stats.side_tests;
  c["exact_fallback_tets"] = m.stats.exact_tets;
  c["output_tets"] = m.stats.output_tets;
  c["output_vertices"] = m.stats.output_vertices;
  c["helper_tets_dropped"] = m.stats.helper_tets;
  c["generic_attempts"] = m.stats.attempts;
  c["embedded_vertices"] = m.embedding.size();
  c["embedding_error"] = m.stats.embedding_error;
  c["unused_vertices"] = m.stats.unused_vertices;
  c["graph_nodes"] = immersion.layout.node_count();
  Json& per_cell = (c["copies_per_cell"] = Json::array());
  for (std::size_t n : m.stats.copies_per_cell) per_cell.emplace_back(n);
  if (m.stats.graded.tets > 0) {
    const dim3::GradedStats& g = m.stats.graded;
    Json& b = (j["graded_background"] = Json::object());
    b["far_size"] = g.far_size;
    b["surface_size"] = g.surface_size;
    b["gap_size"] = g.gap_size;
    b["base_tets"] = g.base_tets;
    b["tets"] = g.tets;
    b["vertices"] = g.vertices;
    b["surface_tets"] = g.surface_tets;
    b["gap_tets"] = g.gap_tets;
    b["closure_bisections"] = g.closure_bisections;
    b["min_dihedral_deg"] = g.min_dihedral_deg;
    b["max_dihedral_deg"] = g.max_dihedral_deg;
    b["min_dihedral_bound_deg"] = dim3::graded_min_dihedral_bound();
  }
  j["input_shift"] = point_json(m.stats.input_shift);
  Json& phases = (j["mesh_phases_ms"] = Json::object());
  phases["background"] = m.stats.seconds_background * 1e3;
  phases["virtual"] = m.stats.seconds_virtual * 1e3;
  phases["assembly"] = m.stats.seconds_assembly * 1e3;
  // CPU milliseconds inside the virtual stage, summed over threads (not part of the wall-time
  // breakdown above; the exact arithmetic includes the booleans).
  Json& cpu = (j["virtual_cpu_ms"] = Json::object());
  cpu["exact_arithmetic"] = m.stats.cpu_seconds_exact * 1e3;
  cpu["booleans"] = m.stats.cpu_seconds_booleans * 1e3;
  return j;
}

/// The note for input vertices no triangle uses (-1 in the .emb), from either 3D mesher.
void print_unused_vertices_note(Session& s, const PreparedSurface& p, const std::vector<std::size_t>& unused) {
  if (unused.empty()) return;
  const std::size_t v = unused.front();
  s.err() << "immerse: note: " << plural(unused.size(), "input vertex", "input vertices") << " (vertex " << v << " "
          << dim3::format_point(p.surface.vertices[v]) << (unused.size() > 1 ? ", ..." : "")
          << ") used by no triangle: left out of the embedding (-1 in the .emb)\n";
}

/// A mesh that cannot be built (exit 2): the defects on stderr (at most 20 lines), the summary,
/// and the --json failure report. `how`: "" or "conformingly".
int mesh_failure(Session& s, const PreparedSurface& p, const ValidationReport& report,
                 const std::optional<std::string>& json_path, const std::string& how) {
  s.err() << "immerse: " << cannot_mesh_message(p.path, report, 20, how) << '\n';
  s.set_counts("meshing failed (" + plural(report.total(), "defect") + ")");
  if (json_path) {
    Json j = Json::object();
    j["input"] = input_json(p);
    j["status"] = "invalid-input";
    j["defects"] = defects_json(report, "triangles");
    j["timings_ms"] = s.timings_json();
    if (!s.write(*json_path, j.dump(2) + "\n", "report")) return kExitInternalError;
  }
  print_written(s);
  return kExitInvalidInput;
}

/// Writes `mesh -o` and `--embedding` of immersion i (numbered files with --all; TetGen's .node
/// also writes the .ele beside it, region attribute = graph node) and lists them in
/// entry["outputs"]. @return false after a failed write (already reported).
bool write_tet_outputs(Session& s, const CommandLine& cl, bool all, std::size_t i, const dim3::TetMesh& mesh,
                       const std::vector<dim3::EmbeddedVertex3>& embedding, const std::string& what_mesh,
                       const std::string& what_embedding, Json& entry) {
  Json& outputs = (entry["outputs"] = Json::object());
  if (auto path = cl.value("-o")) {
    const std::string out = all ? numbered_output(*path, i) : *path;
    if (extension_of(out) == ".node") {
      const dim3::TetGenTexts texts = dim3::format_tetgen(mesh);
      const auto [node_path, ele_path] = dim3::tetgen_paths(out);
      if (!s.write(node_path, texts.node, "the tet mesh's vertices (TetGen)") ||
          !s.write(ele_path, texts.ele, "the tet mesh's tets (TetGen, region = graph node)"))
        return false;
    } else if (!s.write(out, format_tet_mesh(out, mesh), what_mesh)) {
      return false;
    }
    outputs["mesh"] = out;
  }
  if (auto path = cl.value("--embedding")) {
    const std::string out = all ? numbered_output(*path, i) : *path;
    if (!s.write(out, dim3::format_embedding(embedding), what_embedding)) return false;
    outputs["embedding"] = out;
  }
  return true;
}

Json conforming3_json(const dim3::ConformingResult& m, std::size_t k, const Immersion& immersion) {
  Json j = Json::object();
  j["immersion"] = k;
  Json& c = (j["counts"] = Json::object());
  c["cut_triangles"] = m.stats.plc_triangles;
  c["cut_points"] = m.stats.plc_points;
  c["tetgen_tets"] = m.stats.tetgen_tets;
  c["tetgen_points"] = m.stats.tetgen_points;
  c["tet_components"] = m.stats.components;
  c["output_tets"] = m.stats.output_tets;
  c["output_vertices"] = m.stats.output_vertices;
  c["helper_tets_dropped"] = m.stats.helper_tets;
  c["embedded_vertices"] = m.embedding.size();
  c["embedding_error"] = m.stats.embedding_error;
  c["unused_vertices"] = m.stats.unused_vertices;
  c["graph_nodes"] = immersion.layout.node_count();
  Json& per_cell = (c["copies_per_cell"] = Json::array());
  for (std::size_t n : m.stats.copies_per_cell) per_cell.emplace_back(n);
  Json& q = (j["quality"] = Json::object());
  q["min_dihedral_deg"] = m.stats.min_dihedral;
  q["median_dihedral_deg"] = m.stats.median_dihedral;
  q["max_radius_edge"] = m.stats.max_radius_edge;
  q["median_radius_edge"] = m.stats.median_radius_edge;
  q["sliver_bound_deg"] = m.stats.sliver_bound;
  q["slivers"] = m.stats.slivers;
  q["slivers_at_surface"] = m.stats.slivers_at_surface;
  q["slivers_in_narrow_wedge"] = m.stats.slivers_in_narrow_wedge;
  q["slivers_on_cap"] = m.stats.slivers_on_cap;
  q["slivers_on_needle"] = m.stats.slivers_on_needle;
  q["min_cell_wedge_deg"] = m.stats.min_cell_wedge;
  q["narrow_wedge_edges"] = m.stats.narrow_wedge_edges;
  Json& phases = (j["mesh_phases_ms"] = Json::object());
  phases["exact_checks"] = m.stats.seconds_checks * 1e3;
  phases["tetgen"] = m.stats.seconds_tetgen * 1e3;
  phases["assembly"] = m.stats.seconds_assembly * 1e3;
  return j;
}

}  // namespace

int mesh_surface(Session& s, const CommandLine& cl, const SearchRequest& request, const dim3::MeshOptions& options,
                 std::size_t k, bool all, const dim3::ConformingOptions* conforming) {
  if (cl.has("--svg")) return usage_error(s.env(), "mesh", "--svg is for 2D curves only");
  // The mesher options themselves were checked by parse_mesh_choice (shared with deform, weights).
  if (conforming)
    for (const char* option : {"--method", "--threads"})
      if (cl.has(option))
        return usage_error(s.env(), "mesh", std::string(option) + " is for the background mesher, not --conforming");
  if (auto path = cl.value("-o")) {
    const std::string ext = extension_of(*path);
    if (ext != ".mesh" && ext != ".vtu" && ext != ".veg" && ext != ".msh" && ext != ".node" && !is_stream_output(*path))
      return usage_error(s.env(), "mesh",
                         "-o " + *path + ": a tet mesh is written as .mesh, .vtu, .veg, .msh or .node (+ .ele)");
  }
  s.enable_summary();
  PreparedSurface p;
  p.path = cl.positional[0];
  const auto json_path = cl.value("--json");
  const bool boxes_allowed = !cl.has("--no-helper-boxes");
  dim3::Immersed im;
  if (const int code = immerse_or_report(s, p, cl, request, im); code != kExitOk) return code;
  const SearchResult& r = im.search;
  const CellComplex<3>& complex = p.complex->complex;
  if (r.status != ImmersionStatus::Immersible) {
    s.set_counts(complex_counts(complex) + ", " + immersion_counts(r));
    print_no_immersion(s, p.path, r, dim3::helper_box_hint(im, boxes_allowed));
    if (json_path && !s.write(*json_path, search_json(input_json(p), r, s).dump(2) + "\n", "report")) return kExitInternalError;
    print_written(s);
    return kExitNotImmersible;
  }
  if (r.immersions.size() <= k) {
    s.set_counts(complex_counts(complex) + ", " + immersion_counts(r));
    return usage_error(s.env(), "mesh",
                       immersion_index_message(k, p.path, r.immersions.size(), r.complete, kProgramOptions));
  }
  dim3::MeshOptions mesh_options = options;
  if (s.show_progress()) mesh_options.progress = [&s](const std::string& m) { s.err() << "immerse: mesh: " << m << '\n'; };
  Json report = Json::object();
  report["input"] = input_json(p);
  report["status"] = "ok";
  report["immersions_found"] = r.immersions.size();
  report["helper_boxes"] = helper_boxes_json(im);
  Json& o = (report["options"] = Json::object());
  o["resolution"] = options.background_path ? Json() : Json(options.graded ? options.graded->far_resolution : options.resolution);
  o["surface_resolution"] = options.graded ? Json(options.graded->surface_resolution) : Json();
  o["gap_resolution"] =
      options.graded && options.graded->gap_resolution > 0 ? Json(options.graded->gap_resolution) : Json();
  o["background"] = options.background_path ? Json(*options.background_path) : Json();
  o["threads"] = options.threads;
  o["method"] = options.method == MeshMethod::Csg ? "csg" : "clip";
  Json& meshes = (report["meshes"] = Json::array());
  const std::size_t first = all ? 0 : k;
  const std::size_t last = all ? r.immersions.size() : k + 1;
  std::size_t total_tets = 0;
  dim3::ConformingOptions conforming_options;
  if (conforming) {
    conforming_options = *conforming;
    conforming_options.progress = mesh_options.progress;
    if (const std::string error = default_edge_length(p.surface, options.resolution, conforming_options); !error.empty())
      return usage_error(s.env(), "mesh", error);
    conforming = &conforming_options;
    o["conforming"] = true;
    o["edge_length"] = conforming->edge_length;
    o["radius_edge"] = conforming->radius_edge;
    o["min_dihedral"] = conforming->min_dihedral;
  }
  for (std::size_t i = first; i < last && conforming; ++i) {
    const dim3::ConformingResult m = s.timed("mesh", [&] {
      return dim3::mesh_conforming(*p.complex, r.immersions[i], conforming_options, im.input_vertices,
                                    im.input_triangles);
    });
    if (!m.report.ok()) {
      return mesh_failure(s, p, m.report, json_path, "conformingly");
    }
    total_tets += m.stats.output_tets;
    print_unused_vertices_note(s, p, m.stats.unused_vertices);
    s.out() << describe_input(p) << ": immersion " << i << " of " << r.immersions.size() << (r.complete ? "" : "+")
            << " meshed conformingly: " << plural(m.stats.output_tets, "tet") << ", "
            << plural(m.stats.output_vertices, "vertex", "vertices") << " (TetGen " << plural(m.stats.tetgen_tets, "tet")
            << " on " << plural(m.stats.plc_triangles, "cut triangle")
            << (m.stats.helper_tets > 0 ? ", " + std::to_string(m.stats.helper_tets) + " helper-box tets dropped" : "")
            << "; dihedral angles min " << m.stats.min_dihedral << " median " << m.stats.median_dihedral
            << " deg, radius-edge max " << m.stats.max_radius_edge << "; "
            << plural(m.stats.slivers, "sliver") << " below " << m.stats.sliver_bound << " deg: "
            << m.stats.slivers_in_narrow_wedge << " in cell wedges narrower than that, " << m.stats.slivers_on_cap
            << " on caps, " << m.stats.slivers_on_needle << " on needles; narrowest cell wedge "
            << m.stats.min_cell_wedge << " deg)\n";
    Json entry = conforming3_json(m, i, r.immersions[i]);
    if (!write_tet_outputs(s, cl, all, i, m.mesh, m.embedding, "the conforming tet mesh (reference = graph node)",
                           "the embedding of the input vertices (weight 1 each)", entry))
      return kExitInternalError;
    meshes.emplace_back(std::move(entry));
  }
  for (std::size_t i = first; i < last && !conforming; ++i) {
    const dim3::MeshResult m = s.timed("mesh", [&] {
      return dim3::mesh_immersion(*p.complex, r.immersions[i], mesh_options, im.input_vertices, im.input_triangles);
    });
    if (!m.report.ok()) {
      return mesh_failure(s, p, m.report, json_path, "");
    }
    total_tets += m.stats.output_tets;
    if (m.stats.input_shift != Point3{0, 0, 0}) {
      s.err() << "immerse: note: the input touches the background mesh non-generically (an input vertex on a tet "
                 "face, an edge through a tet edge, ...): meshed the input translated by "
              << dim3::format_point(m.stats.input_shift)
              << " relative to the background; the embedding reproduces the translated vertices\n";
    } else if (m.stats.attempts > 1) {
      s.err() << "immerse: note: the grid touched the input non-generically; it was shifted "
              << plural(static_cast<std::size_t>(m.stats.attempts - 1), "time") << '\n';
    }
    print_unused_vertices_note(s, p, m.stats.unused_vertices);
    warn_embedding_error(s, m.stats.embedding_error);
    s.out() << describe_input(p) << ": immersion " << i << " of " << r.immersions.size() << (r.complete ? "" : "+")
            << " meshed: " << plural(m.stats.output_tets, "tet") << ", " << plural(m.stats.output_vertices, "vertex", "vertices")
            << " (background " << plural(m.stats.background_tets, "tet")
            << graded_summary(m.stats.graded)
            << ", " << m.stats.cut_tets
            << " cut by the input" << (m.stats.helper_tets > 0 ? ", " + std::to_string(m.stats.helper_tets) + " helper-box tets dropped" : "")
            << ")\n";
    Json entry = mesh3_json(m, i, r.immersions[i]);
    if (!write_tet_outputs(s, cl, all, i, m.mesh, m.embedding, "the tet mesh (reference = graph node)",
                           "the embedding of the input vertices", entry))
      return kExitInternalError;
    meshes.emplace_back(std::move(entry));
  }
  s.set_counts(complex_counts(complex) + ", " + immersion_counts(r) + ", " + plural(total_tets, "tet"));
  report["timings_ms"] = s.timings_json();
  if (json_path && !s.write(*json_path, report.dump(2) + "\n", "mesh counts and timings (JSON)")) return kExitInternalError;
  print_written(s);
  return kExitOk;
}

// ---- generate ---------------------------------------------------------------------------------

std::vector<GeneratorEntry> surface_generator_list() {
  std::vector<GeneratorEntry> out;
  for (const auto& g : dim3::surface_registry().summaries()) out.push_back({g.name, g.params, g.description});
  return out;
}

bool is_surface_generator(const std::string& name) {
  return dim3::surface_registry().find(name) != nullptr;
}

int command_generate_surface(Session& s, const std::string& name,
                             const std::vector<std::string>& params,
                             const std::optional<std::string>& out) {
  const std::string ext = out ? extension_of(*out) : ".obj";
  if (ext != ".obj" && ext != ".off") {
    return usage_error(s.env(), "generate",
                       "-o " + *out + ": a surface is written as .obj or .off");
  }
  const Clock::time_point start = Clock::now();
  dim3::SurfaceGenerateResult g = dim3::generate_surface(name, params);
  if (!g.ok()) return usage_error(s.env(), "generate", g.error);
  s.enable_summary();
  s.add_time("generate", seconds_since(start));
  const std::string counts = plural(g.surface.triangle_count(), "triangle") + ", " +
                             plural(g.surface.vertex_count(), "vertex", "vertices");
  s.set_counts("generated '" + name + "': " + counts);
  const std::string text =
      ext == ".off" ? dim3::format_off(g.surface) : dim3::format_obj(g.surface);
  if (!out) {
    s.out() << text;
    return kExitOk;
  }
  if (!s.write(*out, text, "surface '" + name + "' (" + counts + ")")) return kExitInternalError;
  print_written(s);
  return kExitOk;
}

}  // namespace imm::cli
