// `immerse deform` and `immerse weights` (app/cli_deform.cpp): the deformation library on the
// unglued mesh of an input, or on its glued baseline.
#pragma once

#include <string>

#include "app/cli_common.h"

namespace imm::cli {

CommandSpec deform_command_spec();
CommandSpec weights_command_spec();
/// Runs `immerse deform` (command == "deform") or `immerse weights`. @return the exit code.
int command_deform_or_weights(Session& s, const CommandLine& cl, const std::string& command);

}  // namespace imm::cli
