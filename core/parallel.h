// A small std::thread loop for the independent per-element work of the meshing step (paper §7.1:
// every background element's local regions are computed on their own) and of the deformation
// solvers. TBB is not a dependency of this project, so the loop is written out once here and
// shared by the exact clipping and the CSG baseline, which must run on the same number of
// threads to be compared fairly.
#pragma once

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cfenv>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace imm {

/// Most threads a caller may ask for (0 = all cores): the program's --threads and the C++ API's
/// `threads` refuse more, since per-thread scratch is allocated up front.
inline constexpr unsigned kMaxThreads = 1024;

/// CPU seconds the calling thread has used so far (POSIX CLOCK_THREAD_CPUTIME_ID): for
/// attributing work done on several threads, which wall time cannot when threads share cores.
inline double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// CPU seconds the whole process has used so far, all threads (POSIX CLOCK_PROCESS_CPUTIME_ID):
/// the work of a stage that runs on several threads, which the calling thread's clock misses.
inline double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// CPU seconds the calling thread has spent so far as worker 0 of loops run on several threads
/// (parallel_for): thread_cpu_seconds() minus this is its serial work, outside those loops (the
/// serial fraction of BENCHMARKS.md's thread-scaling model).
inline double& loop_cpu_seconds() {
  thread_local double seconds = 0.0;
  return seconds;
}

/// The thread count to use for a request of `threads` (0 = one per hardware thread).
inline unsigned resolve_threads(unsigned threads) {
  return threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
}

namespace detail {

/// The threads parallel_for runs on, started on first use and kept for the life of the process.
/// A meshing run makes hundreds of loops (454 on two tori at 2.5 M tets): a thread started per
/// loop cost its start-up, a cold cache and a fresh malloc cache every time (BENCHMARKS.md,
/// "Thread pool"). One loop runs at a time; the calling thread takes part as worker 0.
class WorkerPool {
 public:
  using Task = void (*)(void* context, unsigned worker);

  /// The process's pool. Never destroyed: its threads sleep until the process ends, so no exit
  /// path (std::exit from any thread, a Python interpreter shutting down) waits on them.
  static WorkerPool& instance() {
    static WorkerPool* pool = new WorkerPool;
    return *pool;
  }

  /// True on a thread running a loop's task (the calling thread included, and the threads of a
  /// loop that could not have the pool): a loop started there runs inline, so nested loops do
  /// not multiply the threads.
  static bool& inside() {
    thread_local bool flag = false;
    return flag;
  }

  /// Runs task(context, w) for every w in [0, workers), w = 0 on the calling thread and the
  /// others on the pool's threads (started when fewer are running), all in the calling thread's
  /// floating-point environment (rounding mode), and returns when all have returned. The task must
  /// not throw. Returns false, having run nothing, when another thread is running a loop on the
  /// pool, or in a child process forked after the pool started (the child has none of its
  /// threads: waiting for them would hang, as in a Python multiprocessing worker). When the system
  /// refuses a new thread (pthread_create: a process limit, no memory for its stack) the loop
  /// runs on the threads there are, so `workers` is an upper bound: parallel_for's items are
  /// taken dynamically, by any number of workers.
  bool try_run(unsigned workers, Task task, void* context) {
    if (::getpid() != owner_) return false;
    std::unique_lock<std::mutex> caller(run_mutex_, std::try_to_lock);
    if (!caller.owns_lock()) return false;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      while (threads_.size() + 1 < workers) {
        const auto id = static_cast<unsigned>(threads_.size() + 1);
        // Thread id's condition variable is wakes_[id - 1]: added only with its thread, so that
        // a refused thread leaves the two lists in step (it left a stray one, and every later
        // thread then slept on its neighbour's, a hang).
        auto wake = std::make_unique<std::condition_variable>();
        wakes_.reserve(threads_.size() + 1);  // so that its push_back below cannot throw
        try {
          threads_.emplace_back([this, id, w = wake.get()] { serve(id, *w); });
        } catch (const std::system_error&) {
          workers = static_cast<unsigned>(threads_.size() + 1);
          break;
        }
        wakes_.push_back(std::move(wake));
      }
      task_ = task;
      context_ = context;
      std::fegetenv(&environment_);
      participants_ = workers;
      pending_ = workers - 1;
      ++generation_;
    }
    // Only this loop's threads: after a loop on many threads, the others sleep on.
    for (unsigned w = 1; w < workers; ++w) wakes_[w - 1]->notify_one();
    inside() = true;
    task(context, 0);
    inside() = false;
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return pending_ == 0; });
    return true;
  }

 private:
  WorkerPool() = default;

  void serve(unsigned id, std::condition_variable& wake) {
    inside() = true;
    std::uint64_t served = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      // A loop not served yet that needs this thread (the loops it is not part of pass it by).
      wake.wait(lock, [&] { return generation_ != served && id < participants_; });
      served = generation_;
      const Task task = task_;
      void* const context = context_;
      std::fesetenv(&environment_);
      lock.unlock();
      task(context, id);
      lock.lock();
      if (--pending_ == 0) done_.notify_one();
    }
  }

  const pid_t owner_ = ::getpid();  ///< the process whose threads these are
  std::mutex run_mutex_;  ///< held by the thread whose loop runs on the pool
  std::mutex mutex_;      ///< guards everything below
  std::condition_variable done_;
  std::vector<std::unique_ptr<std::condition_variable>> wakes_;  ///< thread k - 1's, woken for its loops
  std::vector<std::thread> threads_;  ///< thread k - 1 is worker k
  std::uint64_t generation_ = 0;      ///< loops started so far
  Task task_ = nullptr;
  void* context_ = nullptr;
  std::fenv_t environment_{};  ///< the calling thread's, set on the pool's threads for the task
  unsigned participants_ = 0;  ///< workers of the current loop, the calling thread included
  unsigned pending_ = 0;       ///< pool threads of the current loop still running it
};

}  // namespace detail

