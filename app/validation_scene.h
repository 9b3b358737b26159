#pragma once
// Scenes of the Hertz validation study (`hertzgear validate hertz`, data/scenes/validation/):
// one small parameter file (.prm) per canonical case, every key with its unit, range and help
// text (docs/validation-hertz.md). Kept apart from the gear scene (app/scene.h).
#include <filesystem>
#include <string>
#include <vector>

namespace hertzgear
{
  struct ValidationScene
  {
    std::filesystem::path file;
    std::string           name; // the file's stem: the case name in the results
    std::string           kind; // sphere | ellipsoid | cylinder-2d | finite-cylinder | crowned-flank
    std::string           description;

    // The equivalent body against the rigid plane (E/(1 - nu^2) = E* of the pair).
    double youngs_modulus_MPa       = 0;
    double poisson_ratio            = 0;
    double radius_x_mm              = 0;
    double radius_y_mm              = 0;
    double load_N                   = 0; // 3D cases
    double load_per_length_N_per_mm = 0; // cylinder-2d
    double half_width_x_mm          = 0;
    double half_width_y_mm          = 0;
    double depth_mm                 = 0;
    double roller_half_length_mm    = 0; // finite-cylinder: 0 = the elastic body ends
    std::vector<double> reading_depths_mm;

    // crowned-flank: the gear scene whose pair is checked at the pitch point.
    std::string           gear_scene_entry; // as written
    std::filesystem::path gear_scene;       // resolved against this file's folder

    int    levels                      = 0;
    int    ci_levels                   = 0;
    int    initial_cells_per_semi_axis = 0;
    double kelly_fraction              = 0;
    int    max_active_set_iterations   = 0;

    std::string used_parameters_prm;
  };

  // Parses and checks a validation scene; `overrides` are "Section/key=value" strings. Throws
  // InputError naming the file, key and value for an unknown key or a value out of range.
  ValidationScene load_validation_scene(const std::filesystem::path &file,
                                        const std::vector<std::string> &overrides = {});
} // namespace hertzgear
