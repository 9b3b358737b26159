#pragma once
// The FE stiffness stage: scene -> gmsh bodies -> deal.II elastic bodies -> flank compliance
// tables -> loaded TCA over the mesh cycle -> stiffness table (the contract with dynamics).
#include "app/scene.h"
#include "common/progress.h"
#include "dynamics/stiffness_table.h"
#include "fem/mesh_cycle.h"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace hertzgear
{
  struct StiffnessStageResult
  {
    fem::MeshCycleResult      cycle;
    dynamics::StiffnessTable  table;    // SI, for the dynamics
    nlohmann::json            metadata; // FE settings, DOFs, wall times
    double                    load_N = 0;
  };

  // Runs the stage; meshes go to `mesh_dir` (created). Collective under MPI.
  StiffnessStageResult run_stiffness_stage(const Scene &scene, const std::filesystem::path &mesh_dir,
                                           PhaseTimer &timer);

  // stiffness.csv: a row per mesh position, units in the column names.
  std::string stiffness_csv(const StiffnessStageResult &result, double hertz_exponent);
  // stiffness.json: the dynamics' stiffness table plus means, k_total and STE series, metadata.
  nlohmann::json stiffness_json(const StiffnessStageResult &result, const Scene &scene);
} // namespace hertzgear
