// Internal to the `immerse` command line (app/cli.cpp, app/cli_surface.cpp): the pieces both
// dimensions' commands share. Not a library API: nothing outside the `immerse` target includes it.
//
//  - Session: timings per stage, the one-line summary, atomic writes and the list of written files;
//  - CommandLine: a parsed command line (parsing itself stays in cli.cpp);
//  - messages and exit-code helpers (usage errors, defects, search verdicts);
//  - JSON writers that read only dimension-generic data (reports, conflicts, immersions, and the
//    combinatorial cell complex through hooks for the dimension's geometry).
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <ostream>
#include <set>
#include <span>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/atomic_file.h"
#include "core/output_budget.h"
#include "core/cell_complex.h"
#include "app/cli.h"
#include "app/command_line.h"
#include "core/diagnostics.h"
#include "core/perturbation.h"
#include "core/graph_search.h"
#include "core/verdicts.h"
#include "dim2/mesh2.h"
#include "dim3/conforming_mesh3.h"
#include "dim3/mesh3.h"

#include <sys/stat.h>

#include <nlohmann/json.hpp>

namespace imm::cli {

/// Every JSON the program writes: keys in insertion order (DESIGN §3).
using Json = nlohmann::ordered_json;

using Clock = std::chrono::steady_clock;

/// The default output budget of one command (--max-output): 4 GiB in all files.
inline constexpr std::uint64_t kDefaultMaxOutput = std::uint64_t{4} << 30;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// At most this many rows in the tables printed on stdout (the JSON has everything).
inline constexpr std::size_t kMaxTableRows = 40;

// ---- small text helpers (cli.cpp) -------------------------------------------------------------

std::string lower(std::string s);
/// The extension with its dot, lower case (".obj").
std::string extension_of(const std::string& path);
/// "0.52 ms", "12.3 ms", "1234 ms".
std::string format_ms(double seconds);

// ---- the command line --------------------------------------------------------------------------

/// Prints "immerse COMMAND: message", the command's usage line and a pointer to its --help.
/// @return kExitUsage.
int usage_error(const CliEnvironment& env, const std::string& command, const std::string& message);

/// The search budgets and count asked for on the command line.
struct SearchRequest {
  std::size_t max_immersions = 1;
  std::size_t max_states = SearchOptions{}.max_states;
  double time_limit = 0.0;
  bool classic_search = false;  ///< --classic-search: SearchOptions::sheets_first, continue_sheets off
};

/// Empty when `resolution` is a usable 3D grid resolution, else the usage message (the commands
/// that mesh a surface on a generated grid: mesh, deform, weights).
inline std::string check_resolution3(int resolution) {
  if (resolution <= dim3::kMaxGridResolution) return {};
  return "--resolution " + std::to_string(resolution) + ": at most " + std::to_string(dim3::kMaxGridResolution) +
         " grid cubes along the longest side in 3D";
}

/// --edge-length, --radius-edge, --min-dihedral of the 3D conforming mesher (mesh, deform,
/// weights), into `options` (edge_length 0: not given, see conforming_edge_length).
/// @return a usage error message, or empty.
inline std::string parse_conforming3(const CommandLine& cl, dim3::ConformingOptions& options) {
  options.edge_length = 0.0;
  if (auto h = cl.real("--edge-length")) {
    if (!std::isfinite(*h)) return "--edge-length expects a positive number";
    options.edge_length = *h;
  }
  if (auto r = cl.real("--radius-edge")) {
    if (!(*r >= 1.0 && std::isfinite(*r))) return "--radius-edge expects a number >= 1";
    options.radius_edge = *r;
  }
  if (auto a = cl.real("--min-dihedral")) {
    if (!(*a <= 30.0)) return "--min-dihedral expects degrees in (0, 30]";
    options.min_dihedral = *a;
  }
  return {};
}

/// `options`' edge length defaulted, when not given, to the grid's cube side for `surface`
/// (dim3::conforming_edge_length at `resolution`): mesh, deform and weights alike.
/// @return a usage error when the input's box gives no usable length, else empty.
inline std::string default_edge_length(const dim3::Surface& surface, int resolution, dim3::ConformingOptions& options) {
  if (options.edge_length == 0.0) options.edge_length = dim3::conforming_edge_length(surface, resolution);
  if (options.edge_length > 0 && std::isfinite(options.edge_length)) return {};
  return "--conforming: the input's box is flat or not finite; pass --edge-length";
}

// ---- how mesh, deform and weights mesh their input ---------------------------------------------

/// The mesher options `mesh`, `deform` and `weights` share: a generated grid (uniform, or graded
/// toward the surface in 3D), a background file, or the conforming mesher with its sizes. Parsed
/// and checked in one place (parse_mesh_choice), so the three commands accept the same options and
/// refuse the same combinations with the same messages.
struct MeshChoice {
  std::optional<int> resolution;              ///< --resolution, as given
  std::optional<std::string> background;      ///< --background FILE
  std::optional<dim3::GradedOptions> graded;  ///< --surface-resolution [--gap-resolution] (3D)
  bool conforming = false;                    ///< --conforming
  dim3::ConformingOptions conforming3;        ///< its sizes (edge_length 0: conforming_edge_length)

