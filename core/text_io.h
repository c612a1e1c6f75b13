// Text helpers shared by the readers and writers of mesh files (core/medit.cpp,
// dim3/surface_io.cpp, dim3/tet_io.cpp; dim3/text_io.h adds the 3D point helpers). Internal to
// the readers: not a public interface.
//
// One copy of what both need to agree on: how a number is parsed (std::from_chars, correctly
// rounded, so that a written mesh reads back bit for bit) and written (shortest round trip), how
// a text file is split into tokens with line numbers, how a token and a place are quoted in a
// message, and how a whole file is read into one buffer.
#pragma once

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace imm::text {

/// How many messages a reader lists per defect kind: a broken file with a million records must
/// not produce a million lines.
inline constexpr std::size_t kMaxDefectsPerKind = 20;

/// White space within a line (the line break is handled by the callers, which count lines).
inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

/// The whole token as a double, correctly rounded; a leading '+' is allowed, "+-1" is not.
/// Out-of-range values become +-inf or the nearest tiny value, as strtod gives them.
/// @return nullopt when the token is not entirely a number
inline std::optional<double> parse_double(std::string_view s) {
  const char* begin = s.data();
  const char* end = begin + s.size();
  if (begin != end && *begin == '+') {
    ++begin;
    if (begin != end && *begin == '-') return std::nullopt;
  }
  double value = 0;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ptr != end) return std::nullopt;
  if (ec == std::errc::result_out_of_range)
    return std::strtod(std::string(s).c_str(), nullptr);  // +-inf or tiny
  if (ec != std::errc()) return std::nullopt;
  return value;
}

/// The whole token as an integer; a leading '+' is allowed.
/// @return nullopt when the token is not entirely an integer or does not fit a long long
inline std::optional<long long> parse_integer(std::string_view s) {
  const char* begin = s.data();
  const char* end = begin + s.size();
  if (begin != end && *begin == '+') ++begin;
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}

/// Reads a header token as a non-negative record count.
inline std::optional<long long> parse_count(std::optional<std::string_view> token) {
  if (!token) return std::nullopt;
  const auto n = parse_integer(*token);
  if (!n || *n < 0) return std::nullopt;
  return n;
}

/// Reserves room for `n` records of at least `min_record_size` bytes each, bounded by the size
/// of `text` so that a wrong count costs no memory.
template <class T>
void reserve_records(std::vector<T>& records, long long n, std::string_view text,
                     std::size_t min_record_size) {
  records.reserve(static_cast<std::size_t>(
      std::min<long long>(n, static_cast<long long>(text.size() / min_record_size))));
}

/// Whether a token starts with a letter (a keyword of the keyword formats: Medit, Vega).
inline bool starts_with_letter(std::string_view token) {
  return !token.empty() && std::isalpha(static_cast<unsigned char>(token.front()));
}

/// A token for a message: in single quotes, at most 40 characters, unprintable ones as '?'.
inline std::string quoted(std::string_view token) {
  constexpr std::size_t kMax = 40;
  std::string s(token.substr(0, kMax));
  for (char& c : s) {
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  }
  return "'" + s + (token.size() > kMax ? "...'" : "'");
}

/// "file:12: ", the start of a message about line 12 of a text file.
inline std::string at(const std::string& file, std::uint64_t line) {
  return file + ":" + std::to_string(line) + ": ";
}

/// The message for a file that ends after `i` of the `n` records (`what`) its header announced.
inline std::string truncated_message(const std::string& file, const char* what, long long i,
                                      long long n, std::uint64_t header_line) {
  return file + ": the file ends after " + std::to_string(i) + " of the " + std::to_string(n) +
         " " + what + " announced on line " + std::to_string(header_line);
}

/// The shortest decimal that reads back as the same double (as exact as max_digits10, shorter);
/// "0" for both zeros, "nan", "inf", "-inf".
inline std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  if (value == 0.0) return "0";  // also -0
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);  // shortest round trip
  return std::string(buffer, result.ptr);
}

