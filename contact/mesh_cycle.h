#pragma once
// Loaded tooth contact analysis (TCA) over one mesh cycle with the hybrid finite-element /
// half-space method (docs/theory-tca.md):
//
//   C_ij = sum_bodies [ C_FE(i*, j) + C_B(i, j) - C_B(i*, j) ]
//
// C_FE is the structural compliance of a body between flank points, read at a reference depth d
// below the surface (i* = the point at depth d under i); C_B is the Boussinesq-Love half-space
// compliance, whose surface-minus-depth difference restores the local (Hertzian) deformation the
// FE mesh cannot resolve. Per mesh position the discrete contact problem (gap from the unloaded
// kinematics, pressures >= 0, load balance) is solved exactly; the Hertzian (local) part of the
// approach is separated from the total, and k_h, k_total, k_rest, STE and load sharing are fitted
// by Fourier series over the cycle.
//
// Spur and helical pairs: a helical pair's contact band follows its inclined contact lines face
// column by face column; the contact problem is solved normal to the flanks (gaps, compliances,
// pressures on the flank's area), while the load given and every force, approach, STE and
// stiffness reported are measured along the transverse line of action, as for a spur pair
// (docs/theory-tca.md, "Helical pairs on the contact grid").
//
// Units inside: mm, N, MPa (so compliances are mm/N and pressures MPa).
#include "contact/contact_solver.h"
#include "common/fourier_series.h"
#include "common/material.h"
#include "meshing/flank_point.h"
#include "meshing/pair_kinematics.h"