  /// The 2D mesher's options of this choice.
  [[nodiscard]] dim2::MeshOptions options2() const {
    dim2::MeshOptions o;
    if (resolution) o.resolution = *resolution;
    o.background_path = background;
    o.conforming = conforming;
    return o;
  }
  /// The 3D background mesher's options of this choice.
  [[nodiscard]] dim3::MeshOptions options3() const {
    dim3::MeshOptions o;
    if (resolution) o.resolution = *resolution;
    o.background_path = background;
    o.graded = graded;
    return o;
  }
};

/// The option specs of MeshChoice, for the commands' --help (`what`: "" for mesh, whose help
/// explains them; "as for 'immerse mesh'" style pointers otherwise).
std::vector<OptionSpec> mesh_choice_options(bool full_help);

/// Reads and checks the options of MeshChoice; `surface`: the input is a 3D surface (the graded
/// and conforming sizes are 3D only). @return a usage error message, or empty.
std::string parse_mesh_choice(const CommandLine& cl, bool surface, MeshChoice& choice);

/// Whether `path` (links followed) is an existing FIFO or character device (/dev/null,
/// /dev/stdout on a pipe): written through, in the default format whatever its name.
inline bool is_stream_output(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && (S_ISFIFO(st.st_mode) || S_ISCHR(st.st_mode));
}

// ---- one run: timings, counts, written files -------------------------------------------------

class Session {
 public:
  explicit Session(const CliEnvironment& env) : env_(env) {}

  [[nodiscard]] const CliEnvironment& env() const { return env_; }
  std::ostream& out() const { return env_.out; }
  std::ostream& err() const { return env_.err; }
  [[nodiscard]] bool show_progress() const { return env_.show_progress; }
  /// A progress callback printing "immerse: <stage>: message" ("immerse: message" for an empty
  /// stage, when the library's messages name their stages) when progress is wanted, else empty.
  [[nodiscard]] LogCallback progress(const std::string& stage) const {
    if (!show_progress()) return {};
    const std::string prefix = "immerse: " + (stage.empty() ? std::string() : stage + ": ");
    return [this, prefix](const std::string& m) { err() << prefix << m << '\n'; };
  }

  /// Runs f() and adds its wall time to `stage` (stages are listed in first-use order).
  template <class F>
  auto timed(const std::string& stage, F&& f) {
    const Clock::time_point start = Clock::now();
    struct Adder {
      Session& session;
      const std::string& stage;
      Clock::time_point start;
      ~Adder() { session.add_time(stage, seconds_since(start)); }
    } adder{*this, stage, start};
    return f();
  }
  void add_time(const std::string& stage, double seconds) {
    for (auto& [name, total] : stages_) {
      if (name == stage) {
        total += seconds;
        return;
      }
    }
    stages_.emplace_back(stage, seconds);
  }
  [[nodiscard]] Json timings_json() const {
    Json t = Json::object();
    for (const auto& [name, total] : stages_) (t[name] = total * 1e3);
    return t;
  }

