#pragma once
// The FE source (Stiffness/source = fem): loaded tooth contact analysis over the mesh cycle with
// the hybrid finite-element / half-space method (docs/theory-tca.md). Its phases, in order:
//   mesh                gmsh bodies of both gears (rank 0), meshing/
//   bodies              deal.II elastic bodies clamped at the bore, one factorisation each, fem/
//   compliance tables   unit patch loads on the flank nodes, read at the reference depth, fem/
//   contact             the contact problem at every mesh position, contact/
//   fit                 the dynamics' table: Fourier fits in SI
//   output              fields of the loaded bodies per position (optional)
// MPI: collective over MPI_COMM_WORLD. Rank 0 meshes; every rank reads the meshes into a
// parallel::shared triangulation, so assembly, the solver set-up and the solves are distributed;
// the compliance tables and the contact solves are replicated, so every rank returns the same
// result. Only rank 0 writes result files and prints progress.
#include "contact/mesh_cycle.h"
#include "meshing/gear_body_mesher.h"
#include "stiffness/stiffness_source.h"

namespace hertzgear::stiffness
{
  // The body mesh settings of the FE source.
  meshing::MeshSettings fe_mesh_settings(const FeSettings &fe);

  // The reference depth d [mm] at which the FE compliance is read: FeSettings::reference_depth_mm,
  // or 3 x the element size in the contact band (meshing::MeshSettings::band_element_size_mm).
  // Load patches have radius d/2.
  double fe_reference_depth_mm(const FeSettings &fe, double module_mm);

  // The contact grid of the FE source for a scene's input: cells across the profile and along
  // the face, the face extent, the Hertz exponent and the contact solver's iteration cap (3D;
  // the FE stage sets positions, harmonics and plane strain itself).
  contact::MeshCycleSettings fe_contact_grid_settings(const StiffnessInput &input);
} // namespace hertzgear::stiffness
