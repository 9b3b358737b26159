#include "app/stiffness_setup.h"

#include "app/meshing_setup.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/processes.h"
#include "stiffness/registry.h"
#include "stiffness/table_file.h"
#include "stiffness/table_writer.h"


namespace hertzgear
{
  namespace fs = std::filesystem;

  namespace
  {
    // Renames a folder written under a temporary name (fields/, mesh/) into place (the old folder
    // is gone by then), so that the folder is never half there.
    void commit_folder(const fs::path &partial, const fs::path &folder)
    {
      if (!partial.empty() && fs::exists(partial))
        fs::rename(partial, folder);
    }
  } // namespace

  stiffness::StiffnessInput stiffness_input(const Scene &scene)
  {
    const auto               &st = scene.stiffness;
    stiffness::StiffnessInput in;
    in.pair                    = pair_parameters(scene);
    in.pinion_material         = scene.pinion_material;
    in.gear_material           = scene.gear_material;
    in.torque_Nm               = scene.operating.torque_Nm;
    in.positions_per_cycle     = st.positions_per_cycle;
    in.harmonics               = st.harmonics;
    in.hertz_exponent          = st.hertz_exponent;
    in.table_file              = st.table_file;
    in.unloaded_ste_from_table = scene.effects.ste_excitation == "table";
    const auto &f              = st.fourier;
    in.k_rest_N_per_m =
      fourier_series(f.k_rest_mean_N_per_m, f.k_rest_amplitudes_N_per_m, f.k_rest_phases_rad);
    in.k_hertz_N_per_m_pow_n = fourier_series(
      f.k_hertz_mean_N_per_m_pow_n, f.k_hertz_amplitudes_N_per_m_pow_n, f.k_hertz_phases_rad);
    auto &fe                      = in.fe;
    fe.dimension                  = st.fe_dimension;
    fe.level                      = st.fe_level;
    fe.degree                     = st.fe_degree;
    fe.body_model                 = scene.mesh.body_model;
    fe.teeth_per_sector           = scene.mesh.teeth_per_sector;
    fe.face_width_layers          = scene.mesh.face_width_layers;
    fe.contact_grid_profile_cells = st.contact_grid_profile_points;
    fe.contact_grid_face_cells    = st.contact_grid_face_points;
    fe.contact_grid_face_extent   = st.contact_grid_face_extent;
    fe.contact_max_iterations     = st.contact_max_iterations;
    fe.decoupled_teeth            = st.tooth_coupling == "decoupled";
    fe.reference_depth_mm         = st.reference_depth_mm;
    fe.table_face_nodes           = st.table_face_nodes;
    fe.table_roll_nodes           = st.table_roll_nodes;
    fe.table_half_space_split     = st.table_half_space_split;
    fe.linear_solver              = st.linear_solver;
    fe.linear_solver_tolerance    = st.linear_solver_tolerance;
    in.torque_map_percent         = st.map_torque_percent;
    // The ladder only when the dynamics will use it (and only the FE analysis makes one).
    if (makes_load_ladder(scene))
      in.load_ladder_percent = st.load_ladder_percent;
    for (const double beta : st.map_crowning_um)
      in.crowning_map_mm.push_back(beta * 1e-3);
    for (const double f : st.map_mesh_misalignment_um)
      in.misalignment_map_mm.push_back(f * 1e-3);
    for (const double f : st.map_helix_slope_deviation_um)
      in.helix_slope_map_mm.push_back(f * 1e-3);
    in.map_product = st.map_combination == "product";
    return in;
  }

  const stiffness::StiffnessSource &stiffness_source(const Scene &scene)
  {
    return stiffness::find_source(scene.stiffness.source);
  }

  void check_stiffness_input(const Scene &scene)
  {
    const auto &source = stiffness_source(scene);
    const auto  input  = stiffness_input(scene);
    if (input.has_map() && !source.uses_fe())
      throw ParameterError("Stiffness/Map", msg("a load and design map needs the contact analysis of "
                                                "Stiffness/source = fem, not ", source.name()));
    source.check(input);
  }

  stiffness::StiffnessResult write_stiffness(const Scene &scene, const RunDirectory &dir,
                                             const bool write_fields, PhaseTimer &timer,
                                             const std::vector<std::string> &previous_records)
  {
    const auto &source = stiffness_source(scene);
    auto        input  = stiffness_input(scene);
    // The meshes are made in a hidden folder and arrive with their table (below): a run stopped
    // during the analysis leaves the old table with its own meshes. One name for every process
    // (rank 0's), since all of them read the meshes.
    const fs::path mesh_dir = dir.path() / "mesh";
    if (source.uses_fe())
      input.fe.mesh_dir = processes::all_gather(temporary_path_for(mesh_dir).string()).front();
    if (write_fields && source.uses_fe())
      input.fe.fields_dir = dir.path() / "fields";
    stiffness::StiffnessResult result;
    try
      {
        result = source.compute(input, timer);
      }
    catch (...)
      {
        // A stopped analysis leaves no hidden mesh folder behind (the old table keeps its own).
        // Whichever rank stops first removes it: under mpirun it ends every rank (MPI_Abort),
        // so rank 0 may not get here.
        if (source.uses_fe())
          {
            std::error_code ec;
            fs::remove_all(input.fe.mesh_dir, ec);
          }
        throw;
      }
    if (processes::is_root())
      {
        PhaseTimer::Scope scope(timer, "write stiffness");
        // What belongs to the previous table leaves before the new one arrives, the table
        // (stiffness.json) first: an interruption at any point leaves the old set without some of
        // its files, or the new set without some of its files, never a mix of the two (no new
        // table beside old fields or meshes, no new stiffness.csv beside an old stiffness.json).
        std::vector<std::string> previous = {"stiffness.json"};
        previous.insert(previous.end(), previous_records.begin(), previous_records.end());
        for (const auto *file : {"stiffness_map.csv", "contact_pattern.csv", "fields", "mesh"})
          previous.emplace_back(file);
        for (const auto &file : previous)
          fs::remove_all(dir.path() / file);
        nlohmann::json    json = stiffness::stiffness_json(result);
        json.update(provenance(scene));
        json["pair"] = stiffness::pair_record(input.pair); // ties the table to its pair
        dir.write_text("stiffness.csv", stiffness::stiffness_csv(result));
        // The map and contact pattern of this table, when it has them.
        if (!result.map.empty())
          dir.write_text("stiffness_map.csv", stiffness::stiffness_map_csv(result));
        if (!result.pattern.empty())
          dir.write_text("contact_pattern.csv", stiffness::contact_pattern_csv(result));
        dir.write_json("stiffness.json", json); // the table, last of the tables
        // The meshes and fields folders appear complete, after the tables, or not at all.
        if (source.uses_fe())
          commit_folder(input.fe.mesh_dir, mesh_dir);
        commit_folder(result.fields_partial_dir, input.fe.fields_dir);
      }
    return result;
  }
} // namespace hertzgear