  /// What the summary line says before the timings ("4 cells, 8 patches, ...").
  void set_counts(std::string text) { counts_ = std::move(text); }
  void enable_summary() { summary_ = true; }
  /// --strict: refuse exact contacts (exit 2) instead of resolving them by a perturbation.
  void set_strict(bool strict) { strict_ = strict; }
  [[nodiscard]] bool strict() const { return strict_; }
  /// --repair-folds MAX (3D): move local-fold vertices by at most MAX instead of exit 3.
  void set_repair_folds(std::optional<double> max) { repair_folds_ = max; }
  [[nodiscard]] std::optional<double> repair_folds() const { return repair_folds_; }

  /// Writes `content` to `path`'s temporary (creating parent directories) and records it for
  /// the listing; the outputs of one command land together (commit) or not at all (DESIGN §3):
  /// a failed or refused write, or a second write to the same file (by any path), makes the
  /// command keep none of them. FIFOs and devices are written through at once.
  /// @return false (after printing why) on failure.
  bool write(const std::string& path, const std::string& content, const std::string& what) {
    return timed("write", [&] {
      if (const WriteStatus dir = ensure_parent_directory(path); !dir.ok()) {
        err() << "immerse: " << dir.error << '\n';
        return fail();
      }
      // The whole command is bounded (issue 13): nothing is written after the --time-limit
      // deadline, nor beyond the output budget (--max-output).
      if (budget_.expired()) {
        err() << "immerse: the time limit was reached; '" << path << "' was not written\n";
        time_limit_reached_ = true;
        return fail();
      }
      std::string identity = output_identity(path);
      const auto clash = [&](const std::string& earlier_path, const std::string& earlier_what) {
        err() << "immerse: '" << path << "' (" << what << ") is the file '" << earlier_path << "' (" << earlier_what
              << ") already written by this command; not written\n";
        collision_ = true;
        return fail();
      };
      for (const Output& o : outputs_)
        if (o.identity == identity && !o.staged.temporary.empty()) return clash(o.staged.path, o.what);  // a stream takes both
      if (const auto it = committed_.find(identity); it != committed_.end())  // an earlier batch
        return clash(it->second.first, it->second.second);
      // The temporaries wait for the end of the command in the signal handler's table
      // (core/atomic_file.cpp, 1024 slots): a command writing more files than that (deform
      // with hundreds of frames) commits them in batches.
      if (outputs_.size() >= kMaxStaged && !commit()) return false;
      if (!budget_.charge(content.size())) {
        err() << "immerse: '" << path << "' (" << content.size() << " bytes) would pass the output budget of "
              << budget_.max_bytes() << " bytes (" << budget_.used() << " already written; --max-output); not written\n";
        return fail();
      }
      Output output{std::move(identity), what, {}};
      const WriteStatus status = stage_write(
          path,
          [&](std::ostream& out) {
            out.write(content.data(), static_cast<std::streamsize>(content.size()));
            return static_cast<bool>(out);
          },
          output.staged);
      if (!status.ok()) {
        err() << "immerse: " << status.error << '\n';
        return fail();
      }
      outputs_.push_back(std::move(output));
      written_.emplace_back(path, what);
      return true;
    });
  }
  [[nodiscard]] const std::vector<std::pair<std::string, std::string>>& written() const {
    return written_;
  }

