// core/parallel.h: parallel_for on the process's thread pool. Every index runs once, the caller
// is worker 0, the pool's threads are kept between loops, nested loops run inline, errors come
// back to the caller, loops from two outside threads both finish, and bodies run in the caller's
// rounding mode; a loop that finds the pool busy keeps the caller as worker 0 and its nested loops
// inline, a forked child's loops do not wait for the parent's threads, and a loop runs on the
// threads there are when the system refuses more.
#include "core/parallel.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>

#include <atomic>
#include <cfenv>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <set>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <vector>

namespace imm {
namespace {

/// The threads (and their worker numbers) that ran a loop of `count` items on `threads` threads.
struct LoopRun {
  std::vector<int> visits;
  std::set<std::thread::id> ids;
  std::set<unsigned> workers;
  std::thread::id worker0;
};

LoopRun run(unsigned threads, std::size_t count, std::size_t grain = 1) {
  LoopRun r;
  r.visits.assign(count, 0);
  std::mutex mutex;
  std::condition_variable arrived;
  // Every worker holds its first item until min(threads, count) threads have one (or 10 s have
  // passed, which fails the checks on the thread set): so each worker takes an item however late
  // the machine schedules it.
  const std::size_t expected = std::min<std::size_t>(threads, count);
  parallel_for(threads, count, [&](std::size_t i, unsigned worker) {
    std::atomic_ref<int>(r.visits[i]).fetch_add(1);
    std::unique_lock<std::mutex> lock(mutex);
    const bool first = r.ids.insert(std::this_thread::get_id()).second;
    r.workers.insert(worker);
    if (worker == 0) r.worker0 = std::this_thread::get_id();
    if (first) {
      arrived.notify_all();
      arrived.wait_for(lock, std::chrono::seconds(10), [&] { return r.ids.size() >= expected; });
    }
  }, grain);
  return r;
}

TEST(ParallelFor, EveryIndexRunsOnceOnEveryThreadCount) {
  for (unsigned threads : {1u, 2u, 3u, 8u}) {
    for (std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{100}}) {
      const LoopRun r = run(threads, count);
      for (std::size_t i = 0; i < count; ++i) EXPECT_EQ(r.visits[i], 1) << threads << " threads, item " << i;
      for (unsigned w : r.workers) EXPECT_LT(w, threads);
      EXPECT_LE(r.ids.size(), std::min<std::size_t>(threads, std::max<std::size_t>(count, 1)));
    }
  }
}

TEST(ParallelFor, TheCallerIsWorkerZeroAndThePoolsThreadsAreKept) {
  const LoopRun first = run(3, 300);
  ASSERT_EQ(first.ids.size(), 3u);
  EXPECT_EQ(first.worker0, std::this_thread::get_id());
  const LoopRun second = run(3, 300);
  EXPECT_EQ(second.ids, first.ids) << "a loop started threads of its own instead of the pool's";
  const LoopRun two = run(2, 300);
  EXPECT_EQ(two.ids.size(), 2u);
  for (const std::thread::id& id : two.ids) EXPECT_EQ(first.ids.count(id), 1u);
}

TEST(ParallelFor, ANestedLoopRunsInlineOnItsWorker) {
  std::vector<int> inner_on_own_thread(8, 0);
  parallel_for(2, 8, [&](std::size_t i, unsigned) {
    const std::thread::id outer = std::this_thread::get_id();
    bool same = true, worker_zero = true;
    parallel_for(4, 64, [&](std::size_t, unsigned worker) {
      same = same && std::this_thread::get_id() == outer;
      worker_zero = worker_zero && worker == 0;
    }, 1);
    inner_on_own_thread[i] = same && worker_zero;
  }, 1);
  for (int ok : inner_on_own_thread) EXPECT_EQ(ok, 1);
}

TEST(ParallelFor, AnErrorReachesTheCallerAndThePoolStaysUsable) {
  EXPECT_THROW(parallel_for(2, 1000, [](std::size_t i, unsigned) {
    if (i == 500) throw std::runtime_error("item 500");
  }, 1), std::runtime_error);
  const LoopRun after = run(2, 100);
  for (int v : after.visits) EXPECT_EQ(v, 1);
}

TEST(ParallelFor, LoopsFromTwoOutsideThreadsBothFinish) {
  std::vector<LoopRun> runs(2);
  std::thread a([&] { runs[0] = run(2, 400); });
  std::thread b([&] { runs[1] = run(2, 400); });
  a.join();
  b.join();
  for (const LoopRun& r : runs)
    for (int v : r.visits) EXPECT_EQ(v, 1);
}

/// Another thread's loop holding the pool (both of its workers busy) until release().
class PoolHolder {
 public:
  PoolHolder()
      : thread_([this] {
          parallel_for(2, 2, [this](std::size_t, unsigned) {
            holding_ = true;
            while (!release_) std::this_thread::yield();
          }, 1);
        }) {
    while (!holding_) std::this_thread::yield();
  }
  ~PoolHolder() { release(); }
  void release() {
    release_ = true;
    if (thread_.joinable()) thread_.join();
  }

