// Messages are printable text (issue 13): a reader may quote bytes of a broken or binary file in a
// defect message; they must reach neither a terminal nor a JSON report raw.
#pragma once

#include <string>

namespace imm {

/// Replaces, in place, every byte of `message` that is not printable text by '?': control
/// characters other than newline and tab, and bytes that are not part of a valid UTF-8 sequence
/// (valid UTF-8, such as a file name with accents, is kept). ValidationReport::summary applies
/// it to every message; writers of defect messages elsewhere (JSON reports) call it too.
void sanitize_message(std::string& message);

/// The same, on a copy.
inline std::string printable(std::string message) {
  sanitize_message(message);
  return message;
}

}  // namespace imm