  /// Makes every output written so far visible (renames the temporaries), unless a write of this
  /// command failed: then removes them all, says which, and forgets them. @return whether the
  /// outputs landed (false: the command must exit 1).
  bool commit() {
    if (failed_) {
      discard_all();
      return false;
    }
    for (std::size_t i = 0; i < outputs_.size(); ++i) {
      const bool regular = !outputs_[i].staged.temporary.empty();  // not a stream written through
      if (const WriteStatus status = commit_write(outputs_[i].staged); !status.ok()) {
        err() << "immerse: " << status.error << '\n';
        failed_ = true;
        outputs_.erase(outputs_.begin(), outputs_.begin() + static_cast<std::ptrdiff_t>(i) + 1);
        discard_all();
        return false;
      }
      if (regular && committed_.empty()) first_committed_ = outputs_[i].staged.path;
      if (regular)  // its identity again: the file exists now (staged, it may have had none)
        committed_.emplace(output_identity(outputs_[i].staged.path),
                           std::make_pair(outputs_[i].staged.path, outputs_[i].what));
    }
    outputs_.clear();
    return true;
  }
  /// At the end of the command: commit what is staged, or discard it after exit code 1 or a
  /// failed write. @return false when the exit code must become 1 (a rename failed, or a write
  /// failed in a command that still returned 0).
  bool finish(int exit_code) {
    if (exit_code == kExitInternalError) failed_ = true;
    if (failed_) {
      discard_all();
      return exit_code != kExitOk;
    }
    return commit();
  }
  ~Session() {
    for (Output& o : outputs_) discard_write(o.staged);
  }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  void print_summary() const {
    if (!summary_) return;
    std::ostringstream os;
    os << "immerse: " << (counts_.empty() ? std::string("done") : counts_);
    if (!stages_.empty()) {
      os << " |";
      for (std::size_t i = 0; i < stages_.size(); ++i)
        os << (i ? ", " : " ") << stages_[i].first << ' ' << format_ms(stages_[i].second);
    }
    env_.err << os.str() << '\n';
  }

  /// Bounds what the command writes: `max_bytes` in all, and nothing after `time_limit` seconds
  /// from the start of the command (0: no deadline).
  void bound_outputs(std::uint64_t max_bytes, double time_limit) {
    std::optional<Clock::time_point> deadline;
    if (time_limit > 0)
      deadline = start_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(time_limit));
    budget_ = OutputBudget(max_bytes, deadline);
  }
  /// Whether `bytes` more would fit the output budget and the deadline has not passed; says why
  /// not (naming `what`) when they would not. For outputs estimated before they are built.
  bool can_write(std::uint64_t bytes, const std::string& what) {
    if (budget_.expired()) {
      err() << "immerse: the time limit was reached; " << what << " not written\n";
      time_limit_reached_ = true;
      failed_ = true;
      return false;
    }
    if (budget_.fits(bytes)) return true;
    err() << "immerse: " << what << " would take about " << bytes << " bytes, more than the output budget of "
          << budget_.max_bytes() - budget_.used() << " bytes left (--max-output); not written\n";
    failed_ = true;
    return false;
  }
  /// Whether a write was refused because its file was already written by this command (two
  /// outputs on one path that the command line check could not see): a usage error.
  [[nodiscard]] bool output_collision() const { return collision_; }
  /// Whether a write was refused because the --time-limit deadline had passed.
  [[nodiscard]] bool time_limit_reached() const { return time_limit_reached_; }

 private:
  const CliEnvironment& env_;
  Clock::time_point start_ = Clock::now();
  OutputBudget budget_{kDefaultMaxOutput};
  bool time_limit_reached_ = false;
  std::vector<std::pair<std::string, double>> stages_;
  std::string counts_;
  bool summary_ = false;
  bool strict_ = false;
  std::optional<double> repair_folds_;
  std::vector<std::pair<std::string, std::string>> written_;

  /// One staged output.
  struct Output {
    std::string identity;  ///< output_identity of its path
    std::string what;
    StagedWrite staged;
  };
  std::vector<Output> outputs_;  ///< staged, not yet committed
  /// Outputs already renamed into place (earlier batches): identity -> (path, what).
  std::map<std::string, std::pair<std::string, std::string>> committed_;
  std::string first_committed_;
  bool failed_ = false;  ///< a write failed or was refused: nothing of this command lands
  bool collision_ = false;
  static constexpr std::size_t kMaxStaged = 960;

