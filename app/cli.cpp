// The `immerse` command line (DESIGN §3). See app/cli.h for the command list and exit codes.
//
// This layer owns everything user-facing: parsing, messages, exit codes, JSON/SVG reports and
// the one-line timing summary. The library calls below never print; they return reports and
// verdicts, which are mapped here (CONVENTIONS "Errors and diagnostics"):
//   ValidationReport not ok            -> exit 2, every defect printed
//   Inversion / not immersible / budget -> exit 3, the rule / region / cell named
//   InvariantError, std::exception     -> exit 1
// Every output goes through write_file_atomic: complete or absent, never half-written.
//
// This file holds the parsing, the help texts, the 2D commands and the pieces both dimensions
// share (declared in app/cli_common.h); the commands dispatch to app/cli_surface.cpp when the
// input is a 3D surface (is_surface_file) or the generator name is a 3D one.
#include "app/cli.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string_view>
#include <variant>

#include "core/atomic_file.h"
#include "app/cli_common.h"
#include "core/parallel.h"
#include "app/cli_deform.h"
#include "app/cli_render.h"
#include "core/diagnostics.h"
#include "core/printable.h"
#include "core/graph_search.h"
#include "dim2/complex2.h"
#include "dim2/curves.h"
#include "dim2/generators.h"
#include "dim2/mesh2.h"
#include "dim2/svg.h"
#include "dim3/tet_mesh.h"

