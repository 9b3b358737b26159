#pragma once
// Scenes of the Hertz validation study (`hertzgear validate hertz`, data/scenes/validation/):
// one small parameter file (.prm) per canonical case, every key with its unit, range and help
// text (docs/validation-hertz.md). Kept apart from the gear scene (app/scene.h).
#include "fem/hertz_validation.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hertzgear
{
  struct ValidationScene
  {
    std::filesystem::path file;
    std::string           name; // the file's stem: the case name in the results
    std::string           description;

    // The case as the study reads it (name, kind, loads, the equivalent body against the rigid
    // plane and its block, reading depths, Kelly fraction); the counts below complete it.
    fem::HertzCaseInput input;

    // crowned-flank: the gear scene whose pair is checked at the pitch point.
    std::string           gear_scene_entry; // as written
    std::filesystem::path gear_scene;       // resolved against this file's folder

    int levels                      = 0;
    int ci_levels                   = 0;
    int initial_cells_per_semi_axis = 0;
    int max_active_set_iterations   = 0;

    std::string used_parameters_prm;
  };

  // Parses and checks a validation scene; `overrides` are "Section/key=value" strings. Throws
  // InputError naming the file, key and value for an unknown key or a value out of range.
  ValidationScene load_validation_scene(const std::filesystem::path &file,
                                        const std::vector<std::string> &overrides = {});
} // namespace hertzgear
