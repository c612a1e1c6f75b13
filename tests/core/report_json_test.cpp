// The JSON writer of the reports (core/report_json.h) and atomic output files
// (core/atomic_file.h, DESIGN §3: never a half-written output).
#include "core/report_json.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/diagnostics.h"

namespace imm {
namespace {

namespace fs = std::filesystem;

TEST(Json, EscapesStrings) {
  EXPECT_EQ(json_escape("plain"), "plain");
  EXPECT_EQ(json_escape("a\"b\\c"), "a\\\"b\\\\c");
  EXPECT_EQ(json_escape("line\nnext\ttab\r"), "line\\nnext\\ttab\\r");
  EXPECT_EQ(json_escape(std::string("\x01\x1f", 2)), "\\u0001\\u001f");
  EXPECT_EQ(json_escape("caf\xc3\xa9"), "caf\xc3\xa9");  // UTF-8 passes through
}

TEST(Json, NumbersRoundTripAndNonFiniteIsNull) {
  EXPECT_EQ(json_number(0.0), "0");
  EXPECT_EQ(json_number(-0.0), "0");
  EXPECT_EQ(json_number(1.5), "1.5");
  EXPECT_EQ(json_number(0.1), "0.1");
  const double third = 1.0 / 3.0;
  EXPECT_EQ(std::stod(json_number(third)), third);
  EXPECT_EQ(json_number(std::nan("")), "null");
  EXPECT_EQ(json_number(std::numeric_limits<double>::infinity()), "null");
  EXPECT_EQ(Json(std::nan("")).type(), Json::Type::Null);
}

TEST(Json, PrettyPrintsInInsertionOrder) {
  Json doc = Json::object();
  doc.set("name", "fig \"6\"");
  doc.set("count", 2);
  doc.set("complete", true);
  doc.set("ratio", 0.25);
  doc.set("missing", nullptr);
  Json& list = doc.set("windings", Json::array());
  for (int w : {1, 2, 3}) list.push(w);
  Json& nodes = doc.set("nodes", Json::array());
  Json& node = nodes.push(Json::object());
  node.set("cell", 0u);
  node.set("copy", 1L);
  doc.set("empty_list", Json::array());
  doc.set("empty_object", Json::object());
  doc.set("count", 3);  // replaces, keeps its place
  EXPECT_EQ(doc.dump(),
            "{\n"
            "  \"name\": \"fig \\\"6\\\"\",\n"
            "  \"count\": 3,\n"
            "  \"complete\": true,\n"
            "  \"ratio\": 0.25,\n"
            "  \"missing\": null,\n"
            "  \"windings\": [1, 2, 3],\n"
            "  \"nodes\": [\n"
            "    {\n"
            "      \"cell\": 0,\n"
            "      \"copy\": 1\n"
            "    }\n"
            "  ],\n"
            "  \"empty_list\": [],\n"
            "  \"empty_object\": {}\n"
            "}\n");
}

TEST(Json, LongScalarArraysWrap) {
  Json list = Json::array();
  for (int i = 0; i < 100; ++i) list.push(1000 + i);
  const std::string text = list.dump();
  std::istringstream lines(text);
  std::string line;
  int count = 0;
  while (std::getline(lines, line)) {
    ++count;
    EXPECT_LE(line.size(), 110u) << line;
  }
  EXPECT_GT(count, 1);
  // Every number appears once, in order.
  std::size_t at = 0;
  for (int i = 0; i < 100; ++i) {
    at = text.find(std::to_string(1000 + i), at);
    ASSERT_NE(at, std::string::npos) << i;
  }
}

TEST(Json, MisuseIsABug) {
  Json scalar = 3;
  EXPECT_THROW(scalar.push(1), InvariantError);
  EXPECT_THROW(scalar.set("a", 1), InvariantError);
}

class AtomicFile : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("imm_atomic_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  [[nodiscard]] std::size_t temporaries() const {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir_))
      n += e.path().filename().string().find(".tmp.") != std::string::npos;
    return n;
  }
  static std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  fs::path dir_;
};

TEST_F(AtomicFile, WritesAndReplaces) {
  const std::string path = (dir_ / "out.txt").string();
  EXPECT_TRUE(write_file_atomic(path, "first\n").ok());
  EXPECT_EQ(read(path), "first\n");
  EXPECT_TRUE(write_file_atomic(path, std::string("second\0x", 8)).ok());
  EXPECT_EQ(read(path), std::string("second\0x", 8));
  EXPECT_EQ(temporaries(), 0u);
  EXPECT_EQ(temporary_path(path), path + ".tmp." + std::to_string(::getpid()));
}

TEST_F(AtomicFile, FailureLeavesTheOldFileAndNoTemporary) {
  const std::string path = (dir_ / "keep.txt").string();
  ASSERT_TRUE(write_file_atomic(path, "old\n").ok());
  // Abandoned by the writer.
  const WriteStatus abandoned = write_file_atomic(path, [](std::ostream& out) {
    out << "half";
    return false;
  });
  EXPECT_FALSE(abandoned.ok());
  EXPECT_EQ(read(path), "old\n");
  // An exception while writing: cleaned up, then rethrown.
  EXPECT_THROW(write_file_atomic(path,
                                 [](std::ostream& out) -> bool {
                                   out << "half";
                                   throw std::runtime_error("disk on fire");
                                 }),
               std::runtime_error);
  EXPECT_EQ(read(path), "old\n");
  // A directory in the way: rename fails, nothing is left behind.
  fs::create_directories(dir_ / "a_directory" / "inside");
  const WriteStatus onto_directory = write_file_atomic((dir_ / "a_directory").string(), "x");
  EXPECT_FALSE(onto_directory.ok());
  EXPECT_TRUE(fs::is_directory(dir_ / "a_directory"));
  // A missing parent directory: the temporary cannot even be created.
  const WriteStatus no_parent = write_file_atomic((dir_ / "no" / "such" / "f.txt").string(), "x");
  EXPECT_FALSE(no_parent.ok());
  EXPECT_NE(no_parent.error.find("cannot create"), std::string::npos) << no_parent.error;
  EXPECT_EQ(temporaries(), 0u);
}

TEST_F(AtomicFile, EnsureDirectory) {
  EXPECT_TRUE(ensure_directory((dir_ / "a" / "b").string()).ok());
  EXPECT_TRUE(fs::is_directory(dir_ / "a" / "b"));
  EXPECT_TRUE(ensure_directory((dir_ / "a").string()).ok());
  ASSERT_TRUE(write_file_atomic((dir_ / "file").string(), "x").ok());
  EXPECT_FALSE(ensure_directory((dir_ / "file").string()).ok());
}

}  // namespace
}  // namespace imm