namespace imm::cli {
namespace {

// ---- help texts ---------------------------------------------------------------------------

constexpr const char* kMainHelp = R"(usage: immerse [COMMAND] [ARGS...]

Immersion of self-intersecting curves and surfaces (Li & Barbic 2018, "Immersion of
Self-Intersecting Solids and Surfaces"): cell complex, every immersion, and an unglued simulation
mesh (triangles in 2D, tets in 3D).

commands:
  (none)                           the main job on a bundled curve with two immersions; writes
                                   ./out/ (input, cells, immersions, mesh) and lists the files
  check IN                         validate the input; list every defect with its location
  cells IN [--json OUT]            the cell complex: regions, cells, patches, arcs, windings
  immersions IN [options]          the immersion search (paper §6, Algorithm 1)
  mesh IN [options]                mesh one immersion (paper §7): triangles in 2D, tets in 3D
  generate NAME [PARAMS] [-o OUT]  procedural curves and surfaces; 'generate --list' names them
  render IN -o OUT.png [options]   a picture of a surface, tet mesh or curves (POV-Ray, rsvg-convert)
  deform IN --handles H.json -o DIR  pull the unglued mesh apart (ARAP, FEM; paper §8); --glued compares
  weights IN --handles H.json -o OUT.vtu  bounded biharmonic weights and geodesic distance
  help [COMMAND]                   this text, or the options of one command (also CMD --help)

input: the dimension is taken from the file.
  2D, closed polygonal curves:
  .txt .xy .poly (and other)  one vertex 'x y' per line, '#' comments, a blank line ends a curve
  .svg                        <polygon>, <polyline>, <path> with straight segments
  .obj                        'v' and 'l' lines
  3D, closed triangle meshes (several components allowed; polygons are fan-triangulated):
  .obj .off .ply .stl          OBJ ('f' faces, no 'l' lines), OFF, PLY and STL (ASCII or binary)
Orientation: the vertex order; a counter-clockwise outer curve, or a surface whose triangles are
counter-clockwise seen from outside, has winding number +1 inside. An input whose winding
numbers are all <= 0 is reversed (and says so).

exit codes:
  0   success (check: the input is valid; immersions/mesh: the input is immersible)
  1   internal error (a bug: please report it), or an output file that could not be written
  2   invalid input: every defect is printed (kind, stage, curve/segment or triangle ids,
      vertex ids, coordinates)
  3   valid input that is not immersible: an inverted region (negative winding number), the
      conflicting rule with its cells and patches, a possibly self-connecting cell, or
      "search budget exhausted after N states"
  64  bad command line (unknown command or option, missing or malformed value)

A one-line timing summary is always printed on stderr, progress messages too when stderr is a
terminal. Outputs are written to '<path>.tmp.<pid>' and renamed: never a partial file.
)";

// ---- the commands' options (parsed by CLI11, app/command_line.h) --------------------------------

std::vector<OptionSpec> search_option_specs() {
  return {
      {"--all", ValueKind::Flag, "", "enumerate every immersion (pairwise non-isomorphic)"},
      {"--max", ValueKind::Integer, "N", "stop after N immersions (default 1)", 1},
      {"--max-states", ValueKind::Integer, "N", "search budget in explored states (default 50000000)", 1},
      {"--time-limit", ValueKind::Real, "S", "search budget in seconds (default none); also bounds the writing of outputs"},
      {"--max-output", ValueKind::Integer, "BYTES", "output budget: bytes in all files written (default 4 GiB)", 1},
      {"--classic-search", ValueKind::Flag, "",
       "branch on the variable with the fewest options everywhere and grow no sheet by symmetry "
       "(the search before issue 19; same immersions, often far slower on overlapping parts)"},
  };
}

std::vector<CommandSpec> make_command_specs() {
  std::vector<CommandSpec> specs;

  CommandSpec check;
  check.name = "check";
  check.usage = "check IN [--strict]";
  check.positional_help = "a 2D curve file (text, SVG, OBJ lines) or a 3D surface (OBJ, OFF, PLY, STL)";
  check.description =
      "Reads IN and validates it, then builds its cell complex.\n"
      "2D curves: empty input, non-finite coordinates, curves with fewer than three vertices, repeated\n"
      "consecutive vertices, open OBJ curves, collinear overlaps, a vertex touching another segment,\n"
      "three or more segments through one point.\n"
      "3D surfaces (OBJ, OFF, PLY, STL): unreadable or empty files, non-finite coordinates, open\n"
      "boundary, non-manifold edges or vertices, inconsistent orientation, degenerate triangles,\n"
      "duplicate faces. A valid surface prints its triangles, components, intersecting triangle pairs,\n"
      "cells and maximum winding number.\n"
      "Exact contacts (coplanar overlaps, touching without crossing, intersections through vertices or\n"
      "edges, coincident vertices of different parts; in 2D vertices on segments, collinear overlaps,\n"
      "three segments through a point) are listed as notes: every command resolves them by a tiny,\n"
      "reproducible perturbation of the input and says so; with --strict they are defects (exit 2).\n"
      "A local fold (two triangles of a vertex star crossing beyond the vertex) is a note here and\n"
      "exit 3 elsewhere: no perturbation removes it.\n"
      "Every defect is printed with its curve/segment or triangle ids and vertex ids (0-based, file\n"
      "order; polygon faces are fan-triangulated in order) and coordinates.\n";
  check.options = {{"--strict", ValueKind::Flag, "",
       "refuse exact contacts (a vertex on a segment or triangle, touching, coplanar or collinear overlaps) with "
       "exit 2 instead of resolving them by a tiny perturbation"}};
  check.footer =
      "Exit code 0 when the input is valid (an inverted region is reported as a note: the input is\n"
      "valid but not immersible, see 'immerse immersions'), 2 when it is not, 64 on a bad command line.\n";
  specs.push_back(check);

  CommandSpec cells;
  cells.name = "cells";
  cells.usage = "cells IN [--json OUT] [--cut-mesh OUT.obj]";
  cells.positional_help = check.positional_help;
  cells.description =
      "Builds the exact cell complex of IN (paper §4) and prints its counts and a table of the cells.\n";
  cells.options = {
      {"--json", ValueKind::Text, "OUT",
       "write the complex as JSON: counts; per region its winding number, exact measure and simple "
       "connectivity (2D: \"area\" as a rational \"p/q\" and \"area_double\"; 3D: \"volume\" as a double, "
       "\"volume_exact\" as a rational \"p/q\", and the genus of its boundary); per cell its B-patches and "
       "their agreement; per patch its positive/negative regions (3D: and its triangle count); per arc its "
       "four junction patches in cyclic order (2D: counter-clockwise around the crossing point; 3D: around "
       "the intersection curve) and the four wedges (wedge k lies between junction k and k+1); timings in "
       "milliseconds"},
      {"--cut-mesh", ValueKind::Text, "OUT.obj",
       "(3D) the surface cut along its self-intersection curves, one OBJ group per patch, for viewers"},
  };
  cells.options.push_back({"--repair-folds", ValueKind::Real, "MAX",
       "(3D) local folds (a vertex whose star crosses itself) are repaired instead of refused (exit 3): "
       "fold vertices move toward their ring's centroid by at most MAX each, every move is reported"});
  cells.options.push_back({"--strict", ValueKind::Flag, "",
       "refuse exact contacts (a vertex on a segment or triangle, touching, coplanar or collinear overlaps) with "
       "exit 2 instead of resolving them by a tiny perturbation"});
  cells.footer = "Exit codes: 0 ok, 2 invalid input, 3 inverted region, 64 bad command line, 1 internal error.\n";
  specs.push_back(cells);

  CommandSpec immersions;
  immersions.name = "immersions";
  immersions.usage =
      "immersions IN [--all | --max N] [--max-states N] [--time-limit S]\n"
      "                         [--json OUT] [--svg DIR] [--no-helper-boxes] [--classic-search]";
  immersions.positional_help = check.positional_help;
  immersions.description =
      "Searches the immersions of IN (paper §6, Algorithm 1): graphs of cell copies satisfying Rules 1-7.\n"
      "In 3D, a cell that may be self-connecting (paper §5.1) is cut by a helper box added to the input\n"
      "(§6.2) and the search is run again; the boxes used are listed.\n";
  immersions.options = search_option_specs();
  immersions.options.push_back(
      {"--json", ValueKind::Text, "OUT",
       "status, count, completeness, search statistics and, per immersion, its nodes (id, cell, copy), "
       "edges (inner, outer, patch) and the owner node of every patch"});
  immersions.options.push_back(
      {"--svg", ValueKind::Text, "DIR", "(2D) one drawing per immersion, DIR/immersion_K.svg (K = 0, 1, ...)"});
  immersions.options.push_back(
      {"--no-helper-boxes", ValueKind::Flag, "", "(3D) no helper boxes: a possibly self-connecting cell is the verdict"});
  immersions.options.push_back({"--repair-folds", ValueKind::Real, "MAX",
       "(3D) local folds (a vertex whose star crosses itself) are repaired instead of refused (exit 3): "
       "fold vertices move toward their ring's centroid by at most MAX each, every move is reported"});
  immersions.options.push_back({"--strict", ValueKind::Flag, "",
       "refuse exact contacts (a vertex on a segment or triangle, touching, coplanar or collinear overlaps) with "
       "exit 2 instead of resolving them by a tiny perturbation"});
  immersions.footer =
      "Exit codes: 0 immersible, 3 not immersible / inverted / self-connecting cell / budget exhausted\n"
      "(the JSON is written in each of these cases, except when --time-limit ran out: nothing is written\n"
      "after the deadline), 2 invalid input, 64 bad command line, 1 internal error.\n";
  specs.push_back(immersions);

  CommandSpec mesh;
  mesh.name = "mesh";
  mesh.usage =
      "mesh IN [--resolution N [--surface-resolution M [--gap-resolution G]] | --background FILE]\n"
      "                   [--conforming [--edge-length H] [--radius-edge R]\n"
      "                   [--min-dihedral DEG]]\n"
      "                   [--immersion K | --all] [--method clip|csg] [-o OUT] [--embedding OUT.emb]\n"
      "                   [--svg OUT.svg] [--threads N] [--json OUT]";
  mesh.positional_help = check.positional_help;
  mesh.description =
      "Meshes one immersion of IN (paper §7): a background mesh, virtual elements where the input cuts\n"
      "an element (exact clipping), one copy per graph node, copies fused across graph edges, so that\n"
      "overlapping and nearly touching parts are not glued. 2D (curves): triangles. 3D (surfaces): tets.\n";
  mesh.options = mesh_choice_options(true);
  mesh.options.insert(mesh.options.end(), {
      {"--immersion", ValueKind::Integer, "K", "which immersion (0-based, in the search's order; default 0)", 0,
       1'000'000},
      {"--all", ValueKind::Flag, "", "(3D) mesh every immersion: OUT_K.ext and OUT_K.emb for immersion K"},
      {"--method", ValueKind::Text, "clip|csg",
       "the paper's exact clipping (default), or the CSG baseline it compares with (Sifakis et al. 2007: "
       "exact booleans per element, polygon sets in 2D, Nef polyhedra in 3D; the same duplication, much "
       "slower)"},
      {"-o", ValueKind::Text, "OUT",
       "the mesh: 2D Medit .mesh; 3D Medit .mesh, VTK XML .vtu (ParaView), Vega .veg, Gmsh .msh 4.1 "
       "(physical group = graph node + 1) or TetGen .node (+ .ele beside it, region = graph node); the "
       "element reference is the graph node"},
      {"--embedding", ValueKind::Text, "OUT.emb", "per input vertex: output element and barycentric weights"},
      {"--svg", ValueKind::Text, "OUT.svg", "(2D) the output mesh pulled apart by sheet"},
      {"--threads", ValueKind::Integer, "N",
       "(3D) threads for the cell complex, reading a --background and the virtual tets (0 = all cores; the output is the same)",
       0, kMaxThreads},
      {"--no-helper-boxes", ValueKind::Flag, "",
       "(3D) do not cut self-connecting cells (helper-box tets are otherwise dropped)"},
      {"--json", ValueKind::Text, "OUT",
       "counts (background, cut and output elements, vertices, copies per cell) and timings"},
      {"--max-states", ValueKind::Integer, "N", "search budget in explored states (as for 'immerse immersions')", 1},
      {"--time-limit", ValueKind::Real, "S", "search budget in seconds (as for 'immerse immersions')"},
      {"--max-output", ValueKind::Integer, "BYTES", "output budget: bytes in all files written (default 4 GiB)", 1},
  });
  mesh.options.push_back({"--repair-folds", ValueKind::Real, "MAX",
       "(3D) local folds (a vertex whose star crosses itself) are repaired instead of refused (exit 3): "
       "fold vertices move toward their ring's centroid by at most MAX each, every move is reported"});
  mesh.options.push_back({"--strict", ValueKind::Flag, "",
       "refuse exact contacts (a vertex on a segment or triangle, touching, coplanar or collinear overlaps) with "
       "exit 2 instead of resolving them by a tiny perturbation"});
  mesh.footer =
      "Exit codes: 0 ok, 2 invalid input or a background not covering the input (or touching it\n"
      "non-generically), 3 not immersible, 64 bad command line (also: --immersion K beyond the\n"
      "immersions found), 1 internal error.\n";
  specs.push_back(mesh);

  CommandSpec generate;
  generate.name = "generate";
  generate.usage = "generate NAME [PARAMS...] [-o OUT]\n       immerse generate --list";
  generate.positional_name = "NAME PARAMS";
  generate.positional_help = "a generator name and its positional parameters, as listed by --list";
  generate.min_positional = 0;
  generate.max_positional = std::numeric_limits<std::size_t>::max();
  generate.missing_positional = "missing generator name";
  generate.description =
      "Writes a procedural input (the paper's figures and test shapes): a 2D curve or a 3D surface.\n"
      "2D: OUT ending in .obj is written as OBJ 'v'/'l' lines, .svg as polygons, anything else in the\n"
      "text format; without -o the text format goes to standard output.\n"
      "3D: OUT ending in .off is written as OFF, .obj (or no -o: standard output) as OBJ.\n";
  generate.options = {
      {"-o", ValueKind::Text, "OUT", "the output file (default: standard output)"},
      {"--list", ValueKind::Flag, "", "list the generators with their parameters"},
  };
  generate.footer = "Exit codes: 0 ok, 64 unknown name or bad parameters, 1 output not writable.\n";
  specs.push_back(generate);
  specs.push_back(deform_command_spec());
  specs.push_back(weights_command_spec());
  specs.push_back(render_command_spec());
  return specs;
}

/// The command named `name`, or null.
const CommandSpec* find_command(const std::string& name) {
  static const std::vector<CommandSpec> specs = make_command_specs();
  for (const CommandSpec& spec : specs) {
    if (spec.name == name) return &spec;
  }
  return nullptr;
}

}  // namespace

// ---- shared with the 3D commands (app/cli_common.h) -----------------------------------------

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string extension_of(const std::string& path) {
  return lower(std::filesystem::path(path).extension().string());
}

std::string format_ms(double seconds) {
  const double ms = seconds * 1e3;
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, ms < 1.0 ? "%.2f ms" : ms < 100.0 ? "%.1f ms" : "%.0f ms", ms);
  return buffer;
}