  bool fail() {
    failed_ = true;
    return false;
  }
  void discard_all() {
    std::string names;
    for (Output& o : outputs_) {
      if (o.staged.temporary.empty()) continue;  // written through: already delivered
      discard_write(o.staged);
      names += (names.empty() ? "'" : ", '") + o.staged.path + "'";
    }
    if (!names.empty()) {
      err() << "immerse: not written either, so that no output is left without the others: " << names << '\n';
      // Outputs renamed before the failure (an earlier batch of a long deform run, or the first
      // renames of the last batch) are in place: said, not hidden.
      if (!committed_.empty())
        err() << "immerse: " << committed_.size() << " earlier output" << (committed_.size() == 1 ? " was" : "s were")
              << " already in place and stay (the first: '" << first_committed_ << "')\n";
    }
    outputs_.clear();
    written_.clear();
  }
};

/// DESIGN §4.6 promises that the .emb reproduces every input vertex within 1e-9 of the input's
/// diagonal; the libraries measure it (MeshStats::embedding_error) and this says when it is not
/// kept (a --background far larger than the input, issue 13).
inline void warn_embedding_error(Session& s, double error) {
  if (!(error > 1e-9)) return;
  s.err() << "immerse: warning: the embedding reproduces the input vertices only within " << error
          << " of the input's diagonal (the promise is 1e-9): the background mesh is much larger than the "
             "input or far from it\n";
}

/// "wrote PATH  what" for every file written since index `from`.
void print_written(Session& s, std::size_t from = 0);

/// "P0 P3* P7" (* = the patch disagrees with the cell), cut after about 40 characters.
std::string b_patch_list(std::span<const BPatch> b_patches);

/// "immerse: invalid input 'PATH': N defects" and every defect, on stderr; sets the summary.
void print_defects(Session& s, const std::string& path, const ValidationReport& report);

// ---- search verdicts ------------------------------------------------------------------------

/// The library's search options for a request (progress forwarded when wanted).
SearchOptions search_options(const Session& s, const SearchRequest& request);

/// "2 immersions", "at least 2 immersions", "search budget exhausted" for the summary line.
std::string immersion_counts(const SearchResult& r);

/// The verdict line for a search without immersions (exit 3), on stderr, ending with `hint`.
void print_no_immersion(Session& s, const std::string& path, const SearchResult& r,
                        const std::string& hint = "");

/// "DESCRIPTION: immersible, N immersions (...)" and one line per immersion, on stdout.
/// @pre r.status == Immersible.
void print_immersion_list(Session& s, const std::string& description, const SearchResult& r,
                          const SearchRequest& request);

// ---- JSON ----------------------------------------------------------------------------------

/// Every defect: kind, stage, message, `facet_key` (segments / triangles), vertices, points.
Json defects_json(const ValidationReport& report, const std::string& facet_key);

/// Exact contacts of an input and the perturbation that resolved them (DESIGN §5), as the
/// library reports them (dim2::Contacts2, dim3::Contacts).
struct ContactsView {
  const ValidationReport* found = nullptr;
  const std::vector<std::pair<DefectKind, std::size_t>>* counts = nullptr;
  const PerturbationSummary* perturbation = nullptr;  ///< null: not resolved
};
/// Prints "note: N exact contacts (...) resolved by a perturbation of at most D ..."; with
/// `list` every listed contact too (check).
void print_contacts_note(Session& s, const std::string& path, const ContactsView& c, bool list);
/// {"resolved", "counts": {kind: n}, "max_displacement", "diagonal", "amplitude", "seed", "listed"}.
Json contacts_json(const ContactsView& c, const std::string& facet_key);
Json conflict_json(const Conflict& c);
Json immersion_json(const Immersion& im, std::size_t index);
Json stats_json(const SearchStats& s);
inline Json cell_id_json(CellId c) { return c.is_valid() ? Json(c.value()) : Json(); }

