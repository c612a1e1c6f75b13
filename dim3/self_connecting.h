// Self-connecting cells (paper §5.1, Fig. 12-13) cut automatically with helper boxes (§6.2).
//
// A cell of winding number >= 2 whose boundary has genus > 0 may be wrapped onto itself by a
// non-simple immersion; the search then reports SelfConnectingCell. The paper cuts such a cell
// by hand with a box, one of whose faces crosses the cell, added to the input as a separate
// closed component (no CSG). Here it is automatic: the box's face is a plane through the cell's
// bounding box that contains the box's longest axis and is orthogonal to its middle axis (so a
// ring-shaped cell is cut across), offset slightly off-centre; boxes are added until no cell is
// self-connecting or `max_boxes` is reached. A box that makes the input non-generic (a contact
// that is not a crossing) is moved and tried again. The helper triangles come after the user's
// triangles, so later steps can drop them (their tets form separate components).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/graph_search.h"
#include "dim3/complex3.h"

namespace imm::dim3 {

struct ImmerseOptions {
  BuildOptions build;
  SearchOptions search;
  int max_boxes = 8;  ///< 0 disables helper boxes (the SelfConnectingCell verdict is returned)
};

struct Immersed {
  Surface surface;                    ///< the final input: the user's surface, then 12 triangles per box
  BuildResult build;                 ///< of `surface`
  SearchResult search;                ///< on build.complex (empty when the build failed)
  std::vector<Box3> helper_boxes;     ///< in the order they were added
  std::size_t input_triangles = 0;    ///< triangles [0, input_triangles) are the user's
  std::size_t input_vertices = 0;     ///< vertices [0, input_vertices) are the user's
  std::vector<std::string> notes;     ///< what was done about self-connecting cells
  /// The user's exact contacts and their resolution (first build); `surface` then starts from
  /// the perturbed input.
  std::optional<Contacts> contacts;
  /// The user's local folds and their repair (--repair-folds), from the first build; when ok,
  /// `surface` starts from the repaired input.
  std::optional<FoldRepair> repair;
  double build_seconds = 0.0;         ///< total over all rebuilds
  double search_seconds = 0.0;        ///< total over all searches
};

/// Builds the complex, searches, and cuts self-connecting cells with helper boxes until the
/// search gives a verdict other than SelfConnectingCell (or the box budget is spent).
Immersed immerse_surface(const Surface& surface, const ImmerseOptions& options = {});

/// What a verdict should add when helper boxes were involved: "" or, e.g., " (still
/// self-connecting after 2 helper boxes) [cell, patch and arc ids refer to the input with 2 helper
/// boxes added; see the notes above]". `boxes_allowed`: false when max_boxes was 0.
std::string helper_box_hint(const Immersed& im, bool boxes_allowed);

/// "" or the note that defects name helper-box triangles ("triangles from id N on belong to the
/// helper boxes ..."), for a failed build.
std::string helper_box_defect_note(const Immersed& im);

/// The closed, outward-oriented 12-triangle surface of a box.
Surface box_surface(const Box3& box);

}  // namespace imm::dim3
