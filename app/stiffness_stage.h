#pragma once
// The FE stiffness stage: scene -> gmsh bodies -> deal.II elastic bodies -> flank compliance
// tables -> loaded TCA over the mesh cycle -> stiffness table (the contract with dynamics).
//
// MPI: collective over MPI_COMM_WORLD. Rank 0 meshes; every rank reads the meshes into a
// parallel::shared triangulation, so assembly, the solver setup (MUMPS factorisation or AMG
// hierarchy, Stiffness/linear_solver) and the solves are distributed; the compliance tables and
// the contact solves are replicated, so every rank returns the same result. Only rank 0 should write result files.
#include "app/scene.h"
#include "common/progress.h"
#include "dynamics/stiffness_table.h"
#include "fem/mesh_cycle.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <utility>
#include <vector>

namespace hertzgear
{
  struct StiffnessStageOptions
  {
    // Write the fields of the loaded bodies (displacement, von Mises stress, contact pressure)
    // per mesh position into this folder; empty: no fields. The folder is produced under a
    // temporary name and renamed only when complete (StiffnessStageResult::fields_partial_dir
    // until commit_stiffness_fields renames it).
    std::filesystem::path fields_dir;
    // Further contact grids (profile cells, face cells) solved over the cycle with the same FE
    // bodies (the contact-grid ladder of `hertzgear accuracy stiffness`).
    std::vector<std::pair<int, int>> extra_contact_grids;
  };

  struct StiffnessStageResult
  {
    fem::MeshCycleResult      cycle;
    dynamics::StiffnessTable  table;    // SI, for the dynamics
    nlohmann::json            metadata; // FE settings, DOFs, wall times
    double                    load_N = 0;
    std::vector<fem::MeshCycleResult> extra_cycles; // one per options.extra_contact_grids
    std::filesystem::path     fields_partial_dir;    // complete fields under a temporary name
  };

  // Runs the stage; meshes go to `mesh_dir` (created). Collective under MPI.
  StiffnessStageResult run_stiffness_stage(const Scene &scene, const std::filesystem::path &mesh_dir,
                                           PhaseTimer &timer);
  StiffnessStageResult run_stiffness_stage(const Scene &scene, const std::filesystem::path &mesh_dir,
                                           PhaseTimer &timer, const StiffnessStageOptions &options);

  // Renames the fields written by run_stiffness_stage to options.fields_dir (replacing an older
  // folder of that name). Collective; rank 0 renames. Call after the other artifacts are written.
  void commit_stiffness_fields(const StiffnessStageResult &result,
                               const std::filesystem::path &fields_dir);

  // stiffness.csv: a row per mesh position, units in the column names.
  std::string stiffness_csv(const StiffnessStageResult &result, double hertz_exponent);
  // stiffness.json: the dynamics' stiffness table plus means, k_total and STE series, metadata.
  nlohmann::json stiffness_json(const StiffnessStageResult &result, const Scene &scene);

  // The depth d [mm] at which the FE compliance is read (Stiffness/reference_depth_mm, or 3 x the
  // element size in the contact band at the scene's level); load patches have radius d/2.
  double reference_depth_mm(const Scene &scene);

  // True on MPI rank 0 of MPI_COMM_WORLD (the rank that writes files and progress).
  bool is_root_rank();
} // namespace hertzgear
