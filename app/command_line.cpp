#include "app/command_line.h"

#include <CLI/CLI.hpp>

#include <charconv>
#include <cmath>
#include <memory>
#include <sstream>

namespace imm::cli {
namespace {

constexpr std::size_t kHelpWidth = 100;
constexpr std::size_t kNameColumn = 28;

/// Greedy word wrap of `text` to lines of at most `width` characters; explicit newlines kept.
std::string wrap(const std::string& text, std::size_t width) {
  std::string out;
  std::istringstream lines(text);
  std::string line;
  bool first_line = true;
  while (std::getline(lines, line)) {
    if (!first_line) out += '\n';
    first_line = false;
    std::istringstream words(line);
    std::string word;
    std::size_t column = 0;
    while (words >> word) {
      if (column > 0 && column + 1 + word.size() > width) {
        out += '\n';
        column = 0;
      } else if (column > 0) {
        out += ' ';
        ++column;
      }
      out += word;
      column += word.size();
    }
  }
  return out;
}

/// "usage: immerse <usage>", the description, CLI11's option list, the footer.
class HelpFormatter : public CLI::Formatter {
 public:
  explicit HelpFormatter(const CommandSpec& spec) : spec_(spec) { column_width(kNameColumn); }

  std::string make_help(const CLI::App* app, std::string, CLI::AppFormatMode) const override {
    std::ostringstream out;
    out << "usage: immerse " << spec_.usage << "\n\n";
    out << spec_.description;
    out << make_positionals(app) << make_groups(app, CLI::AppFormatMode::Normal);
    if (!spec_.footer.empty()) out << '\n' << spec_.footer;
    return out.str();
  }

  /// CLI11 shows the positional, a vector, as "IN ..."; only commands that take several say so.
  std::string make_option_opts(const CLI::Option* opt) const override {
    if (opt->get_positional() && spec_.max_positional <= 1) return {};
    return CLI::Formatter::make_option_opts(opt);
  }

 private:
  const CommandSpec& spec_;
};

CLI::Validator integer_check(long long low, long long high) {
  return CLI::Validator(
      [low, high](std::string& text) -> std::string {
        long long v = 0;
        const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
        if (r.ec != std::errc() || r.ptr != text.data() + text.size()) return "expects an integer, got '" + text + "'";
        if (v < low || v > high) {
          return "must be " +
                 (high == std::numeric_limits<long long>::max()
                      ? "at least " + std::to_string(low)
                      : "between " + std::to_string(low) + " and " + std::to_string(high)) +
                 ", got " + text;
        }
        return {};
      },
      "", "integer");
}

CLI::Validator positive_real_check() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0;
        const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
        if (r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(v)) {
          return "expects a number, got '" + text + "'";
        }
        if (!(v > 0.0)) return "must be positive, got " + text;
        return {};
      },
      "", "positive real");
}

CLI::Validator non_empty_check() {
  return CLI::Validator([](std::string& text) -> std::string { return text.empty() ? "needs a non-empty value" : ""; },
                        "", "non-empty");
}

}  // namespace

std::optional<long long> CommandLine::integer(const std::string& name) const {
  const auto v = value(name);
  if (!v) return std::nullopt;
  long long n = 0;
  std::from_chars(v->data(), v->data() + v->size(), n);
  return n;
}

std::optional<double> CommandLine::real(const std::string& name) const {
  const auto v = value(name);
  if (!v) return std::nullopt;
  double x = 0;
  std::from_chars(v->data(), v->data() + v->size(), x);
  return x;
}

std::string command_help(const CommandSpec& spec) {
  CLI::App app;
  std::vector<std::string> unused_positional;
  std::vector<std::string> unused_values(spec.options.size());
  app.formatter(std::make_shared<HelpFormatter>(spec));
  app.set_help_flag("-h,--help", "print this help");
  if (spec.max_positional > 0) {
    app.add_option(spec.positional_name, unused_positional, wrap(spec.positional_help, kHelpWidth - kNameColumn))
        ->type_name("");
  }
  for (std::size_t i = 0; i < spec.options.size(); ++i) {
    const OptionSpec& o = spec.options[i];
    const std::string help = wrap(o.help, kHelpWidth - kNameColumn);
    if (o.kind == ValueKind::Flag) {
      app.add_flag(o.name, help);
    } else {
      app.add_option(o.name, unused_values[i], help)->type_name(o.value_name.empty() ? "VALUE" : o.value_name);
    }
  }
  return app.help();
}

int print_usage_error(const CliEnvironment& env, const CommandSpec* spec, const std::string& message) {
  env.err << "immerse" << (spec != nullptr ? " " + spec->name : std::string()) << ": " << message << '\n';
  env.err << "usage: immerse " << (spec != nullptr ? spec->usage : std::string("[COMMAND] [ARGS...]")) << '\n';
  env.err << "run 'immerse " << (spec != nullptr ? spec->name + " " : std::string()) << "--help' for details\n";
  return kExitUsage;
}

std::optional<int> parse_command(const CliEnvironment& env, const CommandSpec& spec,
                                 const std::vector<std::string>& args, CommandLine& out) {
  CLI::App app;
  app.formatter(std::make_shared<HelpFormatter>(spec));
  app.set_help_flag("-h,--help", "print this help");
  std::vector<std::string> positional;
  app.add_option(spec.positional_name, positional, spec.positional_help)->expected(0, CLI::detail::expected_max_vector_size);
  std::vector<std::string> values(spec.options.size());
  std::vector<std::int64_t> flag_counts(spec.options.size(), 0);
  std::vector<CLI::Option*> options(spec.options.size(), nullptr);
  for (std::size_t i = 0; i < spec.options.size(); ++i) {
    const OptionSpec& o = spec.options[i];
    if (o.kind == ValueKind::Flag) {
      options[i] = app.add_flag(o.name, flag_counts[i], o.help)->disable_flag_override();
      continue;
    }
    // An option given twice is a usage error, not a silent overwrite.
    CLI::Option* option = app.add_option(o.name, values[i], o.help)->multi_option_policy(CLI::MultiOptionPolicy::Throw);
    option->check(non_empty_check());
    if (o.kind == ValueKind::Integer) option->check(integer_check(o.low, o.high));
    if (o.kind == ValueKind::Real) option->check(positive_real_check());
    options[i] = option;
  }
  try {
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 consumes from the back
    app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    env.out << command_help(spec);
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    return print_usage_error(env, &spec, e.what());
  }
  for (std::size_t i = 0; i < spec.options.size(); ++i) {
    const std::string& name = spec.options[i].name;
    if (options[i]->count() > 1) return print_usage_error(env, &spec, "option '" + name + "' given twice");
    if (options[i]->count() == 0) continue;
    if (spec.options[i].kind == ValueKind::Flag) {
      out.flags.insert(name);
    } else {
      out.values[name] = values[i];
    }
  }
  if (positional.size() < spec.min_positional) return print_usage_error(env, &spec, spec.missing_positional);
  if (positional.size() > spec.max_positional) {
    return print_usage_error(env, &spec, "unexpected argument '" + positional[spec.max_positional] + "'");
  }
  out.positional = std::move(positional);
  return std::nullopt;
}

}  // namespace imm::cli