/// The extension of `path` in lower case, with its dot (".obj"); empty when there is none.
inline std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

/// Whether the extension of `path`, in any case, is one of `extensions` (lower case, with the dot).
inline bool has_extension(const std::string& path,
                          std::initializer_list<std::string_view> extensions) {
  const std::string ext = lower_extension(path);
  return std::find(extensions.begin(), extensions.end(), ext) != extensions.end();
}

/// The whole file in one buffer.
/// @return nullopt with `error` set ("cannot open 'path': reason", ...) when it cannot be read
inline std::optional<std::string> read_file(const std::string& path, std::string& error) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    error = "cannot read '" + path + "': it is a directory";
    return std::nullopt;
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    error = "cannot open '" + path + "': " + std::strerror(errno);
    return std::nullopt;
  }
  std::string data;
  file.seekg(0, std::ios::end);
  const std::streamoff size = file.tellg();
  file.seekg(0, std::ios::beg);
  if (size > 0) {
    data.resize(static_cast<std::size_t>(size));
    file.read(data.data(), size);
  }
  if (!file) {
    error = "cannot read '" + path + "'";
    return std::nullopt;
  }
  return data;
}

/// What separates the tokens of a format besides white space and line breaks.
struct TokenRules {
  enum class Hash {
    Text,            ///< '#' is an ordinary character (PLY body, STL)
    Comment,         ///< '#' where a token could start begins a comment to the end of the line
                     ///< (OFF: "1#2" is one token)
    CommentAnywhere  ///< also inside a token (Vega, Medit, TetGen: "1#2" is "1", then a comment)
  };
  Hash hash = Hash::Text;
  bool comma_separates = false;  ///< ',' separates like white space (Vega)
};

/// Whitespace-separated tokens with line numbers (OFF, PLY, ASCII STL, Vega, Medit, TetGen).
class Tokens {
 public:
  /// Reads `text` from byte `pos`, which is on line `line`; line() is `first_token_line` until a
  /// token is read.
  Tokens(std::string_view text, TokenRules rules, std::size_t pos = 0, std::uint64_t line = 1,
         std::uint64_t first_token_line = 1)
      : text_(text), rules_(rules), pos_(pos), line_(line), token_line_(first_token_line) {}

  /// The next token, or nullopt at the end; line() is then its line.
  std::optional<std::string_view> next() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        ++line_;
        ++pos_;
      } else if (is_separator(c)) {
        ++pos_;
      } else if (c == '#' && rules_.hash != TokenRules::Hash::Text) {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else {
        break;
      }
    }
    if (pos_ >= text_.size()) return std::nullopt;
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_separator(text_[pos_]) && text_[pos_] != '\n' &&
           !(text_[pos_] == '#' && rules_.hash == TokenRules::Hash::CommentAnywhere))
      ++pos_;
    token_line_ = line_;
    return text_.substr(start, pos_ - start);
  }
  /// The next token if it is on the line of the previous one.
  std::optional<std::string_view> next_on_line() {
    const std::uint64_t line = token_line_;
    const std::size_t pos = pos_;
    const std::uint64_t current = line_;
    auto token = next();
    if (token && token_line_ == line) return token;
    pos_ = pos;
    line_ = current;
    token_line_ = line;
    return std::nullopt;
  }
  /// Skips the rest of the current line (trailing attributes, colors, normals, a count).
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }
  [[nodiscard]] std::uint64_t line() const { return token_line_; }
  /// The byte where reading goes on (after skip_line(): the end of the current line), for a
  /// reader that splits the rest of the text among threads.
  [[nodiscard]] std::size_t position() const { return pos_; }

 private:
  [[nodiscard]] bool is_separator(char c) const {
    return is_space(c) || (rules_.comma_separates && c == ',');
  }
  std::string_view text_;
  TokenRules rules_;
  std::size_t pos_;
  std::uint64_t line_;
  std::uint64_t token_line_;
};

}  // namespace imm::text