int usage_error(const CliEnvironment& env, const std::string& command, const std::string& message) {
  return print_usage_error(env, find_command(command), message);
}

void print_written(Session& s, std::size_t from) {
  if (!s.commit()) return;  // a write failed: nothing of this command was kept
  const auto& written = s.written();
  std::size_t width = 0;
  for (std::size_t i = from; i < written.size(); ++i) width = std::max(width, written[i].first.size());
  for (std::size_t i = from; i < written.size(); ++i) {
    s.out() << "wrote " << written[i].first << std::string(width - written[i].first.size() + 2, ' ')
            << written[i].second << '\n';
  }
}

std::string b_patch_list(std::span<const BPatch> b_patches) {
  std::string patches;
  for (const BPatch& b : b_patches) {
    if (patches.size() > 40) {
      patches += " ...";
      break;
    }
    patches += (patches.empty() ? "P" : " P") + std::to_string(b.patch.value()) + (b.agrees ? "" : "*");
  }
  return patches;
}

/// At most this many defect lines on stderr, then "... and N more" (all of them are in --json):
/// the fuzzer's 20 stacked copies of one curve printed 140 KB (issue 13).
constexpr std::size_t kMaxDefectLines = 50;

void print_defects(Session& s, const std::string& path, const ValidationReport& report) {
  s.err() << "immerse: " << invalid_input_message(path, report, kMaxDefectLines) << '\n';
  s.set_counts("invalid input (" + plural(report.total(), "defect") + ")");
}

SearchOptions search_options(const Session& s, const SearchRequest& request) {
  SearchOptions options;
  options.max_immersions = request.max_immersions;
  options.max_states = request.max_states;
  options.time_limit_seconds = request.time_limit;
  options.sheets_first = !request.classic_search;
  options.continue_sheets = !request.classic_search;
  options.progress = s.progress("search");
  return options;
}

std::string immersion_counts(const SearchResult& r) {
  if (r.status == ImmersionStatus::SearchBudgetExhausted) return "search budget exhausted";
  return (r.complete || r.immersions.empty() ? "" : "at least ") + plural(r.immersions.size(), "immersion");
}

void print_no_immersion(Session& s, const std::string& path, const SearchResult& r, const std::string& hint) {
  s.err() << "immerse: " << no_immersion_message(path, r, kProgramOptions) << hint << '\n';
}

void print_immersion_list(Session& s, const std::string& description, const SearchResult& r,
                          const SearchRequest& request) {
  s.out() << description << ": immersible, " << plural(r.immersions.size(), "immersion");
  if (r.complete) {
    s.out() << (r.immersions.size() == 1 ? " (the only one)" : " (all of them)");
  } else if (request.max_immersions != 0 && r.immersions.size() >= request.max_immersions) {
    s.out() << " (stopped at " << request.max_immersions << "; more may exist: use --all)";
  } else {
    s.out() << " (the search budget ran out after " << r.stats.states
            << " states; more may exist: raise --max-states / --time-limit)";
  }
  s.out() << '\n';
  for (std::size_t k = 0; k < r.immersions.size() && k < kMaxTableRows; ++k) {
    const Immersion& im = r.immersions[k];
    s.out() << "  immersion " << k << ": " << plural(im.layout.node_count(), "node") << ", "
            << plural(im.edges.size(), "edge") << ", " << plural(im.components().size(), "connected component")
            << '\n';
  }
  if (r.immersions.size() > kMaxTableRows) s.out() << "  ... (see --json)\n";
}

Json defects_json(const ValidationReport& report, const std::string& facet_key) {
  Json list = Json::array();
  for (const Defect& d : report.defects) {
    Json& j = list.emplace_back(Json::object());
    j["kind"] = to_string(d.kind);
    j["stage"] = d.stage;
    j["message"] = printable(d.message);  // bytes quoted from a broken file are not JSON text
    Json& facets = (j[facet_key] = Json::array());
    for (long f : d.facets) facets.emplace_back(f);
    Json& vertices = (j["vertices"] = Json::array());
    for (long v : d.vertices) vertices.emplace_back(v);
    Json& points = (j["points"] = Json::array());
    for (const auto& p : d.points) {
      Json& q = points.emplace_back(Json::array());
      for (double x : p) q.emplace_back(x);
    }
  }
  return list;
}

namespace {
std::string contact_counts_text(const ContactsView& c) {
  std::size_t total = 0;
  std::string kinds;
  for (const auto& [kind, n] : *c.counts) {
    total += n;
    kinds += (kinds.empty() ? "" : ", ") + std::to_string(n) + " " + to_string(kind);
  }
  return plural(total, "exact contact") + " (" + kinds + ")";
}
}  // namespace

void print_contacts_note(Session& s, const std::string& path, const ContactsView& c, bool list) {
  if (c.perturbation != nullptr) {
    const PerturbationSummary& p = *c.perturbation;
    char size[160];
    std::snprintf(size, sizeof size, "%.3g (%.3g of the bounding-box diagonal; %zu vertices moved, seed %llu)",
                  p.max_displacement, p.diagonal > 0 ? p.max_displacement / p.diagonal : 0.0, p.moved_vertices,
                  static_cast<unsigned long long>(p.attempt.seed));
    s.err() << "immerse: note: '" << path << "' has " << contact_counts_text(c)
            << ", resolved by perturbing the input by at most " << size
            << ": every result is exact for the perturbed input (solids touching from outside come apart by a thin "
               "gap); --strict refuses them\n";
  } else {
    s.err() << "immerse: note: '" << path << "' has " << contact_counts_text(c) << '\n';
  }
  // At most kMaxDefectLines, then "... and N more" (a duplicated SVG listed 157 KB of contacts).
  if (list) s.err() << c.found->summary(kMaxDefectLines);
}

Json contacts_json(const ContactsView& c, const std::string& facet_key) {
  Json j = Json::object();
  j["resolved"] = c.perturbation != nullptr;
  Json& counts = (j["counts"] = Json::object());
  std::size_t total = 0;
  for (const auto& [kind, n] : *c.counts) {
    counts[to_string(kind)] = n;
    total += n;
  }
  j["total"] = total;  // the "N exact contacts" of the note
  if (c.perturbation != nullptr) {
    j["max_displacement"] = c.perturbation->max_displacement;
    j["diagonal"] = c.perturbation->diagonal;
    j["amplitude"] = c.perturbation->amplitude;
    j["seed"] = c.perturbation->attempt.seed;
    j["moved_vertices"] = c.perturbation->moved_vertices;
  }
  j["listed"] = defects_json(*c.found, facet_key);
  return j;
}

Json conflict_json(const Conflict& c) {
  Json j = Json::object();
  j["rule"] = c.rule;
  j["message"] = c.message;
  Json& cells = (j["cells"] = Json::array());
  for (CellId id : c.cells) cells.emplace_back(id.value());
  Json& nodes = (j["nodes"] = Json::array());
  for (NodeId id : c.nodes) nodes.emplace_back(id.value());
  Json& patches = (j["patches"] = Json::array());
  for (PatchId id : c.patches) patches.emplace_back(id.value());
  j["arc"] = c.arc.is_valid() ? Json(c.arc.value()) : Json();
  return j;
}

Json immersion_json(const Immersion& im, std::size_t index) {
  Json j = Json::object();
  j["index"] = index;
  Json& nodes = (j["nodes"] = Json::array());
  for (NodeId n : ids<NodeId>(im.layout.node_count())) {
    Json& o = nodes.emplace_back(Json::object());
    o["id"] = n.value();
    o["cell"] = im.layout.cell(n).value();
    o["copy"] = im.layout.copy(n);
  }
  Json& edges = (j["edges"] = Json::array());
  for (const ImmersionEdge& e : im.edges) {
    Json& o = edges.emplace_back(Json::object());
    o["inner"] = e.inner.value();
    o["outer"] = e.outer.value();
    o["patch"] = e.patch.value();
  }
  Json& owner = (j["owner"] = Json::array());
  for (NodeId n : im.owner) owner.emplace_back(n.is_valid() ? Json(n.value()) : Json());
  Json& components = (j["components"] = Json::array());
  for (const auto& component : im.components()) {
    Json& c = components.emplace_back(Json::array());
    for (NodeId n : component) c.emplace_back(n.value());
  }
  return j;
}

Json stats_json(const SearchStats& s) {
  Json j = Json::object();
  j["states"] = s.states;
  j["branches"] = s.branches;
  j["dead_ends"] = s.dead_ends;
  j["duplicates"] = s.duplicates;
  j["groups"] = s.groups;
  j["seconds"] = s.seconds;
  return j;
}