/// The report of a search: input, status, count, completeness, statistics, conflict, immersions.
Json search_json(Json input, const SearchResult& r, const Session& s);

/// "4 cells, 8 patches, 2 arcs".
template <int D>
std::string complex_counts(const CellComplex<D>& c) {
  return plural(c.cell_count(), "cell") + ", " + plural(c.patch_count(), "patch", "patches") +
         ", " + plural(c.arc_count(), "arc");
}

/// Where the dimension adds its geometry to the complex's JSON (each may be empty).
struct ComplexJsonHooks {
  std::function<void(Json&, RegionId)> region;  ///< measure (area / volume), sample, genus, ...
  std::function<void(Json&, PatchId)> patch;    ///< e.g. triangle count
  std::function<void(Json&, ArcId)> arc;        ///< e.g. the crossing point
  std::string junction_key = "junction_patches";
};

/// Adds the combinatorial cell complex (paper §4) to the object j: regions (id, winding, cell,
/// simple connectivity), cells (region, winding, B-patches with agreement, self-touching arcs),
/// patches (positive/negative region, inner/outer cell, arcs), arcs (the four junction patches in
/// cyclic order and the four wedges: wedge k between junction k and k+1).
template <int D>
void add_complex_json(Json& j, const CellComplex<D>& complex, const ComplexJsonHooks& hooks) {
  Json& regions = (j["regions"] = Json::array());
  for (RegionId r : ids<RegionId>(complex.region_count())) {
    Json& o = regions.emplace_back(Json::object());
    o["id"] = r.value();
    o["winding"] = complex.winding_number(r);
    o["cell"] = cell_id_json(complex.cell_of(r));
    o["simply_connected"] = complex.is_simply_connected(r);
    if (hooks.region) hooks.region(o, r);
  }
  Json& cells = (j["cells"] = Json::array());
  for (CellId c : ids<CellId>(complex.cell_count())) {
    Json& o = cells.emplace_back(Json::object());
    o["id"] = c.value();
    o["region"] = complex.region_of(c).value();
    o["winding"] = complex.winding_number(c);
    Json& b = (o["b_patches"] = Json::array());
    for (const BPatch& bp : complex.b_patches(c)) {
      Json& e = b.emplace_back(Json::object());
      e["patch"] = bp.patch.value();
      e["agrees"] = bp.agrees;
    }
    Json& touching = (o["self_touching_arcs"] = Json::array());
    for (ArcId a : complex.self_touching_arcs(c)) touching.emplace_back(a.value());
  }
  Json& patches = (j["patches"] = Json::array());
  for (PatchId p : ids<PatchId>(complex.patch_count())) {
    Json& o = patches.emplace_back(Json::object());
    o["id"] = p.value();
    o["positive_region"] = complex.sides(p).positive.value();
    o["negative_region"] = complex.sides(p).negative.value();
    o["inner_cell"] = cell_id_json(complex.inner_cell(p));
    o["outer_cell"] = cell_id_json(complex.outer_cell(p));
    if (hooks.patch) hooks.patch(o, p);
    Json& arcs = (o["arcs"] = Json::array());
    for (ArcId a : complex.arcs_of(p)) arcs.emplace_back(a.value());
  }
  Json& arcs = (j["arcs"] = Json::array());
  for (ArcId a : ids<ArcId>(complex.arc_count())) {
    const ArcJunctions& junctions = complex.arc(a);
    Json& o = arcs.emplace_back(Json::object());
    o["id"] = a.value();
    if (hooks.arc) hooks.arc(o, a);
    Json& order = (o[hooks.junction_key] = Json::array());
    for (PatchId p : junctions.patch) order.emplace_back(p.value());
    Json& wedges = (o["wedge_regions"] = Json::array());
    for (RegionId r : junctions.wedge) wedges.emplace_back(r.value());
  }
}

