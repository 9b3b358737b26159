#pragma once
// The one material type of hertzgear: an isotropic linear elastic solid, in the units of the scene
// (MPa, kg/m^3). The FE bodies, the Hertz and half-space closed forms, the stiffness sources and
// the inertias of the dynamics all take it.
namespace hertzgear
{
  struct Material
  {
    double youngs_modulus_MPa = 206000.0;
    double poisson_ratio      = 0.3;
    double density_kg_per_m3  = 7850.0;
  };
} // namespace hertzgear