/// Runs body(i, worker) for every i in [0, count) on at most `threads` threads, `worker` the
/// index of the thread running it (below the number of workers used; 0 is the calling thread).
/// Scheduling is dynamic: workers take min(grain, 16) consecutive indices at a time, so unevenly
/// expensive items balance. With one worker the items run in order on the calling thread, as do
/// loops started inside a body (nested loops do not multiply the threads). The threads are the
/// process's pool (detail::WorkerPool); a loop started while another thread's loop holds the pool
/// runs on threads of its own (the caller still worker 0). An exception thrown by a body stops the
/// loop and is rethrown here (when several workers throw, the lowest-numbered worker's; callers
/// that need the first item's error in item order catch inside the body, as the meshing loops do).
/// @param grain the fewest items worth a thread of their own.
template <class Body>
void parallel_for(unsigned threads, std::size_t count, const Body& body, std::size_t grain = 64) {
  grain = std::max<std::size_t>(grain, 1);
  const std::size_t step = std::min<std::size_t>(grain, 16);
  const auto workers = static_cast<unsigned>(std::min<std::size_t>(std::max(threads, 1u), (count + grain - 1) / grain));
  if (workers <= 1 || detail::WorkerPool::inside()) {
    for (std::size_t i = 0; i < count; ++i) body(i, 0u);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(workers);
  const auto work = [&](unsigned w) {
    try {
      for (std::size_t i; (i = next.fetch_add(step)) < count;)
        for (std::size_t j = i; j < std::min(count, i + step); ++j) body(j, w);
    } catch (...) {
      errors[w] = std::current_exception();
      next = count;
    }
  };
  using Work = decltype(work);
  const detail::WorkerPool::Task task = [](void* context, unsigned w) { (*static_cast<const Work*>(context))(w); };
  const double start = thread_cpu_seconds();
  if (!detail::WorkerPool::instance().try_run(workers, task, const_cast<void*>(static_cast<const void*>(&work)))) {
    const auto inside = [&](unsigned w) {
      detail::WorkerPool::inside() = true;
      work(w);
      detail::WorkerPool::inside() = false;
    };
    std::vector<std::thread> own;
    own.reserve(workers - 1);
    try {
      for (unsigned w = 1; w < workers; ++w) own.emplace_back(inside, w);
    } catch (const std::system_error&) {
      // A refused thread: the loop runs on those started (the items are taken dynamically);
      // unwinding past them would destroy joinable threads (std::terminate).
    }
    inside(0);
    for (std::thread& th : own) th.join();
  }
  loop_cpu_seconds() += thread_cpu_seconds() - start;
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

/// Runs body(begin, end) over [0, count) cut into consecutive blocks of `block` items, the blocks
/// on at most `threads` threads (one block per task: for loops whose items are too cheap to be
/// scheduled one by one).
template <class Body>
void parallel_blocks(unsigned threads, std::size_t count, std::size_t block, const Body& body) {
  block = std::max<std::size_t>(block, 1);
  const std::size_t blocks = (count + block - 1) / block;
  parallel_for(threads, blocks, [&](std::size_t b, unsigned) { body(b * block, std::min(count, (b + 1) * block)); }, 1);
}

/// An ordered append on several threads: item i of [0, count) produces count_of(i) outputs, which
/// go to offsets in item order (item i's at the sum of count_of over the items before it), so the
/// result is the sequential loop's for every thread count. Calls count_of on every item (twice:
/// keep it cheap and pure), then allocate(total) once on the calling thread, then write(i, offset)
/// on every item with count_of(i) > 0, which writes its outputs at offset, offset + 1, ...
/// @return the total.
template <class Count, class Allocate, class Write>
std::size_t parallel_ordered_append(unsigned threads, std::size_t count, const Count& count_of,
                                    const Allocate& allocate, const Write& write, std::size_t block = 8192) {
  block = std::max<std::size_t>(block, 1);
  const std::size_t blocks = (count + block - 1) / block;
  std::vector<std::size_t> offset(blocks + 1, 0);
  parallel_for(threads, blocks, [&](std::size_t b, unsigned) {
    std::size_t n = 0;
    for (std::size_t i = b * block; i < std::min(count, (b + 1) * block); ++i) n += count_of(i);
    offset[b + 1] = n;
  }, 1);
  for (std::size_t b = 0; b < blocks; ++b) offset[b + 1] += offset[b];
  allocate(offset[blocks]);
  parallel_for(threads, blocks, [&](std::size_t b, unsigned) {
    std::size_t at = offset[b];
    for (std::size_t i = b * block; i < std::min(count, (b + 1) * block); ++i) {
      const std::size_t n = count_of(i);
      if (n == 0) continue;
      write(i, at);
      at += n;
    }
  }, 1);
  return offset[blocks];
}

}  // namespace imm