Json search_json(Json input, const SearchResult& r, const Session& s) {
  Json j = Json::object();
  j["input"] = std::move(input);
  j["status"] = to_string(r.status);
  j["count"] = r.immersions.size();
  j["complete"] = r.complete;
  j["stats"] = stats_json(r.stats);
  j["conflict"] = r.status == ImmersionStatus::Immersible ? Json() : conflict_json(r.conflict);
  Json& list = (j["immersions"] = Json::array());
  for (std::size_t k = 0; k < r.immersions.size(); ++k) list.emplace_back(immersion_json(r.immersions[k], k));
  j["timings_ms"] = s.timings_json();
  return j;
}

namespace {

// ---- 2D JSON pieces -------------------------------------------------------------------------

Json point_json(const dim2::Point& p) { return cli::point_json(std::array{p.x, p.y}); }

/// Counts of the complex, shared by every report.
Json counts_json(const dim2::Complex2& c2) {
  const CellComplex<2>& complex = c2.complex;
  Json j = complex_counts_json(complex);
  j["arrangement_vertices"] = c2.arrangement_vertices;
  j["arrangement_edges"] = c2.arrangement_edges;
  j["arrangement_faces"] = c2.arrangement_faces;
  return j;
}

/// Adds the whole cell complex (paper §4) to the object j: counts, regions (with exact areas and
/// a sample point), cells, patches, arcs (with their crossing point; junctions counter-clockwise).
void add_complex_json(Json& j, const dim2::Complex2& c2) {
  const CellComplex<2>& complex = c2.complex;
  j["counts"] = counts_json(c2);
  Rational total = 0;
  for (RegionId r : ids<RegionId>(complex.region_count())) total += complex.measure(r) * complex.winding_number(r);
  j["winding_weighted_area"] = to_string(total);
  ComplexJsonHooks hooks;
  hooks.region = [&](Json& o, RegionId r) {
    o["area"] = to_string(complex.measure(r));
    o["area_double"] = to_double(complex.measure(r));
    o["sample"] = point_json(c2.region_sample[r]);
  };
  hooks.arc = [&](Json& o, ArcId a) { (o["point"] = point_json(c2.arc_point[a])); };
  hooks.junction_key = "junction_patches_ccw";
  cli::add_complex_json(j, complex, hooks);
}

// ---- input ----------------------------------------------------------------------------------

/// Everything read and built from one input file (see "one prepared input" in cli_common.h).
struct Prepared {
  static constexpr const char* kFacetKey = "segments";
  std::string path;
  dim2::CurveSet curves;
  ValidationReport report;                 ///< defects: exit 2
  std::optional<dim2::Inversion> inversion;///< set: exit 3 (check: a note)
  std::shared_ptr<dim2::Complex2> complex;
  std::optional<dim2::Contacts2> contacts;  ///< exact contacts (resolved unless --strict)
  bool list_contacts = false;               ///< print every contact (check)
  ValidationReport folds;                   ///< local folds: none in 2D (a curve's star is two segments)
};

Json inversion_json(const Prepared& p) {
  const dim2::Inversion& inv = *p.inversion;
  Json j = Json::object();
  j["region"] = inv.region.value();
  j["winding"] = inv.winding_number;
  j["sample"] = point_json(inv.sample);
  j["message"] = inv.message;
  return j;
}

Json input_json(const Prepared& p) {
  Json j = Json::object();
  j["path"] = p.path;
  j["dimension"] = 2;
  j["curves"] = p.curves.curves.size();
  j["vertices"] = p.curves.vertex_count();
  j["reversed"] = p.complex ? Json(p.complex->reversed) : Json();
  if (p.contacts) {
    j["contacts"] = contacts_json({&p.contacts->found, &p.contacts->counts,
                                   p.contacts->perturbation ? &*p.contacts->perturbation : nullptr},
                                  "segments");
  }
  return j;
}

void print_defects(Session& s, const Prepared& p) { cli::print_defects(s, p.path, p.report); }

std::string complex_counts(const dim2::Complex2& c2) { return cli::complex_counts(c2.complex); }

/// Reads, validates and builds the cell complex. @return kExitOk, or kExitInvalidInput after
/// printing every defect. An inversion is left in p.inversion for the caller.
/// @pre the file is not a 3D surface (is_surface_file).
int prepare_curves(Session& s, Prepared& p) {
  dim2::ReadResult read = s.timed("read", [&] { return dim2::read_curves(p.path); });
  p.curves = std::move(read.curves);
  p.report = std::move(read.report);
  if (!p.report.ok()) {
    print_defects(s, p);
    return kExitInvalidInput;
  }
  dim2::BuildOptions2 options;
  options.strict = s.strict();
  dim2::BuildResult built = s.timed("complex", [&] { return dim2::build_complex(p.curves, options); });
  p.contacts = std::move(built.contacts);
  if (p.contacts) {
    print_contacts_note(s, p.path,
                        {&p.contacts->found, &p.contacts->counts,
                         p.contacts->perturbation ? &*p.contacts->perturbation : nullptr},
                        p.list_contacts);
  }
  if (!built.report.ok()) {
    p.report = std::move(built.report);
    print_defects(s, p);
    return kExitInvalidInput;
  }
  p.inversion = std::move(built.inversion);
  p.complex = std::move(built.complex);
  if (p.complex && p.complex->reversed) {
    s.err() << "immerse: note: every winding number of '" << p.path
            << "' is <= 0 (clockwise curves): the input was reversed; winding numbers and patch "
               "directions refer to the reversed curves, vertex and segment ids keep the file order\n";
  }
  if (p.inversion) {
    s.set_counts("inverted region, not immersible");
  } else if (p.complex) {
    s.set_counts(complex_counts(*p.complex));
  }
  return kExitOk;
}

// ---- search ------------------------------------------------------------------------------------

SearchResult run_search(Session& s, const dim2::Complex2& c2, const SearchRequest& request) {
  const SearchOptions options = search_options(s, request);
  return s.timed("search", [&] { return find_immersions(c2.complex, options); });
}

Json search_json(const Prepared& p, const SearchResult& r, const Session& s) {
  return cli::search_json(input_json(p), r, s);
}

// ---- generators -----------------------------------------------------------------------------

struct Generated {
  dim2::CurveSet curves;
  std::string error;  ///< non-empty: unknown name or bad parameters (usage error)
};

std::vector<GeneratorEntry> generator_list() {
  std::vector<GeneratorEntry> out;
  for (const auto& g : dim2::curve_registry().summaries()) out.push_back({g.name, g.params, g.description});
  return out;
}
Generated generate_named(const std::string& name, const std::vector<std::string>& params) {
  auto g = dim2::generate(name, params);
  return {std::move(g.curves), std::move(g.error)};
}
constexpr const char* kDefaultInput = "fig6";

/// The curves as an SVG that the SVG reader reads back exactly: one <polygon> per curve, in
/// input coordinates (no y flip), full precision.
std::string format_curves_svg_input(const dim2::CurveSet& curves) {
  double min_x = 0.0, min_y = 0.0, max_x = 1.0, max_y = 1.0;
  bool first = true;
  for (const dim2::Curve& c : curves.curves) {
    for (const dim2::Point& p : c.vertices) {
      min_x = first ? p.x : std::min(min_x, p.x);
      max_x = first ? p.x : std::max(max_x, p.x);
      min_y = first ? p.y : std::min(min_y, p.y);
      max_y = first ? p.y : std::max(max_y, p.y);
      first = false;
    }
  }
  const double margin = 0.02 * std::max({max_x - min_x, max_y - min_y, 1.0});
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"" +
                    dim2::format_number(min_x - margin) + " " + dim2::format_number(min_y - margin) + " " +
                    dim2::format_number(max_x - min_x + 2 * margin) + " " +
                    dim2::format_number(max_y - min_y + 2 * margin) + "\">\n";
  for (const dim2::Curve& c : curves.curves) {
    out += "<polygon fill=\"none\" stroke=\"black\" vector-effect=\"non-scaling-stroke\" points=\"";
    for (std::size_t i = 0; i < c.vertices.size(); ++i) {
      if (i > 0) out += ' ';
      out += dim2::format_number(c.vertices[i].x) + "," + dim2::format_number(c.vertices[i].y);
    }
    out += "\"/>\n";
  }
  out += "</svg>\n";
  return out;
}

/// The curves in the format chosen by the output extension (.obj: v/l lines; .svg: polygons;
/// else text).
std::string format_curves_for(const std::string& path, const dim2::CurveSet& curves) {
  if (extension_of(path) == ".svg") return format_curves_svg_input(curves);
  if (extension_of(path) != ".obj") return dim2::format_curves_text(curves);
  std::string out = "# immerse generate: one 'l' element per closed curve\n";
  std::size_t base = 1;
  for (const dim2::Curve& c : curves.curves) {
    for (const dim2::Point& p : c.vertices) {
      out += "v ";
      out += dim2::format_number(p.x);
      out += ' ';
      out += dim2::format_number(p.y);
      out += " 0\n";
    }
  }
  for (const dim2::Curve& c : curves.curves) {
    out += "l";
    for (std::size_t i = 0; i <= c.vertices.size(); ++i) {
      out += ' ';
      out += std::to_string(base + i % c.vertices.size());
    }
    out += '\n';
    base += c.vertices.size();
  }
  return out;
}

// ---- commands -------------------------------------------------------------------------------

std::string describe_input(const Prepared& p) {
  return cli::describe_input(p.path, 2, plural(p.curves.curves.size(), "curve") + ", " +
                                            plural(p.curves.vertex_count(), "vertex", "vertices"));
}

void add_complex_report(Json& j, const Prepared& p) { add_complex_json(j, *p.complex); }

int command_check(Session& s, const CommandLine& cl) {
  s.enable_summary();
  if (is_surface_file(cl.positional[0])) return check_surface(s, cl.positional[0]);
  Prepared p;
  p.path = cl.positional[0];
  p.list_contacts = true;
  if (const int code = prepare_curves(s, p); code != kExitOk) return code;
  s.out() << describe_input(p) << ": valid";
  if (p.inversion) {
    s.out() << "\nnote: " << p.inversion->message
            << "\n(the input is valid but not immersible: 'immerse immersions' exits with code 3)\n";
    return kExitOk;
  }
  const CellComplex<2>& c = p.complex->complex;
  s.out() << " (" << plural(c.arc_count(), "crossing") << ", " << plural(c.cell_count(), "cell")
          << ", max winding number " << c.max_winding_number() << (p.complex->reversed ? ", reversed" : "") << ")\n";
  return kExitOk;
}

int command_cells(Session& s, const CommandLine& cl) {
  if (is_surface_file(cl.positional[0])) {
    s.enable_summary();
    return cells_surface(s, cl);
  }
  if (cl.has("--cut-mesh")) return usage_error(s.env(), "cells", "--cut-mesh needs a 3D surface input");
  if (cl.has("--repair-folds")) return usage_error(s.env(), "cells", "--repair-folds is for 3D surfaces only");
  s.enable_summary();
  Prepared p;
  p.path = cl.positional[0];
  const auto json_path = cl.value("--json");
  if (const int code = prepare_complex_or_report(s, p, json_path, [&] { return prepare_curves(s, p); }); code != kExitOk) return code;
  s.out() << describe_input(p) << (p.complex->reversed ? " (reversed)" : "") << '\n';
  print_cell_table(s, p.complex->complex, "crossings", "", "area");
  if (json_path && !s.write(*json_path, cells_report_json(p, s).dump(2) + "\n", "the cell complex (JSON)")) {
    return kExitInternalError;
  }
  print_written(s);
  return kExitOk;
}

/// --all / --max / --max-states / --time-limit. @return a usage error message, or empty.
}  // namespace

