#pragma once
// The Hertz validation study (`hertzgear validate hertz`, docs/validation-hertz.md): per canonical
// case (sphere, ellipsoid, 2D and finite cylinders, the paper's crowned flank at its pitch point)
// the Hertz closed forms and the TCA's hybrid local compliance, set against resolved FE contact
// (fem/resolved_contact.h) level by level; results, observed rates and pressure profiles as CSV.
#include "common/material.h"
#include "contact/mesh_cycle.h"
#include "fem/resolved_contact.h"
#include "meshing/gear_parameters.h"

#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace hertzgear::fem
{
  // One case in plain values.
  struct HertzCaseInput
  {
    std::string             name; // in the results
    std::string             kind; // sphere | ellipsoid | cylinder-2d | finite-cylinder | crowned-flank
    ResolvedContactSettings fe;   // the equivalent body, its block and its refinement
    double load_N                   = 0; // 3D cases
    double load_per_length_N_per_mm = 0; // cylinder-2d
    double roller_half_length_mm    = 0; // finite-cylinder: 0 = the elastic body ends
    // crowned-flank: the gear pair checked at its pitch point with the TCA's grid and depth.
    struct GearPair
    {
      meshing::PairParameters    pair;
      Material                   pinion_material, gear_material;
      double                     torque_Nm = 0;
      contact::MeshCycleSettings grid;
      double                     reference_depth_mm = 0;
      std::string                source; // where the pair comes from, for messages
    } gear;
  };

  // A case ready to solve: FE settings and the closed forms to compare with.
  struct HertzCase
  {
    int                     dim = 3;
    ResolvedContactSettings fe;
    double                  contact_modulus = 0;
    double a_x = 0, a_y = 0, p0 = 0, approach = 0; // a_y = 0: line contact
    bool   line               = false;
    double load_per_length    = 0; // line contacts
    double roller_half_length = 0; // finite-cylinder
    // Per reading depth: the closed-form compression between surface and depth, and its name.
    std::vector<std::pair<std::string, double>> depth_references;
    // Rows computed once per level from the FE compression at a depth: (quantity, closed form,
    // index of the reading depth).
    struct Extra
    {
      std::string  quantity;
      double       closed_form;
      unsigned int depth_index;
    };
    std::vector<Extra> extras;
    std::string        notes;
  };

  // The closed forms of a case (InputError for a case the closed forms cannot serve).
  HertzCase make_hertz_case(const HertzCaseInput &input);

  // The study's results over cases and levels.
  class HertzValidationStudy
  {
  public:
    // Solves one case level by level (resolved FE contact in 2D or 3D) and adds its rows and the
    // pressure profiles of its finest level; `say` receives a line on the case (its closed forms
    // and block) and one per level (its errors against them).
    void run_case(const HertzCaseInput &input, const std::function<void(const std::string &)> &say);
    // The rows of one solved level, and the pressure profiles of a case's finest level.
    void add_level(const std::string &name, const HertzCase &c, const ResolvedContactLevel &l);
    void add_profiles(const std::string &name, const HertzCase &c, const ResolvedContactLevel &l);
    // hertz_validation.csv, hertz_rates.csv (observed rates between successive levels against the
    // DOFs and the contact cell size), pressure_profiles.csv.
    std::string results_csv() const;
    std::string rates_csv() const;
    std::string profiles_csv() const { return profiles.str(); }
    // The lines of rates_csv() of the quantities the acceptance is about: semi-axes, half-width,
    // peak pressure.
    std::vector<std::string> acceptance_rates() const;

  private:
    struct Row
    {
      std::string        case_name, quantity;
      double             closed_form = 0, fe = 0;
      unsigned int       level       = 0;
      unsigned long long dofs        = 0;
      double             wall_time_s = 0;
      double             contact_cell_mm = 0;
    };
    std::vector<Row>   rows;
    std::ostringstream profiles{"case,axis,coordinate_mm,fe_pressure_MPa,hertz_pressure_MPa\n",
                                std::ios_base::ate};
  };
} // namespace hertzgear::fem
