// `immerse render` (app/cli_render.cpp): its options, parsed into a render::RenderRequest.
#pragma once

#include "app/cli_common.h"

namespace imm::cli {

CommandSpec render_command_spec();
/// Runs `immerse render`. @return the exit code.
int command_render(Session& s, const CommandLine& cl);

}  // namespace imm::cli
