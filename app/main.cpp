// `immerse`: see app/cli.h. The only program linking every dimension.
#include <unistd.h>

#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "app/cli.h"
#include "core/diagnostics.h"

int main(int argc, char** argv) {
  std::vector<std::string> args;
  for (int i = 1; i < argc; ++i) args.emplace_back(argv[i]);
  const imm::CliEnvironment env{std::cout, std::cerr, ::isatty(STDERR_FILENO) == 1};
  // run_cli already maps library exceptions to exit code 1; this is the last line of defence
  // (e.g. an allocation failure while printing the error itself).
  try {
    return imm::run_cli(args, env);
  } catch (const imm::InvariantError& e) {
    std::cerr << "immerse: internal error (a bug, please report it): " << e.what() << '\n';
  } catch (const std::exception& e) {
    std::cerr << "immerse: internal error: " << e.what() << '\n';
  } catch (...) {
    std::cerr << "immerse: internal error: unknown exception\n";
  }
  return imm::kExitInternalError;
}
