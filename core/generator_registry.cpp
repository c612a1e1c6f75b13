#include "core/generator_registry.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <system_error>

namespace imm {

GeneratorSummary summarize(const GeneratorInfo& info) {
  GeneratorSummary g;
  g.name = info.name;
  for (const GeneratorParameter& p : info.parameters) {
    if (!g.params.empty()) g.params += ' ';
    std::string upper = p.name;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    g.params += "[" + upper + "=" + std::to_string(p.default_value) + "]";
  }
  g.description = info.description + " -- " + info.expected_note;
  return g;
}

std::string unknown_generator_error(std::string_view name) {
  return "unknown generator '" + std::string(name) + "' (see 'immerse generate --list')";
}

std::string parse_generator_arguments(const GeneratorInfo& info,
                                      const std::vector<std::string>& arguments,
                                      std::vector<long>& values) {
  const std::vector<GeneratorParameter>& params = info.parameters;
  const std::string& name = info.name;
  values.clear();
  for (const GeneratorParameter& p : params) values.push_back(p.default_value);
  std::vector<bool> set(params.size(), false);
  std::size_t positional = 0;
  for (const std::string& argument : arguments) {
    std::string key;
    std::string text = argument;
    if (const auto eq = argument.find('='); eq != std::string::npos) {
      key = argument.substr(0, eq);
      text = argument.substr(eq + 1);
    }
    std::size_t index = params.size();
    if (key.empty()) {
      while (positional < params.size() && set[positional]) ++positional;
      index = positional;
    } else {
      // Either case: `generate --list` prints the keys upper case (N=12), usage examples lower.
      const auto same_key = [](std::string_view a, std::string_view b) {
        return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
                 return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
               });
      };
      for (std::size_t i = 0; i < params.size(); ++i) {
        if (same_key(params[i].name, key)) index = i;
      }
      if (index == params.size()) return "generator '" + name + "' has no parameter '" + key + "'";
    }
    if (index >= params.size()) {
      return "generator '" + name + "' takes " + std::to_string(params.size()) + " parameter" +
             (params.size() == 1 ? "" : "s") + ", got '" + argument + "'";
    }
    const GeneratorParameter& p = params[index];
    long value = 0;
    const auto parsed = std::from_chars(text.data(), text.data() + text.size(), value);
    if (parsed.ec != std::errc() || parsed.ptr != text.data() + text.size()) {
      return "parameter '" + p.name + "' of '" + name + "' must be an integer, got '" + text + "'";
    }
    if (value < p.min_value || value > p.max_value) {
      return "parameter '" + p.name + "' of '" + name + "' must lie in [" +
             std::to_string(p.min_value) + ", " + std::to_string(p.max_value) + "], got " +
             std::to_string(value);
    }
    if (p.even && value % 2 != 0) return "parameter '" + p.name + "' of '" + name + "' must be even";
    values[index] = value;
    set[index] = true;
  }
  return {};
}

}  // namespace imm
