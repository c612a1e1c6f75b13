#include "core/diagnostics.h"

#include <sstream>

namespace imm {

const char* to_string(DefectKind kind) {
  switch (kind) {
    case DefectKind::Unreadable: return "unreadable";
    case DefectKind::Empty: return "empty";
    case DefectKind::NonFinite: return "non-finite";
    case DefectKind::TooShort: return "too-short";
    case DefectKind::NotClosed: return "not-closed";
    case DefectKind::NonManifoldEdge: return "non-manifold-edge";
    case DefectKind::NonManifoldVertex: return "non-manifold-vertex";
    case DefectKind::InconsistentOrientation: return "inconsistent-orientation";
    case DefectKind::DegenerateFacet: return "degenerate-facet";
    case DefectKind::DuplicateVertex: return "duplicate-vertex";
    case DefectKind::DuplicateFacet: return "duplicate-facet";
    case DefectKind::CollinearOverlap: return "collinear-overlap";
    case DefectKind::CoplanarOverlap: return "coplanar-overlap";
    case DefectKind::Touching: return "touching";
    case DefectKind::TriplePoint: return "triple-point";
    case DefectKind::NotCovered: return "not-covered";
    case DefectKind::OutOfRange: return "out-of-range";
    case DefectKind::LocalFold: return "local-fold";
  }
  return "unknown";
}

std::string ValidationReport::summary(std::size_t max_lines) const {
  std::ostringstream os;
  std::size_t shown = 0;
  for (const Defect& d : defects) {
    if (shown == max_lines) {
      os << "... and " << (total() - shown) << " more\n";
      return os.str();
    }
    os << to_string(d.kind) << " (" << d.stage << "): " << d.message << '\n';
    ++shown;
  }
  if (unlisted > 0) os << "... and " << unlisted << " more (not listed)\n";
  return os.str();
}

void fail_invariant(const char* cond, const std::string& msg, const char* file, int line) {
  std::ostringstream os;
  os << file << ':' << line << ": invariant violated: " << cond;
  if (!msg.empty()) os << " -- " << msg;
  throw InvariantError(os.str());
}

}  // namespace imm
