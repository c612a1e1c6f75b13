// A tiny JSON writer for reports (DESIGN §3 "JSON report"): objects keep insertion order, numbers
// are printed with full precision (the shortest text that round-trips), strings are escaped, and
// the output is pretty-printed and deterministic. No external library.
#pragma once

#include <concepts>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace imm {

/// `text` with JSON string escapes applied (no surrounding quotes).
std::string json_escape(std::string_view text);

/// The shortest decimal text that reads back as exactly `value`; "null" when not finite
/// (JSON has no NaN or infinity); -0 is written "0".
std::string json_number(double value);

/// A JSON value built in memory and printed with dump().
class Json {
 public:
  enum class Type { Null, Bool, Number, String, Array, Object };

  Json() = default;
  Json(std::nullptr_t) {}
  Json(bool value) : type_(Type::Bool), text_(value ? "true" : "false") {}
  template <std::integral T>
  requires(!std::same_as<T, bool>) Json(T value)
      : type_(Type::Number), text_(std::to_string(value)) {}
  /// A non-finite double becomes null.
  Json(double number);
  Json(const char* text) : type_(Type::String), text_(text) {}
  Json(std::string text) : type_(Type::String), text_(std::move(text)) {}
  Json(std::string_view text) : type_(Type::String), text_(text) {}

  [[nodiscard]] static Json array() {
    Json j;
    j.type_ = Type::Array;
    return j;
  }
  [[nodiscard]] static Json object() {
    Json j;
    j.type_ = Type::Object;
    return j;
  }

  [[nodiscard]] Type type() const { return type_; }

  /// Appends to an array. @pre type() == Array. @return the appended element.
  Json& push(Json value);
  /// Sets a member of an object (replacing one with the same key in place).
  /// @pre type() == Object. @return the member's value.
  Json& set(std::string_view key, Json value);

  /// Pretty-printed text (two spaces per level; arrays of scalars on one wrapped line),
  /// ending with a newline.
  [[nodiscard]] std::string dump() const;

 private:
  void write(std::string& out, int indent) const;

  Type type_ = Type::Null;
  std::string text_;  // Bool / Number: the literal; String: the raw (unescaped) text
  std::vector<Json> elements_;
  std::vector<std::pair<std::string, Json>> members_;
};

}  // namespace imm
