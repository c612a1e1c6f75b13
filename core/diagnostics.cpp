#include "core/diagnostics.h"

#include "core/printable.h"

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

void sanitize_message(std::string& message) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(message[i]); };
  for (std::size_t i = 0; i < message.size();) {
    const unsigned char c = byte(i);
    if (c < 0x80) {
      if ((c < 0x20 && c != '\n' && c != '\t') || c == 0x7f) message[i] = '?';
      ++i;
      continue;
    }
    // The length of a UTF-8 sequence from its lead byte, and the smallest second byte allowed
    // (no overlong forms, no surrogates, nothing beyond U+10FFFF).
    std::size_t length = 0;
    unsigned char low = 0x80, high = 0xbf;
    if (c >= 0xc2 && c <= 0xdf) {
      length = 2;
    } else if (c >= 0xe0 && c <= 0xef) {
      length = 3;
      if (c == 0xe0) low = 0xa0;
      if (c == 0xed) high = 0x9f;
    } else if (c >= 0xf0 && c <= 0xf4) {
      length = 4;
      if (c == 0xf0) low = 0x90;
      if (c == 0xf4) high = 0x8f;
    }
    bool valid = length > 0 && i + length <= message.size() && byte(i + 1) >= low && byte(i + 1) <= high;
    for (std::size_t k = 2; valid && k < length; ++k) valid = byte(i + k) >= 0x80 && byte(i + k) <= 0xbf;
    if (!valid) {
      message[i] = '?';
      ++i;
    } else {
      i += length;
    }
  }
}

std::string ValidationReport::summary(std::size_t max_lines) const {
  std::ostringstream os;
  std::size_t shown = 0;
  for (const Defect& d : defects) {
    if (shown == max_lines) {
      os << "... and " << (total() - shown) << " more\n";
      return os.str();
    }
    os << to_string(d.kind) << " (" << d.stage << "): " << printable(d.message) << '\n';
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
