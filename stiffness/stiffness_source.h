#pragma once
// The stiffness seam: every way hertzgear obtains the mesh stiffness of a pair is a
// StiffnessSource, computed from one plain input (StiffnessInput, filled by app/ from the scene)
// into one result (StiffnessResult: the dynamics' table, a row per mesh position, notes). The
// registry (stiffness/registry.h) lists the sources; the scene's source selection and its help
// text (and so docs/scenes.md), the pipeline and the `stiffness` command all read it
// (docs/architecture.md, "The stiffness seam").
//
// Units: the input in the units gear engineers use (mm, N m, MPa), the table in SI (N/m, N/m^n,
// m), the rows with the unit in each name.
#include "common/fourier_series.h"
#include "common/material.h"
#include "common/progress.h"
#include "table/stiffness_table.h"
#include "meshing/gear_parameters.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hertzgear::stiffness
{
  // The finite-element contact analysis (source fem).
  struct FeSettings
  {
    int         dimension                  = 3; // 2: plane strain, 3: solid
    int         level                      = 1; // refinement level of the contact band
    int         degree                     = 1; // Q1 or Q2
    // full-gear: each body is the full gear clamped at its bore, from one tooth sector with
    // cyclic symmetry (fem::CyclicGearBody); sector: a meshed sector of teeth_per_sector teeth
    // clamped at its cuts and bore (>= the gear's teeth: the full gear meshed as one body).
    std::string body_model                 = "full-gear";
    int         teeth_per_sector           = 5;
    int         face_width_layers          = 8; // 3D: hexahedral layers at level 0
    int         contact_grid_profile_cells = 24;
    int         contact_grid_face_cells    = 16;
    std::string contact_grid_face_extent   = "load"; // load | face-width (3D crowned spur)
    int         contact_max_iterations     = 100;
    bool        decoupled_teeth            = false; // teeth do not feel each other's loads
    double      reference_depth_mm         = 0;     // 0: 3 x the band element size
    int         table_face_nodes           = 0;     // 0: automatic
    int         table_roll_nodes           = 0;     // 0: automatic
    bool        table_half_space_split     = true;  // 3D
    std::string linear_solver              = "direct"; // direct | amg-cg
    double      linear_solver_tolerance    = 1e-10;
    // Where the gmsh bodies go (created); empty fields_dir: no fields of the loaded bodies.
    std::filesystem::path mesh_dir;
    std::filesystem::path fields_dir;
    // Further contact grids (profile cells, face cells) solved with the same FE bodies.
    std::vector<std::pair<int, int>> extra_contact_grids;
  };

  struct StiffnessInput
  {
    meshing::PairParameters pair;
    Material                pinion_material, gear_material;
    double                  torque_Nm           = 0; // on the pinion
    int                     positions_per_cycle = 16;
    int                     harmonics           = 4;
    double                  hertz_exponent      = 1.5; // n of F = k_h delta^n
    // source table: the stiffness.json to read; source fourier: the table the unloaded STE comes
    // from when unloaded_ste_from_table.
    std::filesystem::path table_file;
    bool                  unloaded_ste_from_table = false;
    // source fourier: the series themselves (SI).
    FourierSeries k_rest_N_per_m, k_hertz_N_per_m_pow_n;
    FeSettings    fe;
    // Load and design map (source fem): further contact cycles on the same bodies, on the axes
    // torque (percent of torque_Nm), lead crowning (each variant on both gears), mesh
    // misalignment and the pinion's helix slope deviation f_Hb; an empty axis keeps the pair's
    // own value. Which combinations run: stiffness/load_map.h.
    std::vector<double> torque_map_percent;
    std::vector<double> crowning_map_mm;
    std::vector<double> misalignment_map_mm;
    std::vector<double> helix_slope_map_mm;
    // false: every torque with every crowning, then each misalignment and each f_Hb at torque_Nm
    // with every crowning; true: every combination of the four axes (a tolerance study).
    bool map_product = false;
    // The load ladder of the FE force law (source fem; docs/dynamics.md "The FE force law"): the
    // mesh cycle again at each of these loads [% of torque_Nm], increasing, the top >= 100, on the
    // same bodies, into the table's load_ladder. Empty: no ladder.
    std::vector<double> load_ladder_percent;
    bool has_map() const
    {
      return !torque_map_percent.empty() || !crowning_map_mm.empty() || !misalignment_map_mm.empty() ||
             !helix_slope_map_mm.empty();
    }
  };

  // One mesh position: the columns of stiffness.csv. What a source does not compute is empty.
  struct PositionRow
  {
    double                mesh_phase = 0; // in cycles
    double                ste_um     = 0;
    double                k_total_N_per_m = 0;
    double                k_hertz_N_per_m_pow_n = 0;
    double                k_rest_N_per_m  = 0;
    std::optional<int>    pairs_in_contact;
    std::optional<double> load_share_1, load_share_2; // pair 1 entered at phase 0, pair 2 is ahead
    double                hertz_penetration_um = 0;
    double                contact_a_mm = 0, contact_b_mm = 0, peak_pressure_MPa = 0;
    // Sources that solve the contact (fem): the tangent stiffness dF/d(approach), the
    // force-weighted centre of the contact along the face (0 = mid-face) and whether the loaded
    // contact reaches a face end or a tip (edge contact).
    std::optional<double> k_total_tangent_N_per_m;
    std::optional<double> contact_centre_z_mm;
    std::optional<bool>   face_end_contact, tip_contact;
  };

  // A loaded cell of the contact grid on the pinion flank (contact patterns).
  struct ContactPatternCell
  {
    int    position = 0, pair = 0;
    double pinion_roll_mm = 0, z_mm = 0, pressure_MPa = 0;
  };

  // One case of the load and design map: its torque, lead crowning, mesh misalignment and helix
  // slope deviations, and the rows of its contact cycle.
  struct MapCase
  {
    double                          torque_Nm = 0, torque_percent = 0, load_N = 0;
    double                          pinion_crowning_mm = 0, gear_crowning_mm = 0;
    double                          mesh_misalignment_mm = 0;
    double                          pinion_helix_slope_deviation_mm = 0, gear_helix_slope_deviation_mm = 0;
    std::vector<PositionRow>        rows;
    std::vector<ContactPatternCell> pattern;
    double                          contact_time_s = 0;
  };

  struct StiffnessResult
  {
    table::StiffnessTable table; // SI: the contract with the dynamics
    std::vector<PositionRow> rows;  // empty for a source that reads a table (table, fourier)
    FourierSeries            k_total_N_per_m, ste_m; // fits of the rows
    double                   mean_k_rest_N_per_m = 0;
    double                   load_N              = 0;
    double                   contact_time_s      = 0; // FE source: the contact solves over the cycle
    int                      harmonics           = 0;
    // Source-specific record for stiffness.json, under `notes_key` ("fe", "closed_form_model").
    std::string    notes_key;
    nlohmann::json notes = nlohmann::json::object();
    // fem with FeSettings::fields_dir: the fields, complete, under a temporary name
    // (commit_fields renames them); further contact grids (FeSettings::extra_contact_grids).
    std::filesystem::path        fields_partial_dir;
    std::vector<StiffnessResult> extra_grids;
    // The scene's own cycle as contact pattern, and the load and design map (StiffnessInput).
    std::vector<ContactPatternCell> pattern;
    std::vector<MapCase>            map;
    // Where the pinion's flank lies (contact pattern axes): active profile and face width [mm].
    double pinion_active_roll_min_mm = 0, pinion_active_roll_max_mm = 0, face_width_mm = 0;
  };

  // The fits and means of the rows (k_total, STE, mean k_rest) with `harmonics` harmonics.
  void summarise_rows(StiffnessResult &result);

  class StiffnessSource
  {
  public:
    StiffnessSource(std::string name, std::string summary)
      : source_name(std::move(name)), source_summary(std::move(summary))
    {}
    virtual ~StiffnessSource() = default;
    // The name a scene selects it by, and one line on what it computes.
    const std::string &name() const { return source_name; }
    const std::string &summary() const { return source_summary; }
    // Computed by the stiffness stage into stiffness.json (true), or read directly by the
    // dynamics without a stage (false: a table file, the scene's own coefficients).
    virtual bool is_stage() const { return true; }
    // Meshes and solves FE bodies (writes meshes and fields; needs the FE build).
    virtual bool uses_fe() const { return false; }
    // Whether this build can compute it (fem needs -DHERTZGEAR_WITH_FEM=ON).
    virtual bool available() const { return true; }
    // Whether a stage source's table holds the unloaded STE (unloaded_ste_m) that
    // Effects/ste_excitation = table needs (for a source read directly, its table file says).
    virtual bool tabulates_unloaded_ste() const { return false; }
    // Checks the input before any work or file (throws ParameterError naming the field; other
    // fields a message names are written {field}).
    virtual void check(const StiffnessInput &input) const = 0;
    // The table, with a phase of `timer` per step. Collective under MPI for an FE source (every
    // rank returns the same result; only rank 0 prints progress).
    virtual StiffnessResult compute(const StiffnessInput &input, PhaseTimer &timer) const = 0;

  private:
    std::string source_name, source_summary;
  };

  // A source the dynamics reads directly (a table file, the scene's own coefficients): no
  // stiffness stage, nothing to check before it is read.
  class DirectSource : public StiffnessSource
  {
  public:
    using StiffnessSource::StiffnessSource;
    bool is_stage() const override { return false; }
    void check(const StiffnessInput &) const override {}
  };

  // The one instance of a source class, for its registration function (registry.cc):
  //   const StiffnessSource &iso6336_source() { return the_source<Iso6336Source>(); }
  template <class Source>
  const StiffnessSource &the_source()
  {
    static const Source source;
    return source;
  }
} // namespace hertzgear::stiffness