// ---- one prepared input, either dimension ----------------------------------------------------
//
// The commands of both dimensions share these templates. A prepared input P (Prepared in
// cli.cpp, PreparedSurface in cli_surface.cpp) has `path`, `report`, `inversion` (optional),
// `complex` (shared_ptr to a Complex2/Complex with a `complex` member and `reversed`), and
// `static constexpr const char* kFacetKey` ("segments" / "triangles"); the few functions that
// differ are overloads found by argument-dependent lookup on P: input_json(p), inversion_json(p),
// describe_input(p).

/// Coordinates as a JSON array.
inline Json point_json(std::span<const double> coordinates) {
  Json a = Json::array();
  for (double x : coordinates) a.emplace_back(x);
  return a;
}

/// The counts every complex has; the dimension appends its own.
template <int D>
Json complex_counts_json(const CellComplex<D>& complex) {
  Json j = Json::object();
  j["regions"] = complex.region_count();
  j["cells"] = complex.cell_count();
  j["patches"] = complex.patch_count();
  j["arcs"] = complex.arc_count();
  j["max_winding"] = complex.max_winding_number();
  return j;
}

/// JSON for an input that never reached the search (defects or an inversion).
template <class P>
Json early_json(const P& p, const Session& s) {
  Json j = Json::object();
  j["input"] = input_json(p);
  if (!p.report.ok()) {
    j["status"] = "invalid-input";
    j["defects"] = defects_json(p.report, P::kFacetKey);
  } else if (p.inversion) {
    j["status"] = "inverted";
    j["inversion"] = inversion_json(p);
  } else if (!p.folds.ok()) {
    j["status"] = "local-fold";
    j["folds"] = defects_json(p.folds, P::kFacetKey);
  }
  j["timings_ms"] = s.timings_json();
  return j;
}

template <class P>
void print_inversion(Session& s, const P& p) {
  s.err() << "immerse: " << not_immersible_message(p.path, p.inversion->message) << '\n';
}

/// For the commands that need a valid, non-inverted complex: `prepare()` reads, validates and
/// builds it (returning an exit code). On failure prints the verdict, writes the early JSON report
/// when one was asked for, and @return the exit code (2 invalid input, 3 inverted); kExitOk when
/// the complex is ready.
template <class P, class Prepare>
int prepare_complex_or_report(Session& s, P& p, const std::optional<std::string>& json_path, Prepare&& prepare) {
  int code = prepare();
  if (code == kExitOk && p.inversion) {
    print_inversion(s, p);
    code = kExitNotImmersible;
  }
  if (code != kExitOk) {
    if (json_path && !s.write(*json_path, early_json(p, s).dump(2) + "\n", "report")) return kExitInternalError;
    print_written(s);
  }
  return code;
}

/// `immerse cells --json`: the input, the complex with the dimension's geometry
/// (add_complex_report(j, p), found by argument-dependent lookup) and the timings.
template <class P>
Json cells_report_json(const P& p, const Session& s) {
  Json j = Json::object();
  j["input"] = input_json(p);
  j["status"] = "ok";
  add_complex_report(j, p);
  j["timings_ms"] = s.timings_json();
  return j;
}

/// "'PATH': 3D input, 12 triangles, 8 vertices" (`counts` after the dimension).
inline std::string describe_input(const std::string& path, int dimension, const std::string& counts) {
  return "'" + path + "': " + std::to_string(dimension) + "D input, " + counts;
}

/// An extra column of the cell table (3D: the genus of the cell's region).
struct CellTableColumn {
  std::string header;
  std::function<std::string(RegionId)> value;
};