std::vector<OptionSpec> mesh_choice_options(bool full_help) {
  if (full_help) {
    return {
      {"--resolution", ValueKind::Integer, "N",
       "2D: background edges across the bounding-box diagonal (default 24). 3D: grid cubes (6 Kuhn tets "
       "each) along the longest side of the input's box (at most 150; default 16); the grid is shifted "
       "and retried when it touches the input non-generically",
       1, 100'000},
      {"--surface-resolution", ValueKind::Integer, "M",
       "(3D) a graded background instead of the uniform grid: the Kuhn grid refined by conforming bisection "
       "to cubes of side (longest side / M) where it meets the input, --resolution (default 8) far from it "
       "(rounded to a power-of-two multiple of the surface side); its minimum dihedral angle is reported",
       1, 4096},
      {"--gap-resolution", ValueKind::Integer, "G",
       "(3D, with --surface-resolution) finer cubes (longest side / G, rounded to a power-of-two fraction of "
       "the surface side) where two separate pieces of the input come within about one element: near "
       "self-intersections such as the comb's teeth or the lips of a mouth",
       1, 16384},
      {"--background", ValueKind::Text, "FILE",
       "a background mesh instead of the grid: 2D a Medit .mesh (Dimension 2); 3D Vega .veg, Medit "
       ".mesh, TetGen .node/.ele, Gmsh .msh 4.1 (it must cover the input and meet it generically, else exit 2)"},
      {"--conforming", ValueKind::Flag, "",
       "insert the input as constraints: 2D, no triangle is cut by the curve; 3D, TetGen's constrained Delaunay "
       "tets whose boundary faces are exactly the input triangles cut along the intersection curves (no "
       "background, no virtual tets; each input vertex is an output vertex)"},
      {"--edge-length", ValueKind::Real, "H",
       "(3D --conforming) target edge length inside the cells (TetGen volume bound of the regular tet of edge H; "
       "default: longest side of the input's box / resolution)"},
      {"--radius-edge", ValueKind::Real, "R",
       "(3D --conforming) radius-edge ratio bound of TetGen's quality refinement, >= 1 (default 2)"},
      {"--min-dihedral", ValueKind::Real, "DEG",
       "(3D --conforming) minimum dihedral angle TetGen aims for, up to 30 degrees (default none; slivers on the "
       "preserved surface may stay: the JSON counts them)"},
    };
  }
  const std::string same = "as for 'immerse mesh'";
  return {
      {"--resolution", ValueKind::Integer, "N", same, 1, 100'000},
      {"--surface-resolution", ValueKind::Integer, "M", "(3D) a graded background, " + same, 1, 4096},
      {"--gap-resolution", ValueKind::Integer, "G", "(3D, with --surface-resolution) " + same, 1, 16384},
      {"--background", ValueKind::Text, "FILE", same},
      {"--conforming", ValueKind::Flag, "",
       "the conforming mesh of 'immerse mesh --conforming' (3D: TetGen's tets; --glued: its tets glued back)"},
      {"--edge-length", ValueKind::Real, "H", "(3D --conforming) " + same},
      {"--radius-edge", ValueKind::Real, "R", "(3D --conforming) " + same},
      {"--min-dihedral", ValueKind::Real, "DEG", "(3D --conforming) " + same},
  };
}

std::string parse_mesh_choice(const CommandLine& cl, bool surface, MeshChoice& choice) {
  choice = MeshChoice{};
  choice.conforming = cl.has("--conforming");
  if (cl.has("--resolution") && cl.has("--background")) return "--resolution and --background exclude each other";
  if (cl.has("--surface-resolution") && cl.has("--background"))
    return "--surface-resolution and --background exclude each other";
  if (cl.has("--gap-resolution") && !cl.has("--surface-resolution")) return "--gap-resolution needs --surface-resolution";
  if (choice.conforming)
    for (const char* option : {"--background", "--surface-resolution"})
      if (cl.has(option)) return std::string(option) + " is for the background mesher, not --conforming";
  if (!surface)
    for (const char* option : {"--surface-resolution", "--gap-resolution", "--edge-length", "--radius-edge", "--min-dihedral"})
      if (cl.has(option)) return std::string(option) + " is for 3D surfaces only";
  if (!choice.conforming)
    for (const char* option : {"--edge-length", "--radius-edge", "--min-dihedral"})
      if (cl.has(option)) return std::string(option) + " needs --conforming";
  if (auto n = cl.integer("--resolution")) choice.resolution = static_cast<int>(*n);
  if (auto v = cl.value("--background")) choice.background = *v;
  if (!surface) return {};
  if (choice.resolution)
    if (std::string error = check_resolution3(*choice.resolution); !error.empty()) return error;
  if (choice.background && !dim3::is_tet_mesh_extension(*choice.background))
    return "--background " + *choice.background + ": expected a .veg, .mesh, .node, .ele or .msh tet mesh";
  if (auto m = cl.integer("--surface-resolution")) {
    // Graded: --resolution is the far size; sizes only grow finer toward the surface and gaps.
    dim3::GradedOptions graded;
    graded.far_resolution = choice.resolution.value_or(8);
    graded.surface_resolution = static_cast<int>(*m);
    graded.gap_resolution = static_cast<int>(cl.integer("--gap-resolution").value_or(0));
    if (std::string error =
            dim3::graded_order_error(graded, {"--resolution", "--surface-resolution", "--gap-resolution"});
        !error.empty())
      return error;
    choice.graded = graded;
  }
  if (choice.conforming) return parse_conforming3(cl, choice.conforming3);
  return {};
}

namespace {

std::string parse_search_request(const CommandLine& cl, SearchRequest& request) {
  if (cl.has("--all") && cl.has("--max")) return "--all and --max exclude each other";
  if (cl.has("--all")) request.max_immersions = 0;
  if (auto n = cl.integer("--max")) request.max_immersions = static_cast<std::size_t>(*n);
  if (auto n = cl.integer("--max-states")) request.max_states = static_cast<std::size_t>(*n);
  if (auto t = cl.real("--time-limit")) request.time_limit = *t;
  request.classic_search = cl.has("--classic-search");
  return {};
}

/// --max-output and --time-limit bound every write of the command (issue 13).
void bound_outputs(Session& s, const CommandLine& cl, const SearchRequest& request) {
  const auto max = cl.integer("--max-output");
  s.bound_outputs(max ? static_cast<std::uint64_t>(*max) : kDefaultMaxOutput, request.time_limit);
}

void print_search_result(Session& s, const Prepared& p, const SearchResult& r, const SearchRequest& request) {
  if (r.status != ImmersionStatus::Immersible) {
    print_no_immersion(s, p.path, r);
    return;
  }
  print_immersion_list(s, describe_input(p) + (p.complex->reversed ? " (reversed)" : ""), r, request);
}

/// Writes DIR/immersion_K.svg for every immersion. @return false on a write failure.
bool write_immersion_svgs(Session& s, const Prepared& p, const SearchResult& r, const std::string& dir) {
  for (std::size_t k = 0; k < r.immersions.size(); ++k) {
    // Refused before the first drawing when all of them would not fit the output budget (65,536
    // drawings of a doodle chain were about 15 GB); the time limit is checked at every file.
    if (k == 0) {
      const std::size_t first = dim2::format_immersion_svg(*p.complex, r.immersions[0], {}).size();
      if (!s.can_write(static_cast<std::uint64_t>(first) * r.immersions.size(),
                       std::to_string(r.immersions.size()) + " SVG drawings")) {
        return false;
      }
    }
    dim2::SvgOptions options;
    options.title = "immersion " + std::to_string(k) + " of " + std::to_string(r.immersions.size()) +
                    (r.complete ? "" : "+") + ": " + std::filesystem::path(p.path).filename().string();
    const std::string path = (std::filesystem::path(dir) / ("immersion_" + std::to_string(k) + ".svg")).string();
    if (!s.write(path, dim2::format_immersion_svg(*p.complex, r.immersions[k], options),
                 "immersion " + std::to_string(k) + " (SVG: cell copies, owned/declined patches, graph edges)")) {
      return false;
    }
  }
  return true;
}

int command_immersions(Session& s, const CommandLine& cl) {
  SearchRequest request;
  if (std::string error = parse_search_request(cl, request); !error.empty()) {
    return usage_error(s.env(), "immersions", error);
  }
  bound_outputs(s, cl, request);
  if (is_surface_file(cl.positional[0])) {
    if (cl.has("--svg")) return usage_error(s.env(), "immersions", "--svg draws 2D immersions only");
    s.enable_summary();
    return immersions_surface(s, cl, request);
  }
  for (const char* option : {"--no-helper-boxes", "--repair-folds"})
    if (cl.has(option)) return usage_error(s.env(), "immersions", std::string(option) + " applies to 3D surfaces only");
  s.enable_summary();
  Prepared p;
  p.path = cl.positional[0];
  const auto json_path = cl.value("--json");
  if (const int code = prepare_complex_or_report(s, p, json_path, [&] { return prepare_curves(s, p); }); code != kExitOk) return code;
  const SearchResult r = run_search(s, *p.complex, request);
  s.set_counts(complex_counts(*p.complex) + ", " + immersion_counts(r));
  print_search_result(s, p, r, request);
  // The JSON of every immersion is estimated from the first before it is built (a chain of 16
  // doodles made 6.1 GB of memory for a 657 MB file).
  const bool json_fits = !json_path || r.immersions.empty() ||
                         s.can_write(static_cast<std::uint64_t>(immersion_json(r.immersions[0], 0).dump(2).size()) *
                                         r.immersions.size(),
                                     "the immersions (JSON)");
  const auto failed = [&] { return s.time_limit_reached() ? kExitNotImmersible : kExitInternalError; };
  if (json_path && (!json_fits || !s.write(*json_path, search_json(p, r, s).dump(2) + "\n", "the immersions (JSON)"))) {
    print_written(s);
    return failed();
  }
  if (auto dir = cl.value("--svg"); dir && !write_immersion_svgs(s, p, r, *dir)) {
    print_written(s);
    return failed();
  }
  print_written(s);
  return r.status == ImmersionStatus::Immersible ? kExitOk : kExitNotImmersible;
}

Json mesh_json(const Prepared& p, const SearchResult& r, std::size_t k, const dim2::MeshOptions& options,
               const dim2::MeshResult& m, const CommandLine& cl, const Session& s) {
  Json j = Json::object();
  j["input"] = input_json(p);
  j["status"] = "ok";
  j["immersion"] = k;
  j["immersions_found"] = r.immersions.size();
  Json& o = (j["options"] = Json::object());
  o["resolution"] = options.background_path ? Json() : Json(options.resolution);
  o["background"] = options.background_path ? Json(*options.background_path) : Json();
  o["conforming"] = options.conforming;
  o["method"] = options.method == MeshMethod::Csg ? "csg" : "clip";
  Json& c = (j["counts"] = Json::object());
  c["input_vertices"] = p.curves.vertex_count();
  c["background_triangles"] = m.stats.background_triangles;
  c["cut_triangles"] = m.stats.cut_triangles;
  c["output_triangles"] = m.stats.output_triangles;
  c["output_vertices"] = m.stats.output_vertices;
  c["embedded_vertices"] = m.embedding.size();
  c["embedding_error"] = m.stats.embedding_error;
  c["graph_nodes"] = r.immersions[k].layout.node_count();
  Json& per_cell = (c["copies_per_cell"] = Json::array());
  for (std::size_t n : m.stats.copies_per_cell) per_cell.emplace_back(n);
  Json& phases = (j["mesh_phases_ms"] = Json::object());
  phases["background"] = m.stats.seconds_background * 1e3;
  phases["virtual"] = m.stats.seconds_virtual * 1e3;
  phases["assembly"] = m.stats.seconds_assembly * 1e3;
  Json& outputs = (j["outputs"] = Json::object());
  for (const char* option : {"-o", "--embedding", "--svg"}) {
    const auto v = cl.value(option);
    outputs[std::string(option) == "-o" ? "mesh" : std::string(option).substr(2)] = v ? Json(*v) : Json();
  }
  j["timings_ms"] = s.timings_json();
  return j;
}

/// Meshes immersion k and writes the requested outputs (paths in `cl`: -o, --embedding, --svg,
/// --json). @return the exit code.
int mesh_and_write(Session& s, const Prepared& p, const SearchResult& r, std::size_t k,
                   const dim2::MeshOptions& options, const CommandLine& cl) {
  dim2::MeshOptions mesh_options = options;
  if (s.show_progress()) mesh_options.progress = [&s](const std::string& m) { s.err() << "immerse: mesh: " << m << '\n'; };
  const dim2::MeshResult m =
      s.timed("mesh", [&] { return dim2::mesh_immersion(*p.complex, r.immersions[k], mesh_options); });
  if (!m.report.ok()) {
    s.err() << "immerse: " << cannot_mesh_message(p.path, m.report, kMaxDefectLines) << '\n';
    s.set_counts("meshing failed (" + plural(m.report.defects.size(), "defect") + ")");
    if (auto json_path = cl.value("--json")) {
      Json j = Json::object();
      j["input"] = input_json(p);
      j["status"] = "invalid-input";
      j["defects"] = defects_json(m.report, "segments");
      j["timings_ms"] = s.timings_json();
      if (!s.write(*json_path, j.dump(2) + "\n", "report")) return kExitInternalError;
    }
    return kExitInvalidInput;
  }
  s.set_counts(complex_counts(*p.complex) + ", " + immersion_counts(r) + ", " +
               plural(m.stats.output_triangles, "triangle"));
  s.out() << describe_input(p) << ": immersion " << k << " of " << r.immersions.size() << (r.complete ? "" : "+")
          << " meshed: " << plural(m.stats.output_triangles, "triangle") << ", "
          << plural(m.stats.output_vertices, "vertex", "vertices") << " (background "
          << plural(m.stats.background_triangles, "triangle") << ", " << m.stats.cut_triangles
          << " cut by the input)\n";
  warn_embedding_error(s, m.stats.embedding_error);
  if (auto path = cl.value("-o"); path && !s.write(*path, dim2::format_medit_2d(m.mesh), "the mesh (Medit, reference = graph node)")) {
    return kExitInternalError;
  }
  if (auto path = cl.value("--embedding");
      path && !s.write(*path, dim2::format_embedding(m.embedding), "the embedding of the input vertices")) {
    return kExitInternalError;
  }
  if (auto path = cl.value("--svg");
      path && !s.write(*path, dim2::format_mesh_svg(*p.complex, r.immersions[k], m), "the mesh pulled apart (SVG)")) {
    return kExitInternalError;
  }
  if (auto path = cl.value("--json");
      path && !s.write(*path, mesh_json(p, r, k, mesh_options, m, cl, s).dump(2) + "\n", "mesh counts and timings (JSON)")) {
    return kExitInternalError;
  }
  return kExitOk;
}


int command_mesh(Session& s, const CommandLine& cl) {
  const CliEnvironment& env = s.env();
  const bool surface = is_surface_file(cl.positional[0]);
  MeshChoice choice;
  if (const std::string error = parse_mesh_choice(cl, surface, choice); !error.empty())
    return usage_error(env, "mesh", error);
  MeshMethod method = MeshMethod::Clip;
  std::size_t k = 0;
  if (auto n = cl.integer("--immersion")) k = static_cast<std::size_t>(*n);
  if (auto v = cl.value("--method")) {
    if (*v == "csg") {
      method = MeshMethod::Csg;
    } else if (*v != "clip") {
      return usage_error(env, "mesh", "--method expects 'clip' or 'csg', got '" + *v + "'");
    }
  }
  SearchRequest request;
  if (std::string error = parse_search_request(cl, request); !error.empty()) return usage_error(env, "mesh", error);
  bound_outputs(s, cl, request);
  const bool all = cl.has("--all");
  request.max_immersions = all ? 0 : k + 1;
  if (surface) {
    dim3::MeshOptions options3 = choice.options3();
    options3.method = method;
    if (auto n = cl.integer("--threads")) options3.threads = static_cast<unsigned>(*n);
    if (all && cl.has("--immersion")) return usage_error(env, "mesh", "--all and --immersion exclude each other");
    // --conforming: TetGen's tets; the edge length defaults to the grid's cube side.
    return mesh_surface(s, cl, request, options3, k, all, choice.conforming ? &choice.conforming3 : nullptr);
  }
  for (const char* option : {"--all", "--threads", "--no-helper-boxes", "--repair-folds"})
    if (cl.has(option)) return usage_error(env, "mesh", std::string(option) + " is for 3D surfaces only");
  // The 2D mesh is written as Medit only (x.vtu held Medit text before).
  if (auto path = cl.value("-o"); path && extension_of(*path) != ".mesh" && !is_stream_output(*path))
    return usage_error(env, "mesh", "-o " + *path + ": a 2D triangle mesh is written as .mesh (Medit)");
  if (choice.conforming && cl.has("--method"))  // the CSG baseline clips background triangles; a conforming mesh has none cut
    return usage_error(env, "mesh", "--method is for the background mesher, not --conforming");

  s.enable_summary();
  Prepared p;
  p.path = cl.positional[0];
  const auto json_path = cl.value("--json");
  if (const int code = prepare_complex_or_report(s, p, json_path, [&] { return prepare_curves(s, p); }); code != kExitOk) return code;
  const SearchResult r = run_search(s, *p.complex, request);
  if (r.status != ImmersionStatus::Immersible) {
    s.set_counts(complex_counts(*p.complex) + ", " + immersion_counts(r));
    print_no_immersion(s, p.path, r);
    if (json_path && !s.write(*json_path, search_json(p, r, s).dump(2) + "\n", "report")) return kExitInternalError;
    print_written(s);
    return kExitNotImmersible;
  }
  if (r.immersions.size() <= k) {
    s.set_counts(complex_counts(*p.complex) + ", " + immersion_counts(r));
    return usage_error(env, "mesh",
                       immersion_index_message(k, p.path, r.immersions.size(), r.complete, kProgramOptions));
  }
  dim2::MeshOptions options = choice.options2();
  options.method = method;
  const int code = mesh_and_write(s, p, r, k, options, cl);
  print_written(s);
  return code;
}

int command_generate(Session& s, const CommandLine& cl) {
  if (cl.has("--list")) {
    if (!cl.positional.empty()) return usage_error(s.env(), "generate", "--list takes no name");
    const auto curves = generator_list();
    const auto surfaces = surface_generator_list();
    std::size_t width = 0;
    for (const auto* list : {&curves, &surfaces}) {
      for (const auto& g : *list) width = std::max(width, g.name.size() + 1 + g.params.size());
    }
    const auto print = [&](const std::vector<GeneratorEntry>& list) {
      for (const auto& g : list) {
        const std::string head = g.name + (g.params.empty() ? "" : " " + g.params);
        s.out() << "  " << head << std::string(width - head.size() + 2, ' ') << g.description << '\n';
      }
    };
    s.out() << "2D curves (text, .svg or .obj output):\n";
    print(curves);
    s.out() << "3D surfaces (.obj or .off output):\n";
    print(surfaces);
    return kExitOk;
  }
  if (cl.positional.empty()) return usage_error(s.env(), "generate", "missing generator name");
  const std::string& name = cl.positional[0];
  const std::vector<std::string> params(cl.positional.begin() + 1, cl.positional.end());
  if (dim2::curve_registry().find(name) == nullptr && is_surface_generator(name)) {
    return command_generate_surface(s, name, params, cl.value("-o"));
  }
  Generated g;
  const Clock::time_point start = Clock::now();
  g = generate_named(name, params);
  if (!g.error.empty()) return usage_error(s.env(), "generate", g.error);
  s.enable_summary();
  s.add_time("generate", seconds_since(start));
  s.set_counts("generated '" + name + "': " + plural(g.curves.curves.size(), "curve") + ", " +
               plural(g.curves.vertex_count(), "vertex", "vertices"));
  const auto out = cl.value("-o");
  if (!out) {
    s.out() << dim2::format_curves_text(g.curves);
    return kExitOk;
  }
  if (!s.write(*out, format_curves_for(*out, g.curves), "curve '" + name + "' (" + plural(g.curves.vertex_count(), "vertex", "vertices") + ")")) {
    return kExitInternalError;
  }
  print_written(s);
  return kExitOk;
}

/// `immerse` without arguments: the whole pipeline on the bundled curve, into ./out/.
int command_default(Session& s) {
  s.enable_summary();
  const std::filesystem::path dir = "out";
  const auto at = [&](const std::string& name) { return (dir / name).string(); };
  const Generated g = s.timed("generate", [&] { return generate_named(kDefaultInput, {}); });
  if (!g.error.empty()) {
    s.err() << "immerse: internal error: the bundled curve '" << kDefaultInput << "' is not available: " << g.error << '\n';
    return kExitInternalError;
  }
  s.out() << "immerse: no command given: running the main job on the bundled curve '" << kDefaultInput
          << "' (see 'immerse --help')\n";
  if (!s.write(at("input.txt"), dim2::format_curves_text(g.curves), "the input curve (text format)") || !s.commit()) {
    return kExitInternalError;
  }
  // Read the written file back: the job then runs exactly on what a user can re-run.
  Prepared p;
  p.path = at("input.txt");
  if (const int code = prepare_curves(s, p); code != kExitOk) return code;
  if (p.inversion) {
    print_inversion(s, p);
    return kExitNotImmersible;
  }
  dim2::SvgOptions svg_options;
  svg_options.title = std::string("input '") + kDefaultInput + "': cells and winding numbers";
  if (!s.write(at("input.svg"), dim2::format_complex_svg(*p.complex, svg_options),
               "the input curve: directions, crossings, cells with winding numbers (SVG)") ||
      !s.write(at("cells.json"), cells_report_json(p, s).dump(2) + "\n", "the cell complex (JSON)")) {
    return kExitInternalError;
  }
  SearchRequest request;
  request.max_immersions = 0;
  const SearchResult r = run_search(s, *p.complex, request);
  s.set_counts(complex_counts(*p.complex) + ", " + immersion_counts(r));
  print_search_result(s, p, r, request);
  if (!s.write(at("immersions.json"), search_json(p, r, s).dump(2) + "\n", "every immersion: nodes, edges, owners (JSON)") ||
      !write_immersion_svgs(s, p, r, dir.string())) {
    return kExitInternalError;
  }
  int code = kExitNotImmersible;
  if (r.status == ImmersionStatus::Immersible) {
    CommandLine outputs;
    outputs.values = {{"-o", at("mesh.mesh")}, {"--embedding", at("mesh.emb")}, {"--svg", at("mesh.svg")},
                      {"--json", at("mesh.json")}};
    code = mesh_and_write(s, p, r, 0, dim2::MeshOptions{}, outputs);
  }
  s.out() << "files written into " << dir.string() << "/:\n";
  print_written(s);
  return code;
}

/// One file a command line asks for: the option, its path, and whether `--all` numbers it
/// (PATH_K.ext per immersion K).
struct OutputFile {
  std::string option;  ///< "-o", "--json", "-o (its .ele)", ...
  std::string path;
  bool numbered = false;
  bool derived = false;  ///< not an option's own path (TetGen's .ele beside -o's .node)
};

/// The files of `cl`'s file-valued output options (not the directories of `immersions --svg`
/// and `deform -o`), with the ones derived from them: TetGen's .ele beside a .node.
std::vector<OutputFile> output_files(const std::string& command, const CommandLine& cl) {
  std::vector<OutputFile> files;
  const bool all = command == "mesh" && cl.has("--all");
  for (const char* option : {"-o", "--json", "--embedding", "--svg", "--cut-mesh"}) {
    if ((command == "immersions" && std::string(option) == "--svg") || (command == "deform" && std::string(option) == "-o"))
      continue;
    const auto path = cl.value(option);
    if (!path) continue;
    const bool numbered = all && (std::string(option) == "-o" || std::string(option) == "--embedding");
    if (command == "mesh" && std::string(option) == "-o" && extension_of(*path) == ".node") {
      const auto [node, ele] = dim3::tetgen_paths(*path);
      files.push_back({option, node, numbered});
      files.push_back({"the .ele of -o '" + *path + "':", ele, numbered, true});
    } else {
      files.push_back({option, *path, numbered});
    }
  }
  return files;
}

/// Whether `a` and `b` can name the same file (numbered ones: for some immersion K).
bool same_output(const OutputFile& a, const OutputFile& b) {
  // A FIFO or device takes every output written to it (`-o /dev/null --json /dev/null`).
  if (is_stream_output(a.path) || is_stream_output(b.path)) return false;
  if (a.numbered == b.numbered) {
    const std::string pa = a.numbered ? numbered_output(a.path, 0) : a.path;
    const std::string pb = b.numbered ? numbered_output(b.path, 0) : b.path;
    return output_identity(pa) == output_identity(pb);
  }
  const OutputFile& n = a.numbered ? a : b;  // PATH_K.ext against a plain path: which K would it be?
  const OutputFile& plain = a.numbered ? b : a;
  const std::string ext = extension_of(plain.path);
  const std::string stem = plain.path.substr(0, plain.path.size() - ext.size());
  const std::size_t underscore = stem.rfind('_');
  if (underscore == std::string::npos || underscore + 1 == stem.size()) return false;
  std::size_t k = 0;
  const char* first = stem.data() + underscore + 1;
  const char* last = stem.data() + stem.size();
  if (const auto [ptr, ec] = std::from_chars(first, last, k); ec != std::errc() || ptr != last) return false;
  return output_identity(numbered_output(n.path, k)) == output_identity(plain.path);
}

/// An output path naming an input file (the same file, by any path): `weights in.obj -o in.obj`
/// replaced the surface by the weights' VTU; or two outputs naming one file (`-o a.mesh
/// --embedding a.mesh` kept only the embedding). Empty when there is none, else the usage message.
std::string output_clash(const std::string& command, const CommandLine& cl) {
  std::vector<std::pair<std::string, std::string>> inputs;
  if (!cl.positional.empty()) inputs.emplace_back("the input", cl.positional[0]);
  for (const char* option : {"--background", "--handles"})
    if (auto v = cl.value(option)) inputs.emplace_back(std::string("the ") + option + " file", *v);
  for (const char* option : {"-o", "--json", "--embedding", "--svg", "--cut-mesh"}) {
    const auto out = cl.value(option);
    if (!out) continue;
    for (const auto& [what, in] : inputs) {
      std::error_code ec;
      if (std::filesystem::equivalent(*out, in, ec) && !ec)
        return std::string(option) + " '" + *out + "' is " + what + " '" + in + "'; it would be replaced";
    }
  }
  // The options' own paths were checked against the inputs above; the files derived from them
  // (a .node's .ele) are checked here, and every pair of outputs.
  const std::vector<OutputFile> files = output_files(command, cl);
  for (std::size_t i = 0; i < files.size(); ++i) {
    for (const auto& [what, in] : inputs) {
      std::error_code ec;
      if (files[i].derived && !files[i].numbered && std::filesystem::equivalent(files[i].path, in, ec) && !ec)
        return files[i].option + " '" + files[i].path + "' is " + what + " '" + in + "'; it would be replaced";
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (!same_output(files[j], files[i])) continue;
      const auto shown = [](const OutputFile& f) {
        return f.option + " '" + f.path + "'" + (f.numbered ? " (numbered by --all)" : "");
      };
      return shown(files[j]) + " and " + shown(files[i]) + " name the same file; one would replace the other";
    }
  }
  return {};
}

int dispatch(Session& s, const std::vector<std::string>& args) {
  const CliEnvironment& env = s.env();
  if (args.empty()) return command_default(s);
  const std::string& command = args[0];
  if (command == "--help" || command == "-h" || command == "help") {
    if (args.size() > 2) return usage_error(env, "", "'help' takes at most one command name");
    if (args.size() == 2 && command == "help") {
      const CommandSpec* spec = find_command(args[1]);
      if (spec == nullptr) return usage_error(env, "", "unknown command '" + args[1] + "'");
      env.out << command_help(*spec);
      return kExitOk;
    }
    if (args.size() == 2) return usage_error(env, "", "unexpected argument '" + args[1] + "'");
    env.out << kMainHelp;
    return kExitOk;
  }
  const CommandSpec* spec = find_command(command);
  if (spec == nullptr) {
    if (!command.empty() && command[0] == '-') return usage_error(env, "", "unknown option '" + command + "'");
    return usage_error(env, "", "unknown command '" + command + "'");
  }
  CommandLine cl;
  if (auto code = parse_command(env, *spec, std::vector<std::string>(args.begin() + 1, args.end()), cl)) return *code;
  if (const std::string clash = output_clash(command, cl); !clash.empty()) return usage_error(env, command, clash);
  s.set_strict(cl.has("--strict"));
  s.set_repair_folds(cl.real("--repair-folds"));
  if (command == "check") return command_check(s, cl);
  if (command == "cells") return command_cells(s, cl);
  if (command == "immersions") return command_immersions(s, cl);
  if (command == "mesh") return command_mesh(s, cl);
  if (command == "deform" || command == "weights") return command_deform_or_weights(s, cl, command);
  if (command == "render") return command_render(s, cl);
  return command_generate(s, cl);
}

}  // namespace
}  // namespace imm::cli

namespace imm {

int run_cli(const std::vector<std::string>& args, const CliEnvironment& env) {
  cli::Session session(env);
  int code = kExitInternalError;
  try {
    code = cli::dispatch(session, args);
  } catch (const InvariantError& e) {
    env.err << "immerse: internal error (a bug, please report it): " << e.what() << '\n';
    code = kExitInternalError;
  } catch (const std::exception& e) {
    env.err << "immerse: internal error: " << e.what() << '\n';
    code = kExitInternalError;
  }
  // The outputs land together or not at all: staged until here (or an earlier print_written).
  if (!session.finish(code)) code = kExitInternalError;
  if (session.output_collision()) code = kExitUsage;
  session.print_summary();
  return code;
}

}  // namespace imm
