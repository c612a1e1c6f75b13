#include "core/report_json.h"

#include <charconv>
#include <cmath>

#include "core/diagnostics.h"

namespace imm {

std::string json_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 2);
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      default:
        if (c < 0x20) {
          static constexpr char kHex[] = "0123456789abcdef";
          out += "\\u00";
          out += kHex[c >> 4];
          out += kHex[c & 15];
        } else {
          out += ch;
        }
    }
  }
  return out;
}

std::string json_number(double value) {
  if (!std::isfinite(value)) return "null";
  if (value == 0.0) return "0";  // also turns -0 into 0
  char buffer[64];
  // std::to_chars without a precision gives the shortest text that round-trips.
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  IMM_ASSERT(result.ec == std::errc(), "to_chars failed for a double");
  return std::string(buffer, result.ptr);
}

Json::Json(double number) {
  const std::string text = json_number(number);
  if (text == "null") return;  // stays Type::Null
  type_ = Type::Number;
  text_ = text;
}

Json& Json::push(Json value) {
  IMM_ASSERT(type_ == Type::Array, "Json::push on a value that is not an array");
  elements_.push_back(std::move(value));
  return elements_.back();
}

Json& Json::set(std::string_view key, Json value) {
  IMM_ASSERT(type_ == Type::Object, "Json::set on a value that is not an object");
  for (auto& member : members_) {
    if (member.first == key) {
      member.second = std::move(value);
      return member.second;
    }
  }
  members_.emplace_back(std::string(key), std::move(value));
  return members_.back().second;
}

namespace {

constexpr std::size_t kLineWidth = 100;

void newline(std::string& out, int indent) {
  out += '\n';
  out.append(static_cast<std::size_t>(indent) * 2, ' ');
}

}  // namespace

void Json::write(std::string& out, int indent) const {
  switch (type_) {
    case Type::Null: out += "null"; return;
    case Type::Bool:
    case Type::Number: out += text_; return;
    case Type::String:
      out += '"';
      out += json_escape(text_);
      out += '"';
      return;
    case Type::Array: {
      if (elements_.empty()) {
        out += "[]";
        return;
      }
      bool scalars = true;
      for (const Json& e : elements_)
        scalars = scalars && e.type_ != Type::Array && e.type_ != Type::Object;
      if (scalars) {
        // One line, wrapped when it gets long (continuation lines indented one level deeper).
        out += '[';
        std::size_t line_start = out.rfind('\n');
        line_start = line_start == std::string::npos ? 0 : line_start + 1;
        for (std::size_t i = 0; i < elements_.size(); ++i) {
          if (i > 0) {
            out += ',';
            if (out.size() - line_start > kLineWidth) {
              newline(out, indent + 1);
              line_start = out.size() - static_cast<std::size_t>(indent + 1) * 2;
            } else {
              out += ' ';
            }
          }
          elements_[i].write(out, indent + 1);
        }
        out += ']';
        return;
      }
      out += '[';
      for (std::size_t i = 0; i < elements_.size(); ++i) {
        if (i > 0) out += ',';
        newline(out, indent + 1);
        elements_[i].write(out, indent + 1);
      }
      newline(out, indent);
      out += ']';
      return;
    }
    case Type::Object: {
      if (members_.empty()) {
        out += "{}";
        return;
      }
      out += '{';
      for (std::size_t i = 0; i < members_.size(); ++i) {
        if (i > 0) out += ',';
        newline(out, indent + 1);
        out += '"';
        out += json_escape(members_[i].first);
        out += "\": ";
        members_[i].second.write(out, indent + 1);
      }
      newline(out, indent);
      out += '}';
      return;
    }
  }
}

std::string Json::dump() const {
  std::string out;
  write(out, 0);
  out += '\n';
  return out;
}

}  // namespace imm