/// The counts line and the table of cells (at most kMaxTableRows rows): id, region, winding,
/// simple connectivity, measure (`measure` names it: "area", "volume"), B-patches; `arc_kind`
/// names the arcs ("crossings", "intersection curves"), `detail` is printed after the counts line.
template <int D>
void print_cell_table(Session& s, const CellComplex<D>& c, const std::string& arc_kind, const std::string& detail,
                      const std::string& measure, const std::optional<CellTableColumn>& extra = std::nullopt) {
  s.out() << plural(c.region_count(), "region") << ", " << plural(c.cell_count(), "cell") << ", "
          << plural(c.patch_count(), "patch", "patches") << ", " << plural(c.arc_count(), "arc") << " ("
          << arc_kind << "), max winding number " << c.max_winding_number() << '\n'
          << detail;
  char head[160];
  std::snprintf(head, sizeof head, " cell  region  winding  %s%16s  %12s  B-patches (* = disagrees)\n",
                extra ? (extra->header + "  ").c_str() : "", "simply-connected", measure.c_str());
  s.out() << head;
  std::size_t rows = 0;
  for (CellId cell : ids<CellId>(c.cell_count())) {
    if (++rows > kMaxTableRows) {
      s.out() << " ... and " << (c.cell_count() - kMaxTableRows) << " more cells (see --json)\n";
      break;
    }
    const RegionId r = c.region_of(cell);
    std::string extra_value;
    if (extra) {
      extra_value = extra->value(r);
      extra_value = std::string(extra->header.size() > extra_value.size() ? extra->header.size() - extra_value.size() : 0, ' ') +
                    extra_value + "  ";
    }
    char line[192];
    std::snprintf(line, sizeof line, "%5d  %6d  %7d  %s%16s  %12.6g  ", cell.value(), r.value(), c.winding_number(cell),
                  extra_value.c_str(), c.is_simply_connected(r) ? "yes" : "no", to_double(c.measure(r)));
    s.out() << line << b_patch_list(c.b_patches(cell)) << '\n';
  }
}

// ---- 3D commands (app/cli_surface.cpp) -------------------------------------------------------

/// How many 'f' and 'l' elements an OBJ file has (read in bounded chunks, stopping at a NUL byte;
/// zero for a file that cannot be opened or is a device).
struct ObjElements {
  std::size_t faces = 0;
  std::size_t lines = 0;
};
ObjElements scan_obj_elements(const std::string& path);

/// True when the file is a 3D surface: .off/.ply/.stl, or an OBJ with faces ('l' lines beside
/// them are loose edges, ignored with a note).
bool is_surface_file(const std::string& path);

/// Immersion k's file for `mesh --all`: `path` with `_K` before its extension; a FIFO or device
/// (is_stream_output) is not numbered: it takes every immersion's output.
std::string numbered_output(const std::string& path, std::size_t k);

/// `immerse check IN` on a surface. @return the exit code.
int check_surface(Session& s, const std::string& path);
/// `immerse cells IN [--json OUT] [--cut-mesh OUT.obj]` on a surface.
int cells_surface(Session& s, const CommandLine& cl);
/// `immerse immersions IN [...]` on a surface (helper boxes for self-connecting cells).
int immersions_surface(Session& s, const CommandLine& cl, const SearchRequest& request);
/// `immerse mesh IN [...]` on a surface: immersion k (or every one when `all`), written as
/// .mesh/.vtu/.veg, .emb and JSON. With `conforming` set (`--conforming`), the conforming
/// mesher (dim3/conforming_mesh3.h) instead of the background mesher.
int mesh_surface(Session& s, const CommandLine& cl, const SearchRequest& request, const dim3::MeshOptions& options,
                 std::size_t k, bool all, const dim3::ConformingOptions* conforming = nullptr);

/// One line of `immerse generate --list`.
struct GeneratorEntry {
  std::string name;
  std::string params;  ///< "N SEED", "[N]"
  std::string description;
};
/// The 3D generators (surfaces), for `generate --list`.
std::vector<GeneratorEntry> surface_generator_list();
/// True when `name` is a 3D generator.
bool is_surface_generator(const std::string& name);
/// `immerse generate NAME [PARAMS] [-o OUT]` for a 3D generator. @return the exit code.
int command_generate_surface(Session& s, const std::string& name,
                             const std::vector<std::string>& params,
                             const std::optional<std::string>& out);

}  // namespace imm::cli
