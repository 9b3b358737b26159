#pragma once
// `hertzgear validate hertz`: the Hertz validation study (docs/validation-hertz.md).
#include "app/command.h"

namespace hertzgear
{
  // Adds `validate hertz` under a `validate` group of `top` (created unless another command
  // file already made it).
  void add_validation_commands(CommandRegistry &registry, CLI::App &top);
} // namespace hertzgear
