// Outputs respect what their path names (issue 13, defect 4), temporaries do not outlive a
// SIGTERM (defect 10), and the output budget stops a write (defect 7).
#include "core/atomic_file.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "core/output_budget.h"
#include "support/run_immerse.h"

namespace imm {
namespace {

namespace fs = std::filesystem;

class AtomicTarget : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("imm_atomic_target_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  /// Files in the directory whose name holds ".tmp." (left-over temporaries).
  [[nodiscard]] int temporaries() const {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir_))
      n += e.path().filename().string().find(".tmp.") != std::string::npos ? 1 : 0;
    return n;
  }
  fs::path dir_;
};

TEST_F(AtomicTarget, WritesAndReplaces) {
  const std::string path = (dir_ / "out.txt").string();
  EXPECT_TRUE(write_file_atomic(path, "first\n").ok());
  EXPECT_EQ(read(path), "first\n");
  EXPECT_TRUE(write_file_atomic(path, std::string("second\0x", 8)).ok());
  EXPECT_EQ(read(path), std::string("second\0x", 8));
  EXPECT_EQ(temporaries(), 0);
  EXPECT_EQ(temporary_path(path), path + ".tmp." + std::to_string(::getpid()));
}

TEST_F(AtomicTarget, FailureLeavesTheOldFileAndNoTemporary) {
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
  // A missing parent directory: the temporary cannot even be created.
  const WriteStatus no_parent = write_file_atomic((dir_ / "no" / "such" / "f.txt").string(), "x");
  EXPECT_FALSE(no_parent.ok());
  EXPECT_NE(no_parent.error.find("cannot create"), std::string::npos) << no_parent.error;
  EXPECT_EQ(temporaries(), 0);
}

TEST_F(AtomicTarget, EnsureDirectory) {
  EXPECT_TRUE(ensure_directory((dir_ / "a" / "b").string()).ok());
  EXPECT_TRUE(fs::is_directory(dir_ / "a" / "b"));
  EXPECT_TRUE(ensure_directory((dir_ / "a").string()).ok());
  ASSERT_TRUE(write_file_atomic((dir_ / "file").string(), "x").ok());
  EXPECT_FALSE(ensure_directory((dir_ / "file").string()).ok());
}

TEST_F(AtomicTarget, SymlinkIsFollowedNotReplaced) {
  const fs::path target = dir_ / "target.mesh", link = dir_ / "link.mesh";
  ASSERT_TRUE(write_file_atomic(target.string(), "old\n").ok());
  fs::create_symlink("target.mesh", link);  // relative, as `ln -s` makes them
  ASSERT_TRUE(write_file_atomic(link.string(), "new\n").ok());
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(read(target), "new\n");
  // A chain of links, and a dangling link: the file it names is created.
  fs::create_symlink(link, dir_ / "link2.mesh");
  ASSERT_TRUE(write_file_atomic((dir_ / "link2.mesh").string(), "third\n").ok());
  EXPECT_TRUE(fs::is_symlink(dir_ / "link2.mesh"));
  EXPECT_EQ(read(target), "third\n");
  fs::create_symlink(dir_ / "later.mesh", dir_ / "dangling.mesh");
  ASSERT_TRUE(write_file_atomic((dir_ / "dangling.mesh").string(), "made\n").ok());
  EXPECT_TRUE(fs::is_symlink(dir_ / "dangling.mesh"));
  EXPECT_EQ(read(dir_ / "later.mesh"), "made\n");
  // A loop is an error, not a hang.
  fs::create_symlink("loop_b", dir_ / "loop_a");
  fs::create_symlink("loop_a", dir_ / "loop_b");
  EXPECT_FALSE(write_file_atomic((dir_ / "loop_a").string(), "x").ok());
  EXPECT_EQ(temporaries(), 0);
}

TEST_F(AtomicTarget, FifoIsWrittenThrough) {
  const fs::path fifo = dir_ / "out.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  imm::test::FifoReader reader(fifo);
  const WriteStatus status = write_file_atomic(fifo.string(), "through the pipe\n");
  const std::string received = reader.finish();
  EXPECT_TRUE(status.ok()) << status.error;
  EXPECT_EQ(received, "through the pipe\n");
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(temporaries(), 0);
}