#include <Eigen/Dense>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace hertzgear::contact
{
  // A material point of a drive flank (meshing/flank_point.h); offsets between two of them in
  // the developed flank: meshing::FlankSurface::developed_offset_mm.
  using meshing::FlankPoint;

  // Structural compliance of one body between its flank points: displacement [mm] of `reading`,
  // taken at the reference depth below the flank and along the inward flank normal, per unit
  // normal force [N] pressing on the flank at `load`. Positive: the flank recedes.
  class FlankCompliance
  {
  public:
    virtual ~FlankCompliance() = default;
    virtual double compliance_mm_per_N(const FlankPoint &reading, const FlankPoint &load) const = 0;
    // The depth d [mm] below the surface at which readings are taken.
    virtual double reference_depth_mm() const = 0;
    // Whether the compliance of this tooth's flank is known (a tabulated body covers the teeth
    // of its sector that can be loaded).
    virtual bool covers_tooth(int /*tooth*/) const { return true; }
  };

  // An infinitely stiff body (no structural compliance): with it, the TCA keeps only the local
  // half-space part, and with a very stiff material it returns the unloaded kinematics.
  class RigidFlankCompliance : public FlankCompliance
  {
  public:
    explicit RigidFlankCompliance(double reference_depth_mm) : depth(reference_depth_mm) {}
    double compliance_mm_per_N(const FlankPoint &, const FlankPoint &) const override { return 0; }
    double reference_depth_mm() const override { return depth; }

  private:
    double depth;
  };

  // A body whose teeth do not feel each other's loads: the compliance of `body` between points
  // of the same tooth, zero between different teeth (Stiffness/tooth_coupling = decoupled).
  class DecoupledFlankCompliance : public FlankCompliance
  {
  public:
    explicit DecoupledFlankCompliance(const FlankCompliance &body) : base(body) {}
    double compliance_mm_per_N(const FlankPoint &reading, const FlankPoint &load) const override
    {
      return reading.tooth == load.tooth ? base.compliance_mm_per_N(reading, load) : 0.0;
    }
    double reference_depth_mm() const override { return base.reference_depth_mm(); }
    bool   covers_tooth(const int tooth) const override { return base.covers_tooth(tooth); }

  private:
    const FlankCompliance &base;
  };

  struct MeshCycleSettings
  {
    unsigned int n_positions   = 16;  // S, uniformly over one mesh cycle
    unsigned int n_harmonics   = 4;   // of the Fourier fits
    unsigned int profile_cells = 24;  // across the contact band, per pair
    unsigned int face_cells    = 16;  // along the face extent, per pair (1 for plane strain)
    // Face extent of the contact grid (3D): a band that follows the load for the point contact
    // of a crowned spur pair (load), face_band_semi_axes times the Hertz semi-axis along the face
    // of the whole load on one pair, around the smallest unloaded gap along the face, clipped to
    // the face and enlarged where the contact would reach its inner edge (MeshCycle::face_band,
    // docs/theory-tca.md, "Compliance of the contact grid"), or the whole face width. Uncrowned
    // and helical pairs use the whole face either way.
    enum class FaceExtent
    {
      face_width,
      load
    };
    FaceExtent face_extent         = FaceExtent::load;
    double     face_band_semi_axes = 2.0; // c of the load band's half-length c b_Hertz(F)
    // Half-width of the contact band across the profile [mm]; 0 = automatic: three times the
    // Hertz half-width of the whole load on one pair at the pitch point.
    double band_half_width_mm = 0;
    double hertz_exponent     = 1.5;  // n of F = k_h delta^n
    double tangent_step       = 0.02; // relative load step of the tangent stiffness
    // Whether each position also takes its tangent stiffness (two further solves, or two further
    // grids on a load band); without it k_total_tangent and k_rest are 0. The FE force law's
    // load ladder needs only the approaches.
    bool tangent = true;
    bool   plane_strain       = false;
    // Pairs whose contact line lies up to this many base pitches outside the path of contact are
    // included (extended contact near the tips under load); their gap decides whether they touch.
    double extended_contact_pitches = 0.0;
    unsigned int max_contact_iterations = 100; // of the active-set solver, per solve
  };

  struct PairState
  {
    int    pair            = 0;
    double roll_mm         = 0; // pinion roll distance of the contact line at mid-face (z = 0)
    double force_N         = 0; // the pair's part of the load, along the transverse line of action
    double load_share      = 0;
    // Local (half-space minus depth) part of the approach, along the transverse line of action.
    double hertz_penetration_mm = 0;
    double contact_a_mm    = 0; // semi-axis across the profile (on the flank)
    double contact_b_mm    = 0; // semi-axis along the face width (on the flank)
    double peak_pressure_MPa = 0;

    // Every member, for the transfer of solved positions between processes (boost::serialization
    // archives; the FE stage shares a cycle's positions out over its ranks).
    template <class Archive>
    void serialize(Archive &ar, const unsigned int /*version*/)
    {
      ar &pair &roll_mm &force_N &load_share &hertz_penetration_mm &contact_a_mm &contact_b_mm
        &peak_pressure_MPa;
    }
  };

  struct PositionResult
  {
    double                 mesh_phase = 0; // in cycles
    double                 ste_mm     = 0; // loaded STE along the (transverse) line of action
    double                 unloaded_ste_mm = 0; // of the discrete flanks, no load
    double                 approach_mm     = 0; // elastic approach (loaded - unloaded STE)
    double                 k_total_secant_N_per_mm  = 0;
    double                 k_total_tangent_N_per_mm = 0;
    double                 hertz_penetration_mm = 0; // load-weighted over the pairs
    double                 k_hertz              = 0; // N/mm^n: F = k_h delta_h^n
    double                 k_rest_N_per_mm      = 0; // 1/k_rest = 1/k_tangent - 1/k_h,tangent
    // Where the load sits: its force-weighted centre along the face (0 = mid-face), whether a
    // loaded cell lies in the outermost face column of the grid (3D; the contact reaches a face
    // end) and whether one borders the end of a flank across the profile (a tip or the start of
    // the active profile of either gear: edge contact at a tip).
    double                 contact_centre_z_mm  = 0;
    bool                   face_end_contact     = false;
    // Face extent of the contact grid that was solved [mm] (the whole face, or the load band
    // after any enlargement, FaceExtent::load).
    double                 face_band_min_mm = 0, face_band_max_mm = 0;
    unsigned int           face_band_enlargements = 0;
    bool                   tip_contact          = false;
    std::vector<PairState> pairs;
    unsigned int           n_cells = 0, n_active = 0, n_iterations = 0;

    // The contact grid and its solution, for fields and pressure maps: per cell the pair, the
    // surface coordinate across the profile [mm], the face position [mm] and the pressure [MPa].
    std::vector<int>    cell_pair;
    std::vector<double> cell_u_mm, cell_z_mm, cell_pressure_MPa;
    // Where each cell sits on the flanks (roll distances of the pinion and the gear point; the
    // pinion tooth is +pair, the gear tooth -pair) and its area on the flank [mm^2] (du dz /
    // cos(beta_b)); the cell pressures are normal to the flank, sum p A = load / cos(beta_b).
    std::vector<double> cell_pinion_roll_mm, cell_gear_roll_mm, cell_area_mm2;

    // Every member, as PairState::serialize.
    template <class Archive>
    void serialize(Archive &ar, const unsigned int /*version*/)
    {
      ar &mesh_phase &ste_mm &unloaded_ste_mm &approach_mm &k_total_secant_N_per_mm
        &k_total_tangent_N_per_mm &hertz_penetration_mm &k_hertz &k_rest_N_per_mm
          &contact_centre_z_mm &face_end_contact &face_band_min_mm &face_band_max_mm
            &face_band_enlargements &tip_contact &pairs &n_cells &n_active &n_iterations &cell_pair
              &cell_u_mm &cell_z_mm &cell_pressure_MPa &cell_pinion_roll_mm &cell_gear_roll_mm
                &cell_area_mm2;
    }
  };

  struct MeshCycleResult
  {
    std::vector<PositionResult> positions;
    FourierSeries               k_hertz, k_total, ste_mm;
    double                      mean_k_rest_N_per_mm = 0;
    double                      band_half_width_mm   = 0;
    double                      face_band_min_mm = 0, face_band_max_mm = 0; // before enlargement
    bool                        face_band_follows_load = false; // MeshCycle::face_band_follows_load
    double                      load_N               = 0;
  };

  class MeshCycle
  {
  public:
    MeshCycle(const meshing::PairKinematics &kinematics, const Material &pinion_material,
              const Material &gear_material, const FlankCompliance &pinion_compliance,
              const FlankCompliance &gear_compliance, const MeshCycleSettings &settings);

    // Load along the transverse line of action [N] (F_0 = T_1 / r_b1, as the stiffness stage
    // passes it, spur or helical); the flanks carry the normal force F_0 / cos(beta_b).
    // `progress` is called after every position with its index and result.
    MeshCycleResult
    run(double load_N,
        const std::function<void(unsigned int, const PositionResult &)> &progress = {}) const;

    // One mesh position: run() solves position i at phase_of_position(i).
    PositionResult solve_position(double mesh_phase, double load_N) const;
    double         phase_of_position(unsigned int i) const;
    // The cycle at `load_N` from its solved positions (positions[i] at phase_of_position(i)):
    // the Fourier fits and the grid's extent. run() is solve_position at every position, then
    // assemble; a caller that shares the positions out over processes solves them where it likes
    // and assembles the same result from them.
    MeshCycleResult assemble(double load_N, std::vector<PositionResult> positions) const;
    // The cells of the contact grid of position `mesh_phase` at `load_N` before any enlargement
    // of its face band (PositionResult::n_cells when none is needed): what a position's solve
    // costs grows with it, so that a caller sharing positions out over processes can weigh them.
    unsigned int grid_cells(double mesh_phase, double load_N) const;

    // Half-width of the contact band across the profile [mm] at this load.
    double band_half_width(double load_N) const;

    // Face extent of the contact grid before any enlargement [mm]: the whole face width, or for
    // FaceExtent::load and the crowned (point) contact of a spur pair the band [z_c - c b, z_c + c b] clipped to
    // the face, z_c where the unloaded gap along the face is smallest and b the Hertz semi-axis
    // along the face of the whole load on one pair at the pitch point.
    struct FaceBand
    {
      double min_mm = 0, max_mm = 0;
    };
    FaceBand face_band(double load_N) const;
    // Whether the grid's face extent follows the load (FaceExtent::load and the crowned contact
    // of a spur pair in 3D); the tangent stiffness is then the slope of the approach over the load, each load on
    // its own grid.
    bool face_band_follows_load() const;

  private:
    struct Grid;
    // Whether a contact line at this pinion roll [mm] lies on the path of contact A..E extended
    // by extended_contact_pitches base pitches at either end.
    bool on_extended_path(double roll_mm) const;
    // The grid's extent, cell sizes and tooth pairs (no cells yet); build_grid adds the cells.
    Grid grid_frame(double mesh_phase, double band_half_width_mm, const FaceBand &face) const;
    Grid build_grid(double mesh_phase, double band_half_width_mm, const FaceBand &face) const;
    ContactSolution  solve_contact(const Grid &grid, double load_N) const;

    const meshing::PairKinematics &kinematics;
    Material                   materials[2];
    const FlankCompliance         *compliances[2];
    MeshCycleSettings              settings;
  };
} // namespace hertzgear::contact
