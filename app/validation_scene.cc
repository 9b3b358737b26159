// Validation scene declaration and parsing (deal.II ParameterHandler): every entry has its unit in
// the key name (or is a count or a dimensionless coefficient, said in the help), a range pattern
// and a help text.
#include "app/validation_scene.h"
#include "app/scene.h"

#include "common/errors.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/patterns.h>

#include <fstream>
#include <sstream>

namespace hertzgear
{
  namespace fs = std::filesystem;
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;

  namespace
  {
    void declare(ParameterHandler &prm, ValidationScene &v, std::string &depths)
    {
      prm.enter_subsection("Case");
      prm.add_parameter("kind", v.kind,
                        "Which canonical Hertz case this is: sphere (circular contact), ellipsoid "
                        "(elliptical contact, radii radius_x_mm and radius_y_mm), cylinder-2d "
                        "(plane strain line contact), finite-cylinder (a flat-ended roller of "
                        "length 2 half_width_y_mm, line contact in 3D), crowned-flank (the pitch "
                        "point of the pair in Gear flank/gear_scene).",
                        Patterns::Selection("sphere|ellipsoid|cylinder-2d|finite-cylinder|crowned-flank"));
      prm.add_parameter("description", v.description, "One line that says what the case checks.",
                        Patterns::Anything());
      prm.leave_subsection();

      prm.enter_subsection("Body");
      prm.add_parameter("youngs_modulus_MPa", v.youngs_modulus_MPa,
                        "Young's modulus of the one elastic body that stands for the pair against "
                        "a rigid plane, in MPa: E/(1 - nu^2) is the contact modulus E* of the pair. "
                        "Ignored for crowned-flank (taken from the gear scene).",
                        Patterns::Double(1e-6, 1e9));
      prm.add_parameter("poisson_ratio", v.poisson_ratio,
                        "Poisson's ratio of the equivalent body (dimensionless). Ignored for "
                        "crowned-flank.",
                        Patterns::Double(0.0, 0.49));
      prm.add_parameter("radius_x_mm", v.radius_x_mm,
                        "Effective radius of curvature across x in mm: the gap is "
                        "x^2/(2 radius_x_mm) + y^2/(2 radius_y_mm). Ignored for crowned-flank.",
                        Patterns::Double(1e-6, 1e6));
      prm.add_parameter("radius_y_mm", v.radius_y_mm,
                        "Effective radius of curvature across y in mm (ellipsoid; the sphere uses "
                        "radius_x_mm; line contacts have none).",
                        Patterns::Double(1e-6, 1e6));
      prm.add_parameter("load_N", v.load_N,
                        "Total normal force in N (3D cases). Ignored for crowned-flank (the static "
                        "mesh force of the gear scene).",
                        Patterns::Double(1e-9, 1e9));
      prm.add_parameter("load_per_length_N_per_mm", v.load_per_length_N_per_mm,
                        "Normal force per unit length in N/mm (cylinder-2d).",
                        Patterns::Double(1e-9, 1e9));
      prm.add_parameter("half_width_x_mm", v.half_width_x_mm,
                        "Half-width of the modelled block across x in mm (the model is the "
                        "symmetric half or quarter 0 <= x <= this). Must be large against the "
                        "contact: the Hertz answer is that of a half-space.",
                        Patterns::Double(1e-6, 1e6));
      prm.add_parameter("half_width_y_mm", v.half_width_y_mm,
                        "Half-width of the block across y in mm (3D). For finite-cylinder with "
                        "roller_half_length_mm = 0 the roller's half-length (the elastic body "
                        "ends there, flat); with a rigid roller (roller_half_length_mm > 0) the "
                        "half-width of the raceway under it; for crowned-flank it is taken as "
                        "half the face width.",
                        Patterns::Double(1e-6, 1e6));
      prm.add_parameter("depth_mm", v.depth_mm,
                        "Depth of the block in mm; its far face is displaced rigidly (the "
                        "approach).",
                        Patterns::Double(1e-6, 1e6));
      prm.add_parameter("roller_half_length_mm", v.roller_half_length_mm,
                        "finite-cylinder: 0 = the elastic body itself is the roller and ends "
                        "flat at half_width_y_mm (an elastic roller on a rigid plane); > 0 = a "
                        "rigid roller of this half-length in mm on the wider elastic block (a "
                        "roller on a wide raceway: the pressure peaks at the roller's ends).",
                        Patterns::Double(0.0, 1e6));
      prm.add_parameter("reading_depths_mm", depths,
                        "Depths in mm below the contact centre at which the compression between "
                        "the surface and that point is read (comma-separated; may be empty). For "
                        "crowned-flank the TCA's reference depth is added.",
                        Patterns::List(Patterns::Double(1e-9, 1e6), 0, 20, ","));
      prm.leave_subsection();

      prm.enter_subsection("Gear flank");
      prm.add_parameter("gear_scene", v.gear_scene_entry,
                        "crowned-flank: the gear scene (.prm or .json), relative to this file's "
                        "folder; its pair, materials and torque define the pitch-point contact.",
                        Patterns::Anything());
      prm.leave_subsection();

      prm.enter_subsection("Refinement");
      prm.add_parameter("levels", v.levels,
                        "Number of adaptive levels solved in the full study (count).",
                        Patterns::Integer(1, 12));
      prm.add_parameter("ci_levels", v.ci_levels,
                        "Number of levels of the coarse run (`--coarse`, the CI tests) (count).",
                        Patterns::Integer(1, 12));
      prm.add_parameter("initial_cells_per_semi_axis", v.initial_cells_per_semi_axis,
                        "Contact-face cells across the smaller Hertz semi-axis on the first level "
                        "(count; the mesh is zoomed to it before the first solve, each further "
                        "level halves the contact cells).",
                        Patterns::Integer(1, 64));
      prm.add_parameter("kelly_fraction", v.kelly_fraction,
                        "Fraction of all cells refined per level by Kelly's error estimator, on "
                        "top of the contact-zone cells (dimensionless).",
                        Patterns::Double(0.0, 0.5));
      prm.add_parameter("max_active_set_iterations", v.max_active_set_iterations,
                        "Iteration cap of the primal-dual active set per level (count); reaching "
                        "it or a cycling active set ends the run with exit code 3.",
                        Patterns::Integer(1, 1000));
      prm.leave_subsection();
    }

