#include "core/verdicts.h"

#include <limits>

namespace imm {

std::string plural(std::size_t n, const std::string& word, const std::string& words) {
  return std::to_string(n) + " " + (n == 1 ? word : (words.empty() ? word + "s" : words));
}

namespace {

/// A report's lines without the last line break.
std::string lines_of(const ValidationReport& report, std::size_t max_lines) {
  std::string text = report.summary(max_lines);
  if (!text.empty() && text.back() == '\n') text.pop_back();
  return text;
}

std::string with_defects(const std::string& head, const ValidationReport& report, std::size_t max_lines) {
  const std::string lines = lines_of(report, max_lines);
  return head + plural(report.total(), "defect") + (lines.empty() ? "" : "\n" + lines);
}

}  // namespace

std::string invalid_input_message(const std::string& name, const ValidationReport& report, std::size_t max_lines) {
  return with_defects("invalid input '" + name + "': ", report, max_lines);
}

std::string cannot_mesh_message(const std::string& name, const ValidationReport& report, std::size_t max_lines,
                                const std::string& how) {
  return with_defects("cannot mesh '" + name + "'" + (how.empty() ? "" : " " + how) + ": ", report, max_lines);
}

std::string not_immersible_message(const std::string& name, const std::string& reason) {
  return "'" + name + "' is not immersible: " + reason;
}

std::string local_folds_message(const std::string& name, const ValidationReport& folds) {
  const std::string lines = lines_of(folds, std::numeric_limits<std::size_t>::max());
  return "'" + name + "' is not immersible: " + plural(folds.total(), "local fold") +
         " (no perturbation removes a fold, and no immersed solid has a folded boundary)" +
         (lines.empty() ? "" : "\n" + lines);
}

std::string no_immersion_message(const std::string& name, const SearchResult& r, const OptionNames& names) {
  std::string text = "'" + name + "' ";
  switch (r.status) {
    case ImmersionStatus::NotImmersible:
      text += "is not immersible";
      if (r.conflict.rule > 0 && r.conflict.message.find("Rule " + std::to_string(r.conflict.rule)) == std::string::npos)
        text += " (Rule " + std::to_string(r.conflict.rule) + " cannot be satisfied)";
      return text + ": " + r.conflict.message;
    case ImmersionStatus::SelfConnectingCell:
      // The search's message already says "no simple immersion exists" and names the cell.
      return text + "is not simply immersible: " + r.conflict.message;
    case ImmersionStatus::SearchBudgetExhausted:
      return text + "could not be decided: " + r.conflict.message + " (raise " + names.max_states + " / " +
             names.time_limit + ")";
    case ImmersionStatus::Immersible:
      break;
  }
  return text + "is immersible";
}

std::string immersion_index_message(std::size_t k, const std::string& name, std::size_t found, bool complete,
                                    const OptionNames& names) {
  return std::string(names.immersion) + " " + std::to_string(k) + ": '" + name + "' has only " +
         plural(found, "immersion") + " (numbered from 0)" +
         (complete ? "" : std::string("; the search stopped early, raise ") + names.max_states);
}

}  // namespace imm
