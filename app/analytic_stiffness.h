#pragma once
// Stiffness tables from closed forms, for Stiffness/source = iso6336, hertz-analytic and
// potential-energy (no gmsh, no deal.II). The model is described in docs/stiffness-closed-form.md:
//
//  - structural (rest) stiffness of one tooth pair, k_r1 = 1 / (1/(c' b) - 1/k_line): ISO 6336-1
//    method B single stiffness c' over the face width b, minus the line-contact Hertzian part
//    that c' contains (Palmgren's steel line contact at the static load, tangent stiffness);
//  - Hertzian stiffness of one pair at its load F_i: elliptical Hertz contact (the paper's eq. 5)
//    when the flanks are crowned (profile curvature from the radii of curvature at the contact
//    point, lead curvature 8 beta / b^2 of both gears), Palmgren line contact otherwise;
//    k_h,i = F_i / delta_i^n with the scene's exponent n;
//  - iso6336: constant series, k_rest = k_r1 (0.75 eps_alpha + 0.25) (ISO's c_gamma_alpha / c'
//    ratio), k_h = eps_alpha k_h1 at the pitch point;
//  - hertz-analytic: at S mesh positions, the pairs in contact share the static load so that
//    their approaches agree (each pair: k_r1 in series with its Hertzian contact at its own
//    curvature), k_h = sum of the pairs' k_h,i, k_rest = (number of pairs) k_r1, STE = common
//    approach, k_total = F / STE;
//  - potential-energy: as hertz-analytic, with the structural stiffness of each pair at its
//    contact point from both teeth's bending, shear, axial and fillet-foundation compliance
//    (meshing/potential_energy.h) and Yang & Lin's linear line contact on uncrowned flanks;
//    1/k_rest = 1/k_total,tangent - 1/k_h,tangent as in the FE stage.
#include "app/scene.h"

#include <nlohmann/json.hpp>

#include <string>

namespace hertzgear
{
  struct AnalyticStiffness
  {
    nlohmann::json json; // stiffness.json: the table (schema hertzgear-stiffness-table/1) + means
    std::string    csv;  // stiffness.csv: a row per mesh position (same columns as the FE stage)
  };

  // iso6336, hertz-analytic or potential-energy: a table without meshing or FE.
  bool is_closed_form_source(const std::string &source);

  // Throws InputError when Stiffness/source is not a closed-form source, or when the closed
  // forms give no positive structural stiffness (the values are named).
  AnalyticStiffness analytic_stiffness(const Scene &scene);
} // namespace hertzgear