    void apply_override(ParameterHandler &prm, const std::string &text)
    {
      const auto eq    = text.find('=');
      const auto slash = text.substr(0, eq).rfind('/');
      HG_REQUIRE_INPUT(eq != std::string::npos && slash != std::string::npos,
                       "--set \"", text, "\": expected \"Section/key=value\"");
      const std::string section = text.substr(0, slash);
      const std::string key     = text.substr(slash + 1, eq - slash - 1);
      const std::string value   = text.substr(eq + 1);
      std::vector<std::string> parts;
      std::stringstream        ss(section);
      for (std::string p; std::getline(ss, p, '/');)
        parts.push_back(p);
      unsigned int entered = 0;
      try
        {
          for (const auto &p : parts)
            {
              prm.enter_subsection(p);
              ++entered;
            }
          prm.set(key, value);
        }
      catch (const dealii::ExceptionBase &e)
        {
          for (unsigned int i = 0; i < entered; ++i)
            prm.leave_subsection();
          throw InputError(msg("--set \"", text, "\": unknown key or value not allowed for ",
                               section, "/", key, " = \"", value, "\" (", user_message(e), ")"));
        }
      for (unsigned int i = 0; i < entered; ++i)
        prm.leave_subsection();
    }
  } // namespace

  ValidationScene load_validation_scene(const fs::path &file, const std::vector<std::string> &overrides)
  {
    ValidationScene  v;
    ParameterHandler prm;
    std::string      depths;
    v.kind                        = "sphere";
    v.youngs_modulus_MPa          = 103000;
    v.poisson_ratio               = 0.3;
    v.radius_x_mm                 = 10;
    v.radius_y_mm                 = 10;
    v.load_N                      = 100;
    v.load_per_length_N_per_mm    = 100;
    v.half_width_x_mm             = 20;
    v.half_width_y_mm             = 20;
    v.depth_mm                    = 20;
    v.levels                      = 4;
    v.ci_levels                   = 2;
    v.initial_cells_per_semi_axis = 2;
    v.kelly_fraction              = 0.1;
    v.max_active_set_iterations   = 40;
    declare(prm, v, depths);

    HG_REQUIRE_INPUT(fs::is_regular_file(file), "validation scene ", file.string(),
                     " does not exist or is not a file");
    HG_REQUIRE_INPUT(file.extension() == ".prm", "validation scene ", file.string(),
                     ": expected a .prm file");
    try
      {
        prm.parse_input(file.string(), "", false, false);
      }
    catch (const dealii::ExceptionBase &e)
      {
        throw InputError(msg("validation scene ", file.string(), ": ", user_message(e)));
      }
    for (const auto &o : overrides)
      apply_override(prm, o);

    v.file = fs::absolute(file);
    v.name = file.stem().string();
    v.reading_depths_mm.clear();
    for (const auto &d : Patterns::Tools::Convert<std::vector<double>>::to_value(
           depths, Patterns::List(Patterns::Double(1e-9, 1e6), 0, 20, ",")))
      v.reading_depths_mm.push_back(d);
    if (!v.gear_scene_entry.empty())
      v.gear_scene = fs::path(v.gear_scene_entry).is_relative() ?
                       v.file.parent_path() / v.gear_scene_entry :
                       fs::path(v.gear_scene_entry);

    // Cross-field checks.
    HG_REQUIRE_INPUT(v.kind != "crowned-flank" || !v.gear_scene_entry.empty(), file.string(),
                     ": Gear flank/gear_scene must name the gear scene of a crowned-flank case");
    for (const double d : v.reading_depths_mm)
      HG_REQUIRE_INPUT(d < v.depth_mm, file.string(), ": Body/reading_depths_mm contains ", d,
                       " mm, not inside the block of Body/depth_mm = ", v.depth_mm, " mm");
    HG_REQUIRE_INPUT(v.roller_half_length_mm < v.half_width_y_mm, file.string(),
                     ": Body/roller_half_length_mm = ", v.roller_half_length_mm,
                     " must be shorter than the block, Body/half_width_y_mm = ", v.half_width_y_mm);
    HG_REQUIRE_INPUT(v.ci_levels <= v.levels, file.string(), ": Refinement/ci_levels = ",
                     v.ci_levels, " exceeds Refinement/levels = ", v.levels);

    std::ostringstream used;
    prm.print_parameters(used, ParameterHandler::OutputStyle(ParameterHandler::ShortPRM));
    v.used_parameters_prm = used.str();
    return v;
  }
} // namespace hertzgear
