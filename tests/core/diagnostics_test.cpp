// Defect messages are printable text (issue 13: bytes quoted from a binary file reached the
// terminal raw, and a JSON report of them could not be written).
#include "core/diagnostics.h"
#include "core/printable.h"

#include <gtest/gtest.h>

#include <string>

namespace imm {
namespace {

TEST(Diagnostics, MessagesAreMadePrintable) {
  std::string text = std::string("ok \x01\x7f tab\there\nline ") + "\xff\xfe" + " v\xe9rtex";
  sanitize_message(text);
  EXPECT_EQ(text, "ok ?? tab\there\nline ?? v?rtex");
  // Valid UTF-8 (a file name with accents, a CJK name, an emoji) is kept.
  std::string utf8 = "caf\xc3\xa9.obj \xe6\x97\xa5 \xf0\x9f\x99\x82";
  const std::string before = utf8;
  sanitize_message(utf8);
  EXPECT_EQ(utf8, before);
  // Overlong forms, surrogates, truncated sequences and code points beyond U+10FFFF are not.
  for (std::string bad : {std::string("\xc0\xaf"), std::string("\xed\xa0\x80"), std::string("\xe6\x97"),
                          std::string("\xf4\x90\x80\x80"), std::string("\xf8\x88\x80\x80\x80")}) {
    sanitize_message(bad);
    EXPECT_EQ(bad.find_first_not_of('?'), std::string::npos) << bad;
  }
}

TEST(Diagnostics, SummaryPrintsPrintableMessages) {
  ValidationReport report;
  report.add({DefectKind::Unreadable, "read", std::string("element 'v\xe9rtex'"), {}, {}, {}});
  EXPECT_EQ(report.summary(), "unreadable (read): element 'v?rtex'\n");
  EXPECT_EQ(printable("a\x01" "b"), "a?b");
}

}  // namespace
}  // namespace imm
