// A bound on what one command writes: total bytes and a wall-clock deadline (DESIGN §3: the
// `--time-limit` bounds the whole command, not only the search; outputs cannot fill the disk).
//
// OutputBudget is shared by every output of a command. BudgetedStream wraps the stream a
// write_file_atomic fill callback receives: once the bytes would pass the budget or the deadline
// has passed, the wrapped stream fails (badbit), the fill callback sees it and returns false, and
// write_file_atomic removes the temporary. Callers that can estimate an output's size before
// producing it (an SVG per immersion, a JSON with every graph) ask `fits` first and refuse early,
// before spending memory on it.
#pragma once

#include <chrono>
#include <cstdint>
#include <limits>
#include <optional>
#include <ostream>
#include <streambuf>
#include <string>

namespace imm {

class OutputBudget {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::uint64_t kUnlimited = std::numeric_limits<std::uint64_t>::max();

  /// @param[in] max_bytes total bytes all outputs may take (kUnlimited: no bound)
  /// @param[in] deadline  the time after which nothing more is written (none: no bound)
  explicit OutputBudget(std::uint64_t max_bytes = kUnlimited, std::optional<Clock::time_point> deadline = {})
      : max_bytes_(max_bytes), deadline_(deadline) {}

  /// Takes `bytes` from the budget. @return false (and takes nothing) when they do not fit.
  bool charge(std::uint64_t bytes) {
    if (bytes > max_bytes_ - used_) {
      exceeded_ = true;
      return false;
    }
    used_ += bytes;
    return true;
  }
  /// Whether `bytes` more would fit (nothing is taken).
  [[nodiscard]] bool fits(std::uint64_t bytes) const { return bytes <= max_bytes_ - used_; }
  /// Whether the deadline has passed (checks the clock).
  [[nodiscard]] bool expired() const { return deadline_ && Clock::now() >= *deadline_; }

  [[nodiscard]] std::uint64_t used() const { return used_; }
  [[nodiscard]] std::uint64_t max_bytes() const { return max_bytes_; }
  /// Whether a charge was refused (the budget, not the deadline, stopped a write).
  [[nodiscard]] bool exceeded() const { return exceeded_; }

 private:
  std::uint64_t max_bytes_;
  std::optional<Clock::time_point> deadline_;
  std::uint64_t used_ = 0;
  bool exceeded_ = false;
};

namespace detail {

/// Forwards to another streambuf while charging an OutputBudget; fails once it is spent.
class BudgetedStreambuf : public std::streambuf {
 public:
  BudgetedStreambuf(std::streambuf* target, OutputBudget& budget) : target_(target), budget_(budget) {}

  /// Why writing stopped: "" while it has not.
  [[nodiscard]] const std::string& stopped() const { return stopped_; }

 protected:
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (!stopped_.empty()) return 0;
    // The clock is read about every 64 KiB, not per character.
    since_clock_ += static_cast<std::uint64_t>(n);
    if (since_clock_ >= kClockEvery) {
      since_clock_ = 0;
      if (budget_.expired()) {
        stopped_ = "the time limit was reached while writing";
        return 0;
      }
    }
    if (!budget_.charge(static_cast<std::uint64_t>(n))) {
      stopped_ = "the output budget of " + std::to_string(budget_.max_bytes()) + " bytes would be exceeded";
      return 0;
    }
    return target_->sputn(s, n);
  }
  int sync() override { return target_->pubsync(); }

 private:
  static constexpr std::uint64_t kClockEvery = 64 * 1024;
  std::streambuf* target_;
  OutputBudget& budget_;
  std::uint64_t since_clock_ = kClockEvery;  // the first write reads the clock
  std::string stopped_;
};

}  // namespace detail

/// An ostream over `target` charged to `budget` (see the file comment).
class BudgetedStream : public std::ostream {
 public:
  BudgetedStream(std::ostream& target, OutputBudget& budget) : std::ostream(nullptr), buf_(target.rdbuf(), budget) {
    rdbuf(&buf_);
  }
  /// Why writing stopped ("" while it has not): the budget in bytes or the time limit.
  [[nodiscard]] const std::string& stopped() const { return buf_.stopped(); }

 private:
  detail::BudgetedStreambuf buf_;
};

}  // namespace imm
