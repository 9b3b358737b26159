// Validation scene declaration and parsing (common/parameter_file): every entry has its unit in
// the key name (or is a count or a dimensionless coefficient, said in the help), a range pattern
// and a help text.
#include "app/validation_scene.h"

#include "common/errors.h"
#include "common/parameter_file.h"

namespace hertzgear
{
  namespace fs = std::filesystem;
  namespace Patterns = patterns;

  namespace
  {
    void declare(ParameterFile &prm, ValidationScene &v)
    {
      prm.enter_subsection("Case");
      prm.add("kind", v.input.kind,
              Patterns::Selection("sphere|ellipsoid|cylinder-2d|finite-cylinder|crowned-flank"),
              "Which canonical Hertz case this is: sphere (circular contact), ellipsoid "
              "(elliptical contact, radii radius_x_mm and radius_y_mm), cylinder-2d "
              "(plane strain line contact), finite-cylinder (a flat-ended roller of "
              "length 2 half_width_y_mm, line contact in 3D), crowned-flank (the pitch "
              "point of the pair in Gear flank/gear_scene).");
      prm.add("description", v.description, Patterns::Anything(),
              "One line that says what the case checks.");
      prm.leave_subsection();

      prm.enter_subsection("Body");
      prm.add("youngs_modulus_MPa", v.input.fe.youngs_modulus_MPa, Patterns::Double(1e-6, 1e9),
              "Young's modulus of the one elastic body that stands for the pair against "
              "a rigid plane, in MPa: E/(1 - nu^2) is the contact modulus E* of the pair. "
              "Ignored for crowned-flank (taken from the gear scene).");
      prm.add("poisson_ratio", v.input.fe.poisson_ratio, Patterns::Double(0.0, 0.49),
              "Poisson's ratio of the equivalent body (dimensionless). Ignored for "
              "crowned-flank.");
      prm.add("radius_x_mm", v.input.fe.radius_x_mm, Patterns::Double(1e-6, 1e6),
              "Effective radius of curvature across x in mm: the gap is "
              "x^2/(2 radius_x_mm) + y^2/(2 radius_y_mm). Ignored for crowned-flank.");
      prm.add("radius_y_mm", v.input.fe.radius_y_mm, Patterns::Double(1e-6, 1e6),
              "Effective radius of curvature across y in mm (ellipsoid; the sphere uses "
              "radius_x_mm; line contacts have none).");
      prm.add("load_N", v.input.load_N, Patterns::Double(1e-9, 1e9),
              "Total normal force in N (3D cases). Ignored for crowned-flank (the static "
              "mesh force of the gear scene).");
      prm.add("load_per_length_N_per_mm", v.input.load_per_length_N_per_mm,
              Patterns::Double(1e-9, 1e9),
              "Normal force per unit length in N/mm (cylinder-2d).");
      prm.add("half_width_x_mm", v.input.fe.half_width_x_mm, Patterns::Double(1e-6, 1e6),
              "Half-width of the modelled block across x in mm (the model is the "
              "symmetric half or quarter 0 <= x <= this). Must be large against the "
              "contact: the Hertz answer is that of a half-space.");
      prm.add("half_width_y_mm", v.input.fe.half_width_y_mm, Patterns::Double(1e-6, 1e6),
              "Half-width of the block across y in mm (3D). For finite-cylinder with "
              "roller_half_length_mm = 0 the roller's half-length (the elastic body "
              "ends there, flat); with a rigid roller (roller_half_length_mm > 0) the "
              "half-width of the raceway under it; for crowned-flank it is taken as "
              "half the face width.");
      prm.add("depth_mm", v.input.fe.depth_mm, Patterns::Double(1e-6, 1e6),
              "Depth of the block in mm; its far face is displaced rigidly (the "
              "approach).");
      prm.add("roller_half_length_mm", v.input.roller_half_length_mm, Patterns::Double(0.0, 1e6),
              "finite-cylinder: 0 = the elastic body itself is the roller and ends "
              "flat at half_width_y_mm (an elastic roller on a rigid plane); > 0 = a "
              "rigid roller of this half-length in mm on the wider elastic block (a "
              "roller on a wide raceway: the pressure peaks at the roller's ends).");
      prm.add("reading_depths_mm", v.input.fe.reading_depths_mm,
              Patterns::List(Patterns::Double(1e-9, 1e6), 0, 20, ","),
              "Depths in mm below the contact centre at which the compression between "
              "the surface and that point is read (comma-separated; may be empty). For "
              "crowned-flank the TCA's reference depth is added.");
      prm.leave_subsection();

      prm.enter_subsection("Gear flank");
      prm.add("gear_scene", v.gear_scene_entry, Patterns::Anything(),
              "crowned-flank: the gear scene (.prm or .json), relative to this file's "
              "folder; its pair, materials and torque define the pitch-point contact.");
      prm.leave_subsection();

      prm.enter_subsection("Refinement");
      prm.add("levels", v.levels, Patterns::Integer(1, 12),
              "Number of adaptive levels solved in the full study (count).");
      prm.add("ci_levels", v.ci_levels, Patterns::Integer(1, 12),
              "Number of levels of the coarse run (`--coarse`, the CI tests) (count).");
      prm.add("initial_cells_per_semi_axis", v.initial_cells_per_semi_axis,
              Patterns::Integer(1, 64),
              "Contact-face cells across the smaller Hertz semi-axis on the first level "
              "(count; the mesh is zoomed to it before the first solve, each further "
              "level halves the contact cells).");
      prm.add("kelly_fraction", v.input.fe.kelly_fraction, Patterns::Double(0.0, 0.5),
              "Fraction of all cells refined per level by Kelly's error estimator, on "
              "top of the contact-zone cells (dimensionless).");
      prm.add("max_active_set_iterations", v.max_active_set_iterations,
              Patterns::Integer(1, 1000),
              "Iteration cap of the primal-dual active set per level (count); reaching "
              "it or a cycling active set ends the run with exit code 3.");
      prm.leave_subsection();
    }