 private:
  std::atomic<bool> holding_{false}, release_{false};
  std::thread thread_;
};

// While another thread's loop holds the pool, a loop runs on threads of its own: the caller is
// still worker 0, and a loop nested in its bodies still runs inline (it went to yet more threads).
TEST(ParallelFor, ALoopThatFindsThePoolBusyKeepsTheCallerAsWorkerZeroAndNestsInline) {
  PoolHolder holder;
  std::mutex mutex;
  std::set<std::thread::id> worker0;
  std::vector<int> inline_nested(8, 0);
  parallel_for(2, inline_nested.size(), [&](std::size_t i, unsigned worker) {
    const std::thread::id outer = std::this_thread::get_id();
    if (worker == 0) {
      const std::lock_guard<std::mutex> lock(mutex);
      worker0.insert(outer);
    }
    bool same = true;
    parallel_for(2, 64, [&](std::size_t, unsigned inner) { same = same && inner == 0 && std::this_thread::get_id() == outer; }, 1);
    inline_nested[i] = same;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }, 1);
  holder.release();
  EXPECT_EQ(worker0, std::set<std::thread::id>{std::this_thread::get_id()});
  for (int ok : inline_nested) EXPECT_EQ(ok, 1);
}

// A child forked after the pool started has none of its threads: its loops must not wait for
// them (a Python multiprocessing worker of a process that had meshed hung there).
TEST(ParallelFor, AForkedChildsLoopsRunWithoutTheParentsThreads) {
  run(2, 50);  // the pool's threads are running in this process
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::alarm(10);  // a hang ends as SIGALRM
    std::vector<int> visits(200, 0);
    parallel_for(2, visits.size(), [&](std::size_t i, unsigned) { std::atomic_ref<int>(visits[i]).fetch_add(1); }, 1);
    ::_exit(std::all_of(visits.begin(), visits.end(), [](int v) { return v == 1; }) ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child's loop hung or crashed (signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0) << ")";
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

// The address space limited to what the process maps now plus 1 MB: no thread stack (8 MB) fits,
// so pthread_create fails, as on a machine out of memory or at a process's thread limit.
// @return the limit before
rlimit refuse_new_threads() {
  long pages = 0;
  std::ifstream("/proc/self/statm") >> pages;
  rlimit old{};
  ::getrlimit(RLIMIT_AS, &old);
  rlimit low = old;
  low.rlim_cur = static_cast<rlim_t>(pages) * static_cast<rlim_t>(::sysconf(_SC_PAGESIZE)) + (1 << 20);
  ::setrlimit(RLIMIT_AS, &low);
  try {
    std::thread t([] {});
    t.join();
    std::fprintf(stderr, "the limit did not refuse a thread\n");
    ::_exit(3);
  } catch (const std::system_error&) {
  }
  return old;
}

bool every_item_once(unsigned threads, std::size_t count) {
  std::vector<int> visits(count, 0);
  parallel_for(threads, count, [&](std::size_t i, unsigned) { std::atomic_ref<int>(visits[i]).fetch_add(1); }, 1);
  return std::all_of(visits.begin(), visits.end(), [](int v) { return v == 1; });
}

// In a fresh process (the pool not started yet): a loop on more threads than the system gives
// runs on those there are, and the pool stays usable. A refused thread once left the pool's
// wake-up list one entry ahead of its threads, and the second later loop that needed a new
// thread waited forever for it.
[[noreturn]] void refused_thread_on_the_pool() {
  ::alarm(20);  // a hang ends as SIGALRM
  if (!every_item_once(2, 1000)) ::_exit(1);
  const rlimit old = refuse_new_threads();
  bool ok = false;
  try {
    ok = every_item_once(4, 1000);
  } catch (const std::system_error&) {  // what it did before; the loops below must still run
  }
  ::setrlimit(RLIMIT_AS, &old);
  for (int loop = 0; loop < 3; ++loop) {
    const LoopRun r = run(3, 300);
    if (r.ids.size() != 3 || !std::all_of(r.visits.begin(), r.visits.end(), [](int v) { return v == 1; })) ::_exit(5);
  }
  ::_exit(ok ? 0 : 4);
}

// While another thread's loop holds the pool, a loop starts threads of its own: when the system
// refuses them, the loop runs on the calling thread (it threw, or with one thread started,
// destroyed it joinable: std::terminate).
[[noreturn]] void refused_thread_beside_a_busy_pool() {
  ::alarm(20);
  PoolHolder holder;
  const rlimit old = refuse_new_threads();
  const bool ok = every_item_once(4, 1000);
  ::setrlimit(RLIMIT_AS, &old);
  holder.release();
  ::_exit(ok ? 0 : 4);
}

TEST(ParallelForDeathTest, ALoopRunsOnTheThreadsThereAreWhenTheSystemRefusesMore) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");  // a fresh process: the pool starts in it
  EXPECT_EXIT(refused_thread_on_the_pool(), ::testing::ExitedWithCode(0), "");
  EXPECT_EXIT(refused_thread_beside_a_busy_pool(), ::testing::ExitedWithCode(0), "");
}

// Many tiny loops back to back, on a pool that grows and shrinks between them: every loop ends
// with every item run once (a lost wake-up or a stale loop's task would hang or miscount).
TEST(ParallelFor, ThousandsOfTinyLoopsOnAGrowingAndShrinkingPool) {
  std::vector<int> visits(8);
  for (int loop = 0; loop < 3000; ++loop) {
    const unsigned threads = loop % 3 == 0 ? 2 : loop % 3 == 1 ? 5 : 3;
    std::fill(visits.begin(), visits.end(), 0);
    parallel_for(threads, visits.size(), [&](std::size_t i, unsigned worker) {
      ASSERT_LT(worker, threads);
      std::atomic_ref<int>(visits[i]).fetch_add(1);
    }, 1);
    for (int v : visits) ASSERT_EQ(v, 1) << "loop " << loop;
  }
}

TEST(ParallelFor, BodiesRunInTheCallersRoundingMode) {
  const auto modes = [](unsigned threads) {
    std::vector<int> mode(64, -1);
    parallel_for(threads, mode.size(), [&](std::size_t i, unsigned) {
      mode[i] = std::fegetround();
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    }, 1);
    return std::set<int>(mode.begin(), mode.end());
  };
  const int saved = std::fegetround();
  ASSERT_EQ(std::fesetround(FE_UPWARD), 0);
  const std::set<int> upward = modes(2);
  std::fesetround(saved);
  EXPECT_EQ(upward, std::set<int>{FE_UPWARD});
  EXPECT_EQ(modes(2), std::set<int>{saved}) << "a pool thread kept an earlier caller's rounding mode";
}

TEST(ParallelFor, LoopCpuCountsOnlyLoopsOnSeveralThreads) {
  const auto spin = [](std::size_t, unsigned) {
    volatile double x = 0;
    for (int k = 0; k < 200000; ++k) x = x + 1.0;
  };
  const double before = loop_cpu_seconds();
  parallel_for(1, 20, spin, 1);
  EXPECT_EQ(loop_cpu_seconds(), before);  // one worker: the caller's own (serial) work
  parallel_for(2, 20, spin, 1);
  EXPECT_GT(loop_cpu_seconds(), before);
}

}  // namespace
}  // namespace imm