TEST_F(AtomicTarget, DevicesAreWrittenThroughAndKept) {
  ASSERT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_TRUE(write_file_atomic("/dev/null", "discarded\n").ok());
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  if (fs::is_character_file("/dev/full")) {
    // The device refuses the data (ENOSPC); the error says so, and the device is still a device.
    const WriteStatus full = write_file_atomic("/dev/full", std::string(1 << 16, 'x'));
    EXPECT_FALSE(full.ok());
    EXPECT_NE(full.error.find("/dev/full"), std::string::npos) << full.error;
    // The OS error, not only "was abandoned" (the tester's `--embedding /dev/full`).
    EXPECT_NE(full.error.find(std::strerror(ENOSPC)), std::string::npos) << full.error;
    EXPECT_TRUE(fs::is_character_file("/dev/full"));
  }
  // A symlink to a device writes the device.
  fs::create_symlink("/dev/null", dir_ / "null.mesh");
  EXPECT_TRUE(write_file_atomic((dir_ / "null.mesh").string(), "x").ok());
  EXPECT_TRUE(fs::is_symlink(dir_ / "null.mesh"));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

TEST_F(AtomicTarget, DirectoryIsRefused) {
  fs::create_directories(dir_ / "d");
  const WriteStatus status = write_file_atomic((dir_ / "d").string(), "x");
  EXPECT_FALSE(status.ok());
  EXPECT_NE(status.error.find("directory"), std::string::npos) << status.error;
  EXPECT_TRUE(fs::is_directory(dir_ / "d"));
  EXPECT_EQ(temporaries(), 0);
}

// Every fatal signal a command can meet while its outputs are staged: a reader closing the pipe
// (SIGPIPE: `immerse deform ... | head` left hundreds of temporaries), limits, alarms.
TEST_F(AtomicTarget, TemporaryIsRemovedOnFatalSignals) {
  for (const int signal_number : {SIGTERM, SIGINT, SIGPIPE, SIGXFSZ, SIGXCPU, SIGALRM, SIGUSR1}) {
    SCOPED_TRACE(signal_number);
    // A child process starts a write, reports that its temporary exists, and waits to be killed.
    const fs::path out = dir_ / "big.json";
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      ::close(ready[0]);
      remove_temporaries_on_signals();
      write_file_atomic(out.string(), [&](std::ostream& o) {
        o << std::string(1 << 20, 'x');
        o.flush();
        const char byte = 1;
        if (::write(ready[1], &byte, 1) != 1) ::_exit(10);
        for (;;) ::pause();
        return true;
      });
      ::_exit(11);  // never reached: the signal ends the process
    }
    ::close(ready[1]);
    char byte = 0;
    ASSERT_EQ(::read(ready[0], &byte, 1), 1);
    ::close(ready[0]);
    EXPECT_EQ(temporaries(), 1);  // the write is in progress
    ASSERT_EQ(::kill(child, signal_number), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status)) << "status " << status;
    if (WIFSIGNALED(status)) EXPECT_EQ(WTERMSIG(status), signal_number);
    EXPECT_EQ(temporaries(), 0);
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST_F(AtomicTarget, RegistryIsEmptyAfterWrites) {
  const std::string path = (dir_ / "a.txt").string();
  EXPECT_TRUE(write_file_atomic(path, "x").ok());
  EXPECT_FALSE(write_file_atomic(path, [](std::ostream&) { return false; }).ok());
  EXPECT_EQ(temporaries_in_progress(), 0);
  write_file_atomic(path, [](std::ostream&) {
    EXPECT_EQ(temporaries_in_progress(), 1);
    return true;
  });
  EXPECT_EQ(temporaries_in_progress(), 0);
}

TEST_F(AtomicTarget, BudgetStopsTheWriteAndRemovesTheTemporary) {
  OutputBudget budget(1000);
  const std::string small = (dir_ / "small.txt").string(), large = (dir_ / "large.txt").string();
  std::string why;
  auto fill = [&](std::size_t bytes) {
    return [&, bytes](std::ostream& out) {
      BudgetedStream limited(out, budget);
      for (std::size_t i = 0; i < bytes; i += 100) limited << std::string(100, 'y');
      why = limited.stopped();
      return static_cast<bool>(limited);
    };
  };
  EXPECT_TRUE(write_file_atomic(small, fill(600)).ok());
  EXPECT_EQ(budget.used(), 600u);
  EXPECT_FALSE(write_file_atomic(large, fill(600)).ok());  // 1,200 > 1,000 in all
  EXPECT_NE(why.find("1000 bytes"), std::string::npos) << why;
  EXPECT_TRUE(budget.exceeded());
  EXPECT_FALSE(fs::exists(large));
  EXPECT_EQ(read(small).size(), 600u);
  EXPECT_EQ(temporaries(), 0);
  // What the refused write had already written counts (it reached the disk before its removal):
  // 600 + 400, then nothing more fits.
  EXPECT_EQ(budget.used(), 1000u);
  EXPECT_TRUE(budget.fits(0));
  EXPECT_FALSE(budget.fits(1));
  OutputBudget fresh(1000);
  EXPECT_TRUE(fresh.fits(1000));
  EXPECT_FALSE(fresh.fits(1001));
}

TEST_F(AtomicTarget, DeadlineStopsTheWrite) {
  OutputBudget expired(OutputBudget::kUnlimited, OutputBudget::Clock::now() - std::chrono::seconds(1));
  EXPECT_TRUE(expired.expired());
  std::string why;
  const WriteStatus status = write_file_atomic((dir_ / "late.txt").string(), [&](std::ostream& out) {
    BudgetedStream limited(out, expired);
    limited << "anything";
    why = limited.stopped();
    return static_cast<bool>(limited);
  });
  EXPECT_FALSE(status.ok());
  EXPECT_NE(why.find("time limit"), std::string::npos) << why;
  EXPECT_FALSE(fs::exists(dir_ / "late.txt"));
  OutputBudget open;  // no bound at all
  EXPECT_FALSE(open.expired());
  EXPECT_TRUE(open.charge(std::uint64_t{1} << 60));
}

// A set of outputs lands together (the CLI's Session): staged writes are invisible until their
// commit, a discard leaves the old file, and output_identity sees one file behind two paths.
TEST_F(AtomicTarget, StagedWritesLandOnlyOnCommit) {
  const std::string a = (dir_ / "a.mesh").string(), b = (dir_ / "b.emb").string();
  { std::ofstream(b) << "old"; }
  StagedWrite sa, sb;
  const auto fill = [](const char* text) {
    return [text](std::ostream& out) { return static_cast<bool>(out << text); };
  };
  ASSERT_TRUE(stage_write(a, fill("mesh"), sa).ok());
  ASSERT_TRUE(stage_write(b, fill("new"), sb).ok());
  EXPECT_FALSE(fs::exists(a));
  EXPECT_EQ(read(b), "old");
  EXPECT_EQ(temporaries(), 2);
  EXPECT_EQ(temporaries_in_progress(), 2);  // removed on a signal until committed
  ASSERT_TRUE(commit_write(sa).ok());
  discard_write(sb);
  EXPECT_EQ(read(a), "mesh");
  EXPECT_EQ(read(b), "old");
  EXPECT_EQ(temporaries(), 0);
  EXPECT_EQ(temporaries_in_progress(), 0);
}

TEST_F(AtomicTarget, OutputIdentityFollowsLinksAndDirectories) {
  fs::create_directories(dir_ / "sub");
  const std::string plain = (dir_ / "x.mesh").string();
  EXPECT_EQ(output_identity(plain), output_identity((dir_ / "sub" / ".." / "x.mesh").string()));
  EXPECT_NE(output_identity(plain), output_identity((dir_ / "y.mesh").string()));
  fs::create_symlink("x.mesh", dir_ / "link.mesh");  // dangling: names the file to create
  EXPECT_EQ(output_identity(plain), output_identity((dir_ / "link.mesh").string()));
  { std::ofstream(plain) << "x"; }
  EXPECT_EQ(output_identity(plain), output_identity((dir_ / "link.mesh").string()));
  fs::create_hard_link(plain, dir_ / "hard.mesh");
  EXPECT_EQ(output_identity(plain), output_identity((dir_ / "hard.mesh").string()));
}

TEST_F(AtomicTarget, DevicesAreNotInputs) {
  EXPECT_EQ(unreadable_file_kind("/dev/zero"), "a character device");
  fs::create_symlink("/dev/urandom", dir_ / "r.txt");
  EXPECT_EQ(unreadable_file_kind((dir_ / "r.txt").string()), "a character device");
  { std::ofstream(dir_ / "f.txt") << "0 0\n"; }
  EXPECT_EQ(unreadable_file_kind((dir_ / "f.txt").string()), "");
  ASSERT_EQ(::mkfifo((dir_ / "in.fifo").c_str(), 0600), 0);
  EXPECT_EQ(unreadable_file_kind((dir_ / "in.fifo").string()), "");
  EXPECT_EQ(unreadable_file_kind((dir_ / "missing.txt").string()), "");
}

}  // namespace
}  // namespace imm