    void apply_override(ParameterFile &prm, const std::string &text)
    {
      const auto eq    = text.find('=');
      const auto slash = text.substr(0, eq).rfind('/');
      HG_REQUIRE_INPUT(eq != std::string::npos && slash != std::string::npos,
                       "--set \"", text, "\": expected \"Section/key=value\"");
      const std::string section = text.substr(0, slash);
      const std::string key     = text.substr(slash + 1, eq - slash - 1);
      const std::string value   = text.substr(eq + 1);
      try
        {
          prm.set(section, key, value);
        }
      catch (const ParameterFileError &e)
        {
          // e names the entry and the value, or says that there is no such entry
          throw InputError(msg("--set \"", text, "\": ", e.what()));
        }
    }
  } // namespace

  ValidationScene load_validation_scene(const fs::path &file, const std::vector<std::string> &overrides)
  {
    ValidationScene  v;
    ParameterFile    prm;
    auto            &in = v.input;
    in.kind             = "sphere";
    in.load_N = in.load_per_length_N_per_mm = 100;
    in.fe.youngs_modulus_MPa                = 103000;
    in.fe.poisson_ratio                     = 0.3;
    in.fe.radius_x_mm = in.fe.radius_y_mm = 10;
    in.fe.half_width_x_mm = in.fe.half_width_y_mm = in.fe.depth_mm = 20;
    in.fe.kelly_fraction                    = 0.1;
    v.levels                                = 4;
    v.ci_levels                             = 2;
    v.initial_cells_per_semi_axis           = 2;
    v.max_active_set_iterations             = 40;
    declare(prm, v);

    HG_REQUIRE_INPUT(fs::is_regular_file(file), "validation scene ", file.string(),
                     " does not exist or is not a file");
    HG_REQUIRE_INPUT(file.extension() == ".prm", "validation scene ", file.string(),
                     ": expected a .prm file");
    try
      {
        prm.parse_file(file);
      }
    catch (const ParameterFileError &e)
      {
        // e names the file and the line
        throw InputError(msg("validation scene ", e.what()));
      }
    for (const auto &o : overrides)
      apply_override(prm, o);

    v.file = fs::absolute(file);
    v.name = in.name = file.stem().string();
    if (!v.gear_scene_entry.empty())
      v.gear_scene = fs::path(v.gear_scene_entry).is_relative() ?
                       v.file.parent_path() / v.gear_scene_entry :
                       fs::path(v.gear_scene_entry);

    // Cross-field checks.
    HG_REQUIRE_INPUT(in.kind != "crowned-flank" || !v.gear_scene_entry.empty(), file.string(),
                     ": Gear flank/gear_scene must name the gear scene of a crowned-flank case");
    for (const double d : in.fe.reading_depths_mm)
      HG_REQUIRE_INPUT(d < in.fe.depth_mm, file.string(), ": Body/reading_depths_mm contains ", d,
                       " mm, not inside the block of Body/depth_mm = ", in.fe.depth_mm, " mm");
    HG_REQUIRE_INPUT(in.roller_half_length_mm < in.fe.half_width_y_mm, file.string(),
                     ": Body/roller_half_length_mm = ", in.roller_half_length_mm,
                     " must be shorter than the block, Body/half_width_y_mm = ",
                     in.fe.half_width_y_mm);
    HG_REQUIRE_INPUT(v.ci_levels <= v.levels, file.string(), ": Refinement/ci_levels = ",
                     v.ci_levels, " exceeds Refinement/levels = ", v.levels);

    v.used_parameters_prm =
      prm.print(ParameterFile::Style::short_form, ParameterFile::Order::alphabetical);
    return v;
  }
} // namespace hertzgear
