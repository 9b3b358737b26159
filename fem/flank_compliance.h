#pragma once
// Structural compliance of a gear body between points of its drive flanks, tabulated once from
// the FE model (ElasticBody) and interpolated for any mesh position.
//
// Nodes: for each tooth of the table, a grid of roll distances (active profile) times face
// positions (3D). Load case j: a unit normal force on a small patch of the flank at node j,
// pressing into the body. Reading i: the displacement along the inward flank normal of node i,
// at the reference depth d below the surface (where the FE solution has converged; the local part
// above it comes from the half-space, see MeshCycle). One factorisation, one substitution per
// load case. In 2D (plane strain) the body has unit thickness and the force is spread over the
// face width b, so the compliance is divided by b.
//
// Near its load the reading at depth d is dominated by the half-space response of the patch,
// which peaks over a width of about d; the rest of the structural compliance (tooth bending and
// shear, body) varies over the tooth's own length scales. With `split_half_space` (3D) the table
// keeps only the remainder R(i, j) = C_FE(i, j) - K_d(|x_i - x_j|) between points of one tooth,
// K_d the half-space displacement at depth d under the same patch (half_space::PatchLoadKernel),
// interpolates R, and adds K_d back at the exact distance between the reading and the load: the
// nodes can then be spaced by the smooth remainder, not by d. Distances are measured in the
// flank's developed surface (FlankSurface::developed_offset_mm; for a spur flank the involute arc
// length across the profile and z along the face).
#include "fem/elastic_body.h"
#include "contact/half_space.h"
#include "contact/mesh_cycle.h"
#include "meshing/flank_surface.h"
#include "meshing/gear_geometry.h"

#include <Eigen/Dense>

#include <memory>
#include <vector>

namespace hertzgear::fem
{
  using contact::FlankCompliance;
  using contact::FlankPoint;

  struct FlankTableSettings
  {
    std::vector<int> teeth{-1, 0, 1}; // relative to the body mesh's central tooth
    unsigned int     n_roll = 16;     // nodes across the active profile
    unsigned int     n_face = 5;      // nodes along the face width (3D)
    double           roll_min_mm = 0; // active profile as roll distances (r_b u)
    double           roll_max_mm = 0;
    double           reference_depth_mm = 0.5;
    double           patch_radius_mm    = 0.3;
    // Tabulate the FE compliance minus the half-space response of the patch at depth d, and add
    // that response back exactly (3D only; see above).
    bool split_half_space = false;
  };

  template <int dim>
  class TabulatedFlankCompliance : public FlankCompliance
  {
  public:
    // Computes the table (collective over the body's MPI communicator).
    TabulatedFlankCompliance(const BodyCompliance<dim> &body, const meshing::GearGeometry &gear,
                             int central_tooth, const FlankTableSettings &settings);

    // A table computed elsewhere (e.g. by the rank that holds the body): `raw` as matrix()
    // returned it there.
    TabulatedFlankCompliance(const Eigen::MatrixXd &raw, double youngs_modulus, double poisson_ratio,
                             const meshing::GearGeometry &gear, const FlankTableSettings &settings);

    double compliance_mm_per_N(const FlankPoint &reading, const FlankPoint &load) const override;
    double reference_depth_mm() const override { return settings.reference_depth_mm; }
    bool   covers_tooth(int tooth) const override;

    unsigned int n_load_cases() const { return static_cast<unsigned int>(table.cols()); }
    // The unit patch load at a flank point of this body, in the body's frame (centre on the
    // modified flank, direction the inward normal, radius the table's patch radius): the load
    // cases of the table, and the loads of the fields written per mesh position.
    typename ElasticBody<dim>::PatchLoad patch_load(const FlankPoint &p) const;
    // The raw FE table (reading x load), for tests (Maxwell-Betti reciprocity, convergence).
    const Eigen::MatrixXd &matrix() const { return table; }
    // The half-space response of a table patch at depth d at this distance [mm/N] (0 without
    // split_half_space), and the developed distance between two points of one flank [mm].
    double half_space_part(const FlankPoint &reading, const FlankPoint &load) const;
    double flank_distance_mm(const FlankPoint &a, const FlankPoint &b) const;
    // Node index of (tooth, roll node, face node).
    unsigned int node(unsigned int tooth_index, unsigned int i_roll, unsigned int i_face) const;

  private:
    const meshing::GearGeometry *geometry = nullptr; // must outlive the table
    meshing::FlankSurface        flank;              // of *geometry
    FlankTableSettings  settings;
    std::vector<double> roll_nodes, face_nodes;
    double              scale = 1; // 1/b in 2D
    Eigen::MatrixXd     table;
    // What the interpolation runs on: the table, or with split_half_space the table minus the
    // half-space part between nodes of one tooth.
    Eigen::MatrixXd     interpolated;
    std::unique_ptr<half_space::PatchLoadKernel> kernel; // with split_half_space
    std::vector<FlankPoint> node_points;

    // Roll and face nodes, their flank points, and the loads and readings of the table.
    void set_up_nodes(std::vector<PatchLoad<dim>> *loads, std::vector<PointReading<dim>> *readings);
    // The interpolated table (and the half-space kernel of the split) from `table`.
    void finish(double youngs_modulus, double poisson_ratio);

    // Interpolation weights of a flank point: up to 4 (node, weight) pairs; false if the tooth
    // is not in the table.
    bool weights(const FlankPoint &p, unsigned int nodes[4], double w[4]) const;
  };
} // namespace hertzgear::fem
