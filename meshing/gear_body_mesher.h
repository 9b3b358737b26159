#pragma once
// gmsh meshes of the gear bodies. This module owns every gmsh call of hertzgear.
//
// A body is a sector of N teeth (or the full gear) from the tip down to the bore, in its own
// frame: centre at the origin, tooth k (k = 0 .. N-1) centred at polar angle
// (k - central_tooth) 2 pi / z, central_tooth = N / 2, so the central tooth points along +x.
// 2D: all-quadrilateral mesh of the transverse section (plane strain). 3D: the 2D mesh extruded
// along the face width with hexahedral layers, z from -b/2 to +b/2 (z = 0 mid-face).
// The flank nodes are placed on the exact involute, then the profile modifications (lead
// crowning Delta(z) = beta (2z/b)^2 and tip relief) are applied as an exact mapping: an involute
// moved by Delta along its normal is the same involute turned by Delta / r_b, so each flank node
// turns by Delta / r_b about the gear axis, and interior nodes follow with a weight that falls
// linearly to 0 at the tooth centre line and below the root circle.
//
// Physical groups (deal.II reads the tags as boundary ids / material id):
//   tag 1            body           (surface in 2D, volume in 3D)
//   tag 10           bore
//   tag 11, 12       sector_cut_start (clockwise end), sector_cut_end   (sector only)
//   tag 13, 14       face_back (z = -b/2), face_front (z = +b/2)        (3D only)
//   tag 15, 16       root (root-circle arcs), tip_land
//   tag 100 + k      drive_flank_k  (+theta flank of tooth k: the loaded flank when the pinion
//                                    drives, see PairKinematics); at most 100 teeth per mesh,
//                                    so the ranges never overlap
//   tag 200 + k      coast_flank_k
//   tag 300 + k      drive_fillet_k
//   tag 400 + k      coast_fillet_k
#include "meshing/gear_geometry.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <string>

namespace hertzgear::meshing
{
  class PairKinematics;
  // Physical-group tags of the bodies (gmsh physical groups; deal.II's GridIn reads them as
  // boundary ids): the bore, the two radial cuts of a sector, and per tooth k of the mesh its
  // drive flank (100 + k), coast flank (200 + k), drive and coast fillets (300 + k, 400 + k).
  namespace physical_tag
  {
    constexpr int bore             = 10;
    constexpr int sector_cut_start = 11;
    constexpr int sector_cut_end   = 12;
    constexpr int root             = 15;
    constexpr int tip_land         = 16;
    constexpr int drive_flank      = 100;
    constexpr int coast_flank      = 200;
    constexpr int drive_fillet     = 300;
    constexpr int coast_fillet     = 400;
  } // namespace physical_tag

  struct MeshSettings
  {
    int  dimension          = 2;
    int  teeth_per_sector   = 5;  // >= z meshes the full gear (2D and 3D)
    int  face_width_layers  = 8;  // hexahedral layers at level 0; doubled per level
    int  refinement_level   = 1;  // each level halves every target size
    // Target element sizes at level 0, in modules: in the contact band of the flanks, at the
    // fillets, and away from the teeth.
    double band_size_modules   = 0.12;
    double fillet_size_modules = 0.2;
    double far_size_modules    = 0.6;
    // Depth of the refined band below the flank surface, in modules.
    double band_depth_modules = 0.3;
    bool   apply_modifications = true; // crowning (3D) and tip relief on the mesh nodes

    // Element size in the contact band [mm]: band_size_modules x module / 2^level. The one rule
    // for it: the mesher sizes the band by it, the FE source derives its reference depth from it.
    double band_element_size_mm(const double module_mm) const
    {
      return band_size_modules * module_mm * std::ldexp(1.0, -refinement_level);
    }
  };

  struct MeshQuality
  {
    int         dimension           = 0;
    std::size_t n_elements          = 0; // quadrilaterals (2D) or hexahedra (3D)
    std::size_t n_other_elements    = 0; // triangles/prisms (0 for a deal.II-ready mesh)
    std::size_t n_nodes             = 0;
    std::size_t n_boundary_elements = 0;
    double      min_scaled_jacobian = 0; // over all element corners, after the mapping
    double      contact_band_target_size_mm = 0;
    double      contact_band_max_edge_mm    = 0; // along the active flank (measured)
    double      contact_band_mean_edge_mm   = 0;
    int         n_teeth_meshed       = 0;
    int         central_tooth        = 0;
    bool        full_gear            = false;
    bool        subdivided           = false; // all-quad obtained by subdivision
    double      max_flank_modification_error_mm = 0; // mapping check on the flank nodes
    std::vector<std::string> physical_groups;
  };
  // A helical body's layers along the face must carry its twist: InputError naming
  // {face_width_layers} and the count needed otherwise (docs/geometry.md, "Meshes"; the mesher
  // checks it, and the FE stage before any work). Nothing for 2D or spur bodies.
  void require_layers_for_twist(const GearGeometry &gear, const MeshSettings &settings,
                                double active_start_radius_mm);
  // The {face_width_layers} that rule needs (1 for 2D or spur bodies).
  unsigned int layers_needed_for_twist(const GearGeometry &gear, const MeshSettings &settings,
                                       double active_start_radius_mm);
  // Both bodies of a pair, each from the start of its active profile: the one that needs more
  // layers is checked first, so that a refusal names the count that carries both.
  void require_layers_for_twist(const PairKinematics &pair, const MeshSettings &settings);

  // Its record in mesh_quality.json (units in the keys).
  nlohmann::json mesh_quality_json(const MeshQuality &quality);

  // Initialises gmsh on construction and finalises it on destruction; one instance at a time.
  class GearBodyMesher
  {
  public:
    GearBodyMesher();
    ~GearBodyMesher();
    GearBodyMesher(const GearBodyMesher &) = delete;
    GearBodyMesher &operator=(const GearBodyMesher &) = delete;

    // Meshes one body and writes it to `msh_file` (MSH 2.2 ASCII, the format deal.II's GridIn
    // reads) through `produce_file_atomically`. `active_start_radius_mm` is the start of the
    // active profile (contact band from there to the tip).
    MeshQuality mesh(const GearGeometry &gear, const MeshSettings &settings,
                     double active_start_radius_mm, const std::filesystem::path &msh_file);

    static int central_tooth(int teeth_per_sector) { return teeth_per_sector / 2; }
  };
} // namespace hertzgear::meshing
