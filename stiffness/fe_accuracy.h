#pragma once
// What accuracy costs in the FE source (`hertzgear accuracy stiffness`, docs/accuracy-stiffness.md).
// Two ladders, each of at least three rungs:
//  - FE refinement levels (each level halves the element size in the contact band) at the input's
//    contact grid, with the reference depth held at the input's value on every level so that the
//    ladder refines one problem;
//  - contact-grid sizes (profile cells, and face cells in 3D, times the given factors) with the FE
//    bodies of the input's level, solved on the same factorised bodies.
// For mean k_total, STE peak-to-peak, k_mh and mean k_rest the three finest rungs of each ladder
// give the observed order and the Richardson-extrapolated value (common/richardson.h), and every
// rung its error against it.
#include "common/progress.h"
#include "common/richardson.h"
#include "stiffness/stiffness_source.h"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace hertzgear::stiffness
{
  struct AccuracyRung
  {
    std::string study; // fe_level | contact_grid
    int         level = 0, degree = 0, profile_cells = 0, face_cells = 0;
    double      h     = 0; // representative size: band element size [mm] or grid cell [mm]
    std::size_t dofs  = 0;
    double      wall_time_s = 0;
    double      k_total = 0, ste_pp_um = 0, k_mh = 0, k_rest = 0; // N/m, um, N/m^n, N/m
  };

  struct FeAccuracyStudy
  {
    double                    reference_depth_mm = 0;
    std::vector<AccuracyRung> fe_rungs, grid_rungs; // coarse to fine
    // Per quantity (mean_k_total_N_per_m, ste_peak_to_peak_um, k_mh_N_per_m_pow_n,
    // mean_k_rest_N_per_m): the extrapolation of each ladder.
    std::map<std::string, Extrapolation> fe_extrapolation, grid_extrapolation;

    // The rung's relative error against its ladder's extrapolation of `quantity` (NaN without one).
    double relative_error(const AccuracyRung &rung, const std::string &quantity) const;
    // One row per rung with the errors (accuracy_stiffness.csv).
    std::string csv() const;
    // accuracy_stiffness.json: the extrapolations, one row per rung with its errors and, under
    // "scene_default", the verdict on the rung of `scene_level` at the input's contact grid: is
    // it within 1 % of the extrapolated k_total and STE peak-to-peak on both ladders?
    nlohmann::json json(int scene_level) const;
    // That verdict and every extrapolation as progress lines.
    void report(int scene_level) const;
  };

  // Runs both ladders on the FE source. `levels` and `grid_factors` are sorted, distinct, at least
  // three each (ParameterError otherwise); meshes go to mesh_root/mesh_level<L>. The finest level
  // runs first, so that one too large for the machine stops the study before the others have run.
  FeAccuracyStudy run_fe_accuracy_study(const StiffnessInput &input, const std::vector<int> &levels,
                                        const std::vector<int> &grid_factors,
                                        const std::filesystem::path &mesh_root, PhaseTimer &timer);
} // namespace hertzgear::stiffness
