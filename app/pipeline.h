#pragma once
// The whole chain from one scene (`hertzgear run`): the stages the scene calls for, each cached
// in the run directory under a key of everything that produced it.
//
// Stages, in order (docs/architecture.md, "The pipeline and its cache"):
//   stiffness  Stiffness/source = fem: meshing + FE contact over the mesh cycle (gmsh, deal.II);
//              iso6336 / hertz-analytic / potential-energy: closed forms. Writes stiffness.json, stiffness.csv
//              (fem also mesh/). Not run for source = table or fourier.
//   dynamics   always: timeseries.csv, poincare.csv, spectrum.csv, force_penetration.csv,
//              impacts.csv, summary.json
//   sweep      when Sweep/enabled: sweep.csv, bifurcation.csv
//   report     when Output/report: report/index.html and its figures
//
// Cache: DIR/.hertzgear-cache/<stage>.json records the stage's key, the scene values it read
// and every artifact with its size and FNV-1a hash. It is written atomically after the
// artifacts, and removed before a stage runs, so an interrupted stage never leaves a manifest
// behind; a stage is reused only when its key matches and every artifact verifies.
#include "app/scene.h"
#include "common/stage_cache.h"
#include "meshing/pair_kinematics.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace hertzgear
{
  struct PipelineOptions
  {
    bool force         = false; // rerun every stage whatever the cache says
    int  sweep_threads = 0;     // 0: all hardware threads
  };

  // The stages a scene calls for, each with a one-line reason (printed by `run`).
  std::vector<std::pair<std::string, std::string>> planned_stages(const Scene &scene);

  // The scene values a stage reads ("stiffness", "dynamics", "sweep", "report").
  std::string stage_scene_values(const Scene &scene, const std::string &stage);

  // The one validation path of a run, before any folder or file is made (`check` runs it too):
  // the geometry of the pair (undercut, pointed tip, interference, contact ratio, ...), the input
  // of the stiffness source, and for a source the dynamics reads directly (table, fourier) the
  // whole dynamics set-up with its table. Throws InputError naming the key.
  // Also: the dynamics checks that need no table when the stiffness stage makes it, whether that
  // table holds what the effects need (the unloaded STE of Effects/ste_excitation = table), the
  // Response/* checks of a shooting sweep (Sweep/mode = shooting), and a warning line (not an
  // error) for an implausible load (warn_implausible_load).
  void check_run_inputs(const Scene &scene);

  // A warning line on stderr when Operating/torque_Nm gives the pair a nominal contact stress
  // sigma_H0 of ISO 6336-2 above stiffness::implausible_contact_stress_MPa (3000 MPa).
  void warn_implausible_load(const Scene &scene, const meshing::PairKinematics &pair);

  // Runs the pipeline of `scene` into `out` and returns what ran; run.json records it too. The
  // caller has made the checks (check_run_inputs) and holds `out` (CommandStart::begin). Under
  // mpirun every rank calls it: rank 0 runs the pipeline, the others their part of its
  // collective stages (and an empty list comes back to them).
  std::vector<StageOutcome> run_pipeline(const Scene &scene, const std::filesystem::path &out,
                                         const std::string &command_line,
                                         const PipelineOptions &options = {});
} // namespace hertzgear
