// The registry of procedural inputs (`immerse generate`), one for every dimension: generators
// by name, their integer parameters and one parser for the arguments ("3", "name=value").
// dim2/generators.h registers the curves, dim3/generators3.h the surfaces; both are a
// GeneratorRegistry<Output> of their output type.
//
// Adding a generator: one `add` call in the dimension's registry file
// (dim2/generator_registry.cpp, dim3/generator_registry.cpp) with its name, a one-line
// description, its parameters (default and inclusive range; `even` for even-only values) and
// the known answer as the `--list` line states it. What the answer is in numbers (immersions,
// cells, arcs, ...) belongs to the tests, which check it (tests/support).
//
// CGAL-free.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace imm {

/// One integer parameter of a generator.
struct GeneratorParameter {
  std::string name;
  std::string description;
  long default_value = 0;
  long min_value = 0;
  long max_value = 0;
  bool even = false;  ///< only even values are accepted
};

/// What `--list` says of a generator.
struct GeneratorInfo {
  std::string name;         ///< "fig6", "helix", ...
  std::string description;  ///< one line
  std::vector<GeneratorParameter> parameters;
  /// The known answer in words ("1 immersion", "inversion (exit 3)", "Catalan(K) immersions").
  std::string expected_note;
};

/// A registry entry in the shape the command line prints it (`immerse generate --list`): name,
/// parameter synopsis ("[LOOPS=4] [SIDES=20]") and the description with the known answer.
struct GeneratorSummary {
  std::string name;
  std::string params;
  std::string description;
};

/// The summary line of one generator.
GeneratorSummary summarize(const GeneratorInfo& info);

/// Parses `arguments` against the generator's parameters: each is a plain integer (the next
/// parameter not yet set) or "name=value"; missing ones take their defaults.
/// @param[out] values  one value per parameter, in order
/// @return an error message (no such parameter, too many, not an integer, out of range, odd
///         where even is asked), empty when the arguments are good
std::string parse_generator_arguments(const GeneratorInfo& info,
                                      const std::vector<std::string>& arguments,
                                      std::vector<long>& values);

/// The message for a name no registry knows.
std::string unknown_generator_error(std::string_view name);

/// Generators of one output type (dim2::CurveSet, dim3::Surface), in the order `--list` prints
/// them. Built once (a function-local static in the dimension's registry file) and then only
/// read, so `find` pointers stay valid.
template <class Output>
class GeneratorRegistry {
 public:
  /// Makes the output from the parsed parameter values (one per parameter, in order).
  using Maker = std::function<Output(const std::vector<long>&)>;

  /// Registers a generator with parameters.
  GeneratorRegistry& add(GeneratorInfo info, Maker make) {
    infos_.push_back(std::move(info));
    makers_.push_back(std::move(make));
    return *this;
  }

  /// Registers a generator without parameters.
  GeneratorRegistry& add_fixed(std::string name, std::string description, std::string note,
                               Output (*make)()) {
    return add({std::move(name), std::move(description), {}, std::move(note)},
               [make](const std::vector<long>&) { return make(); });
  }

  [[nodiscard]] const std::vector<GeneratorInfo>& infos() const { return infos_; }

  /// @return the generator with this name, or nullptr.
  [[nodiscard]] const GeneratorInfo* find(std::string_view name) const {
    const std::size_t i = index_of(name);
    return i < infos_.size() ? &infos_[i] : nullptr;
  }

  [[nodiscard]] std::vector<GeneratorSummary> summaries() const {
    std::vector<GeneratorSummary> out;
    out.reserve(infos_.size());
    for (const GeneratorInfo& info : infos_) out.push_back(summarize(info));
    return out;
  }

  /// Parses the arguments of the named generator (see parse_generator_arguments).
  /// @return an error message, empty on success
  std::string parse(std::string_view name, const std::vector<std::string>& arguments,
                    std::vector<long>& values) const {
    const GeneratorInfo* info = find(name);
    if (info == nullptr) return unknown_generator_error(name);
    return parse_generator_arguments(*info, arguments, values);
  }

  /// Runs the named generator. Never throws for bad arguments.
  /// @param[out] output  the generated input, left alone on an error
  /// @return an error message (unknown name, bad arguments), empty on success
  std::string generate(std::string_view name, const std::vector<std::string>& arguments,
                       Output& output) const {
    std::vector<long> values;
    std::string error = parse(name, arguments, values);
    if (error.empty()) output = makers_[index_of(name)](values);
    return error;
  }

 private:
  [[nodiscard]] std::size_t index_of(std::string_view name) const {
    for (std::size_t i = 0; i < infos_.size(); ++i) {
      if (infos_[i].name == name) return i;
    }
    return infos_.size();
  }

  std::vector<GeneratorInfo> infos_;
  std::vector<Maker> makers_;
};

}  // namespace imm
