// Three channels of failure (CONVENTIONS "Errors and diagnostics"):
//  1. input defects   -> ValidationReport, exit code 2;
//  2. verdicts        -> ImmersionStatus (graph_search.h), exit code 0 or 3;
//  3. internal bugs   -> IMM_ASSERT throws InvariantError, exit code 1.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace imm {

/// What is wrong with an input. Kinds found by the validator and kinds found while building the
/// cell complex share one type; `stage` says which step found it.
enum class DefectKind {
  Unreadable,             ///< the file could not be opened or parsed
  Empty,                  ///< no curve / no triangle
  NonFinite,              ///< NaN or infinite coordinate
  TooShort,               ///< a curve with fewer than 3 distinct vertices
  NotClosed,              ///< open boundary
  NonManifoldEdge,        ///< an edge used by more than two facets
  NonManifoldVertex,      ///< facets around a vertex do not form one fan
  InconsistentOrientation,///< neighbouring facets disagree on orientation
  DegenerateFacet,        ///< zero-length segment / zero-area triangle (exact predicate)
  DuplicateVertex,        ///< repeated consecutive vertex
  DuplicateFacet,         ///< the same facet twice
  CollinearOverlap,       ///< two segments (2D) overlap along a positive length
  CoplanarOverlap,        ///< two triangles (3D) are coplanar and overlap or touch
  Touching,               ///< the input touches itself without crossing (vertex on a facet, ...)
  TriplePoint,            ///< three or more sheets through one point (2D) / non-generic (3D)
  NotCovered,             ///< a background mesh that does not cover the input (meshing)
  OutOfRange,             ///< coordinates a double-precision step (mesh generation) cannot take
  /// Two facets of one vertex star cross beyond the vertex (3D): the surface is not locally
  /// embedded there and no perturbation removes it; a verdict (exit 3), not a file defect.
  LocalFold,
};

/// A short, stable name for a kind ("collinear-overlap", ...), used in messages and JSON.
const char* to_string(DefectKind kind);

/// One defect with everything a user needs to find it.
struct Defect {
  DefectKind kind;
  std::string stage;                ///< "read", "validate", "arrangement", ...
  std::string message;              ///< human-readable, names curve/facet/vertex ids and coordinates
  std::vector<long> facets;         ///< facet (segment / triangle) indices, 0-based in input order
  std::vector<long> vertices;       ///< vertex indices, 0-based in input order
  std::vector<std::vector<double>> points;  ///< coordinates involved (rounded, for display)
};

/// Every defect found in one input. `ok()` when there are none.
struct ValidationReport {
  std::vector<Defect> defects;
  /// Defects found but not listed (a cap keeps a broken 1M-triangle file from printing 1M lines).
  std::size_t unlisted = 0;
  [[nodiscard]] bool ok() const { return defects.empty() && unlisted == 0; }
  void add(Defect d) { defects.push_back(std::move(d)); }
  /// Every defect found, listed or not.
  [[nodiscard]] std::size_t total() const { return defects.size() + unlisted; }
  /// All messages, one per line, at most `max_lines` (then "... and N more").
  [[nodiscard]] std::string summary(std::size_t max_lines = 20) const;
};

/// Thrown by IMM_ASSERT: a bug, never bad input. The CLI maps it to exit code 1.
class InvariantError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

[[noreturn]] void fail_invariant(const char* cond, const std::string& msg, const char* file, int line);

/// Progress / log callback used by long-running library calls (never std::cout in libraries).
using LogCallback = std::function<void(const std::string&)>;

}  // namespace imm

#define IMM_ASSERT(cond, msg)                                         \
  do {                                                                \
    if (!(cond)) ::imm::fail_invariant(#cond, (msg), __FILE__, __LINE__); \
  } while (false)

