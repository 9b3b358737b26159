#pragma once
// Scene -> the stiffness seam: the one place where the scene's stiffness, geometry, material and
// mesh values become the plain StiffnessInput of the stiffness library, and where its results
// become files (stiffness.csv, stiffness.json, fields/). The `stiffness` command and the pipeline's
// stiffness stage both run write_stiffness.
#include "app/run_directory.h"
#include "app/scene.h"
#include "common/errors.h"
#include "common/progress.h"
#include "stiffness/stiffness_source.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hertzgear
{
  // The stiffness library's input of a scene (mesh and field folders left empty).
  stiffness::StiffnessInput stiffness_input(const Scene &scene);

  // The scene's stiffness source from the registry (InputError for one this build lacks).
  const stiffness::StiffnessSource &stiffness_source(const Scene &scene);

  // Checks the scene's stiffness input as its source will (before any folder is made).
  void check_stiffness_input(const Scene &scene);

  // Computes the scene's stiffness (collective under MPI for the FE source) and writes
  // stiffness.csv and stiffness.json into `dir` on the writing process; with `write_fields` an
  // FE source also writes fields/, renamed into place after the tables. Meshes go to mesh/.
  // Before the first new file, the files of the previous table leave: stiffness.json, the map,
  // the contact pattern, fields/ and `previous_records` (the `stiffness` command's
  // used_parameters.prm and run.json, which it writes anew at its end).
  stiffness::StiffnessResult write_stiffness(const Scene &scene, const RunDirectory &dir,
                                             bool write_fields, PhaseTimer &timer,
                                             const std::vector<std::string> &previous_records = {});
} // namespace hertzgear
