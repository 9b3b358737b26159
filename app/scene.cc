// Scene declaration, parsing and checks. Every entry has a unit in its name (or is a count or a
// dimensionless coefficient, said in its help text), a range pattern and a help text.
#include "app/scene.h"

#include "common/errors.h"
#include "app/meshing_setup.h"
#include "common/hash.h"
#include "common/input_file.h"
#include "common/parameter_file.h"
#include "common/shown_text.h"
#include "meshing/gear_geometry.h"
#include "stiffness/registry.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

namespace hertzgear
{
  namespace fs = std::filesystem;
  namespace Patterns = patterns;

  namespace
  {
    // The stiffness sources of the registry, as a selection pattern and a help text.
    std::string source_selection()
    {
      std::string names;
      for (const auto &name : stiffness::source_names())
        names += (names.empty() ? "" : "|") + name;
      return names;
    }

    std::string source_help()
    {
      std::string text = "Stiffness source:";
      for (const auto *source : stiffness::sources())
        text += " " + source->name() + ": " + source->summary() +
                (source == stiffness::sources().back() ? "." : ";");
      return text + " Sources are described in docs/stiffness-closed-form.md and docs/theory-tca.md.";
    }

    // The type of a default: that of its field (so that 10 is a double default of a double).
    template <typename T>
    struct Default
    {
      using type = T;
    };

    // Declares the entries of a Scene, bound to its fields, each with its default (the parameter
    // file records them for unknown-key detection on --set and for docs/scenes.md).
    class SceneSchema
    {
    public:
      ParameterFile prm;

      void enter(const std::string &name, const std::string &help = "")
      {
        prm.enter_subsection(name, help);
      }
      void leave() { prm.leave_subsection(); }

      // Binds `value` to `key` with its documented default; every scene entry needs a help
      // text (ParameterFile::add refuses an empty one).
      template <typename T>
      void add(const std::string &key, T &value, const typename Default<T>::type &default_value,
               const Patterns::Pattern &pattern, const std::string &help)
      {
        value = default_value;
        prm.add(key, value, pattern, help);
      }
    };

    // Declaration of one gear's geometry, with the defaults of the paper's pinion or gear.
    void declare_gear(SceneSchema &s, GearScene &g, const std::string &name, int teeth,
                      double bore_radius_mm, const std::string &hand)
    {
      s.enter(name, "Geometry of the " + std::string(name == "Pinion" ? "driving pinion" : "driven gear") +
                      ", cut by the ISO 53 basic rack.");
      s.add("teeth", g.teeth, teeth, Patterns::Integer(6, 1000), "Number of teeth (count).");
      s.add("module_mm", g.module_mm, 3.0, Patterns::Double(0.05, 100.0),
            "Normal module m [mm]; both gears of a spur pair share it.");
      s.add("pressure_angle_deg", g.pressure_angle_deg, 20.0, Patterns::Double(10.0, 35.0),
            "Pressure angle of the basic rack alpha_P [deg]; both gears share it.");
      s.add("face_width_mm", g.face_width_mm, 20.0, Patterns::Double(0.1, 2000.0),
            "Face width b [mm].");
      // Per gear, as ISO 21771 gives them; check_consistency requires the pair to match.
      s.add("helix_angle_deg", g.helix_angle_deg, 0.0, Patterns::Double(0.0, 45.0),
            "Helix angle beta at the reference circle [deg] (ISO 21771), in [0, 45); 0 = spur. "
            "Given per gear as in ISO 21771; both gears of a pair must give the same value "
            "(checked). module_mm and pressure_angle_deg are then the normal values m_n, alpha_n. "
            "A helical pair needs the 3D FE model (Stiffness/fe_dimension = 3); the closed-form "
            "stiffness sources refuse it.");
      s.add("hand", g.hand, hand, Patterns::Selection("right|left"),
            "Hand of the helix: right or left (defaults: pinion right, gear left); an external "
            "pair needs opposite hands (checked). Ignored when helix_angle_deg = 0.");
      s.add("profile_shift_coefficient", g.profile_shift_coefficient, 0.0,
            Patterns::Double(-1.5, 2.0),
            "Profile shift coefficient x [dimensionless, in modules]; positive moves the rack away.");
      s.add("addendum_coefficient", g.addendum_coefficient, 1.0, Patterns::Double(0.5, 2.0),
            "Addendum of the gear h_a/m [dimensionless, in modules] (ISO 53: 1.0).");
      s.add("dedendum_coefficient", g.dedendum_coefficient, 1.25, Patterns::Double(0.5, 2.5),
            "Dedendum of the gear h_f/m = addendum of the cutting rack [dimensionless, in modules] "
            "(ISO 53 profile A: 1.25).");
      s.add("cutter_tip_radius_coefficient", g.cutter_tip_radius_coefficient, 0.38,
            Patterns::Double(0.0, 0.6),
            "Tip radius of the cutting rack rho_fP/m [dimensionless, in modules]; it shapes the "
            "trochoidal fillet (ISO 53 profile A: 0.38).");
      s.add("tip_radius_mm", g.tip_radius_mm, 0.0, Patterns::Double(0.0, 1.0e4),
            "Tip (outside) radius r_a [mm]; 0 takes r = m z/2 + m (addendum_coefficient + x).");
      s.add("bore_radius_mm", g.bore_radius_mm, bore_radius_mm, Patterns::Double(0.0, 1.0e4),
            "Bore radius [mm] where the body is clamped in the FE model and where the inertia "
            "disc ends; must lie inside the root circle.");
      s.add("crowning_um", g.crowning_um, 0.0, Patterns::Double(0.0, 1000.0),
            "Lead crowning amplitude beta [um]: parabolic material removal "
            "Delta(z) = beta (2z/b)^2 across the face width; 0 = uncrowned.");
      s.add("tip_relief_um", g.tip_relief_um, 0.0, Patterns::Double(0.0, 1000.0),
            "Tip relief amount C_a at the tip [um]; 0 = none.");
      s.add("tip_relief_length_mm", g.tip_relief_length_mm, 0.0, Patterns::Double(0.0, 100.0),
            "Length of the tip relief along the line of action, measured from the tip [mm].");
      s.add("tip_relief_shape", g.tip_relief_shape, "linear",
            Patterns::Selection("linear|parabolic"),
            "Shape of the tip relief along the roll length: linear or parabolic.");
      s.add("helix_slope_deviation_um", g.helix_slope_deviation_um, 0.0,
            Patterns::Double(-1000.0, 1000.0),
            "Helix slope deviation f_Hbeta [um] over the face width (ISO 1328-1): material removed "
            "f_Hbeta z / b, signed (> 0 removes material at the +z face end); 0 = none.");
      s.add("lead_end_relief_um", g.lead_end_relief_um, 0.0, Patterns::Double(0.0, 1000.0),
            "Lead end relief C_b [um] at both face ends, linear over lead_end_relief_length_mm "
            "from each end; 0 = none.");
      s.add("lead_end_relief_length_mm", g.lead_end_relief_length_mm, 0.0,
            Patterns::Double(0.0, 1000.0),
            "Length of the lead end relief from each face end [mm]; at most half the face width.");
      s.add("profile_crowning_um", g.profile_crowning_um, 0.0, Patterns::Double(0.0, 1000.0),
            "Profile crowning (barrelling) C_alpha [um]: parabolic material removal over the active "
            "profile, C_alpha at both of its ends and 0 in its middle; 0 = none.");
      s.add("root_relief_um", g.root_relief_um, 0.0, Patterns::Double(0.0, 1000.0),
            "Root relief C_f [um] at the start of the active profile, linear over "
            "root_relief_length_mm; 0 = none.");
      s.add("root_relief_length_mm", g.root_relief_length_mm, 0.0, Patterns::Double(0.0, 100.0),
            "Length of the root relief along the line of action from the start of the active "
            "profile [mm]; with the tip relief at most the active profile.");
      s.leave();
    }

    void declare_material(SceneSchema &s, Material &m, const std::string &name)
    {
      s.enter(name, "Linear elastic isotropic material of the " + name + ".");
      s.add("youngs_modulus_MPa", m.youngs_modulus_MPa, 206000.0, Patterns::Double(1.0e3, 1.0e7),
            "Young's modulus E [MPa] (steel: 206000).");
      s.add("poisson_ratio", m.poisson_ratio, 0.3, Patterns::Double(0.0, 0.499),
            "Poisson's ratio nu [dimensionless] (steel: 0.3).");
      s.add("density_kg_per_m3", m.density_kg_per_m3, 7850.0, Patterns::Double(100.0, 3.0e4),
            "Mass density rho [kg/m^3] (steel: 7850); gives the inertias of the gear bodies.");
      s.leave();
    }

    void declare_operating(SceneSchema &s, OperatingScene &o)
    {
      s.enter("Operating", "Load, speed and assembly of the pair.");
      s.add("torque_Nm", o.torque_Nm, 210.0, Patterns::Double(0.0, 1.0e7),
            "Torque on the pinion T_1 [N m]; the static mesh force is F_0 = T_1 / r_b1. "
            "0 is allowed for dynamics (rattle) but not for stiffness analysis.");
      s.add("speed_rpm", o.speed_rpm, 150.0, Patterns::Double(1.0e-3, 1.0e6),
            "Rotational speed of the pinion n_1 [rpm]; mesh frequency f_m = z_1 n_1 / 60.");
      s.add("center_distance_mm", o.center_distance_mm, 0.0, Patterns::Double(0.0, 1.0e5),
            "Operating centre distance a [mm]. 0 = the tight-mesh (zero-backlash) distance of the "
            "shifted pair, with backlash_mm made by thinning the teeth. When given, the backlash "
            "follows from it and backlash_mm must be 0.");
      s.add("backlash_mm", o.backlash_mm, 0.1172, Patterns::Double(0.0, 10.0),
            "Total backlash along the line of action 2 b_c [mm] (the dynamics' half backlash b_c is "
            "half of it), made by thinning both gears equally. Used when center_distance_mm = 0.");
      s.add("mesh_misalignment_um", o.mesh_misalignment_um, 0.0, Patterns::Double(-1000.0, 1000.0),
            "Mesh misalignment f_ma [um]: the shafts' misalignment along the line of action over "
            "the face width (ISO 6336-1), signed (> 0 opens the +z face end); it adds f_ma z / b "
            "to the unloaded gap. 0 = aligned.");
      s.add("axis_inclination_um", o.axis_inclination_um, 0.0, Patterns::Double(-1000.0, 1000.0),
            "Inclination of the axes f_Sigma_delta [um] over the face width, in their common plane "
            "(ISO/TR 10064-3); it acts as f_Sigma_delta sin(alpha_w) along the line of action.");
      s.add("axis_deviation_um", o.axis_deviation_um, 0.0, Patterns::Double(-1000.0, 1000.0),
            "Deviation of the axes f_Sigma_beta [um] over the face width, across their common plane "
            "(ISO/TR 10064-3); it acts as f_Sigma_beta cos(alpha_w) along the line of action.");
      s.leave();
    }

    void declare_effects(SceneSchema &s, EffectsScene &e)
    {
      s.enter("Effects", "Which physical effects the dynamics model contains. An effect that is "
                         "off is absent from the equations and the state.");
      s.add("mesh_force_law", e.mesh_force_law, "auto",
            Patterns::Selection("auto|serial-hertz|fe-map"),
            "Force law of the mesh's two springs in series: serial-hertz (the paper's: the "
            "structural spring k u and the Hertzian layer k_h G(delta), fitted at the nominal "
            "torque), fe-map (each spring's force interpolated in the stiffness table's FE load "
            "ladder, which Stiffness/source = fem makes) or auto: fe-map where the stiffness "
            "comes from the FE (source = fem, or a table that holds a load ladder) and the model "
            "has its Hertzian layer, serial-hertz otherwise (docs/dynamics.md).");
      s.add("backlash", e.backlash, "on", Patterns::Selection("on|off"),
            "Backlash non-linearity f(x) with half backlash b_c: on (contact loss and back-side "
            "impacts) or off (always in contact; no separation events).");
      s.add("hertzian_layer", e.hertzian_layer, "dynamic",
            Patterns::Selection("dynamic|quasi-static|off"),
            "Hertzian contact layer k_h(t) G(delta) in series with the structural spring k: dynamic "
            "(penetration delta is a state), quasi-static (delta solved algebraically from "
            "k (f - delta) = k_h G(delta)), off (F = k f(x) + c x', the Kahraman-Singh form).");
      s.add("contact_damping", e.contact_damping, "hunt-crossley",
            Patterns::Selection("hunt-crossley|lankarani-nikravesh|viscous-only"),
            "Damping of the Hertzian layer: hunt-crossley (mu = 1.5 alpha k_mh), "
            "lankarani-nikravesh (mu from restitution_coefficient and impact speed), or "
            "viscous-only (no mu H(delta) delta' term).");
      s.add("mesh_stiffness_variation", e.mesh_stiffness_variation, "fourier",
            Patterns::Selection("fourier|constant"),
            "Time variation of the Hertzian stiffness k_h(t): fourier (series over the mesh "
            "cycle) or constant (its mean k_mh).");
      s.add("rest_stiffness_variation", e.rest_stiffness_variation, "constant",
            Patterns::Selection("constant|fourier"),
            "Time variation of the structural (rest) stiffness k: constant (its mean, as in the "
            "paper) or fourier.");
      s.add("ste_excitation", e.ste_excitation, "off", Patterns::Selection("off|table"),
            "Unloaded static transmission error as a displacement excitation: off, or table "
            "(from the stiffness table's STE series).");
      s.leave();
    }

    void declare_stiffness(SceneSchema &s, StiffnessScene &st)
    {
      s.enter("Stiffness", "Where the mesh stiffness comes from and how finely it is resolved.");
      s.add("source", st.source, "fem", Patterns::Selection(source_selection()), source_help());
      s.add("table_file", st.table_file_entry, "", Patterns::Anything(),
            "Stiffness JSON file for source = table (path relative to the scene file).");
      s.add("positions_per_cycle", st.positions_per_cycle, 16, Patterns::Integer(1, 1024),
            "Number S of mesh positions per mesh cycle in the loaded TCA (count); S >= 2 "
            "harmonics + 1. The paper used 9.");
      s.add("harmonics", st.harmonics, 4, Patterns::Integer(0, 64),
            "Number of harmonics of the Fourier fit of k_h (and STE, k_total) (count).");
      s.add("hertz_exponent", st.hertz_exponent, 1.5, Patterns::Double(1.0, 2.0),
            "Exponent n of the load-penetration law F = k_h delta^n [dimensionless]: 1 for "
            "uncrowned line contact, 1.5 for crowned point contact.");
      s.add("fe_dimension", st.fe_dimension, 3, Patterns::Integer(2, 3),
            "Dimension of the FE bodies: 2 (plane strain, uncrowned pairs only) or 3.");
      s.add("fe_level", st.fe_level, 1, Patterns::Integer(0, 6),
            "FE refinement level (count): each level halves the element size in the contact band "
            "(and, in 3D, the layers across the face width). Each level costs about 4x (2D) or "
            "8x (3D) the DOFs; a 3D 5-tooth sector of module 3 mm at level 1 Q2 needs about 35 GB "
            "for its factorisation (docs/accuracy-stiffness.md).");
      s.add("fe_degree", st.fe_degree, 2, Patterns::Integer(1, 2),
            "Polynomial degree of the FE displacement (1 = Q1, 2 = Q2).");
      s.add("contact_grid_profile_points", st.contact_grid_profile_points, 24,
            Patterns::Integer(4, 4096),
            "Contact grid points across the profile per tooth pair (count).");
      s.add("contact_grid_face_points", st.contact_grid_face_points, 16, Patterns::Integer(1, 4096),
            "Contact grid points along the face width per tooth pair (count).");
      s.add("contact_grid_face_extent", st.contact_grid_face_extent, "load",
            Patterns::Selection("face-width|load"),
            "Face extent of the 3D contact grid: load (for crowned spur point contact a band that "
            "follows the load: 2 x the Hertz semi-axis along the face of the whole load on one "
            "pair either side of the smallest unloaded gap along the face, clipped to the face "
            "and enlarged where the contact reaches its inner edge, with the cells that a flank "
            "end crosses cut at it, so that the contact covers about the same points at every "
            "load and its discretisation error is smooth in the load; docs/theory-tca.md) or "
            "face-width (its points cover the whole face width at every load). Uncrowned flanks, "
            "helical pairs and 2D use the whole face either way.");
      s.add("contact_max_iterations", st.contact_max_iterations, 100, Patterns::Integer(1, 100000),
            "Iteration cap of the active-set contact solver per solve (count); reaching it is a "
            "numerical failure (exit 3) with the history of the active set.");
      s.add("tooth_coupling", st.tooth_coupling, "coupled",
            Patterns::Selection("coupled|decoupled"),
            "Structural compliance between different teeth of a body (source = fem): coupled "
            "(the FE body as it is) or decoupled (a load on one tooth does not move another, "
            "the assumption of the potential-energy method). decoupled is a study switch that "
            "shows what the coupling of loaded teeth through the rim does; it is not a gear.");
      s.add("reference_depth_mm", st.reference_depth_mm, 0.0, Patterns::Double(0.0, 10.0),
            "Depth d [mm] below the flank at which the FE compliance is read; the half-space "
            "supplies the local part above it, and FE load patches have radius d/2. 0 = "
            "automatic: 3 x the element size in the contact band at fe_level (0.54 mm for module "
            "3 at level 1). Fix it to compare levels at the same split (hertzgear accuracy "
            "stiffness does); at most half a module.");
      s.add("table_face_nodes", st.table_face_nodes, 0, Patterns::Integer(0, 1024),
            "Load nodes of the 3D FE compliance table along the face width, per roll node (count); "
            "0 = automatic: spaced at most the reference depth d apart with table_half_space_split "
            "(19 for the paper's 20 mm face at d = 1.08 mm), d/2 without it (37). The structural "
            "compliance read at depth d peaks over a width of about d, and the table interpolates "
            "it between nodes: 6 nodes without the split made the crowned contact 10 % too short "
            "and the single-pair stiffness 3 % too soft "
            "(docs/accuracy-stiffness.md). 1 is refused in 3D; 2D ignores it.");
      s.add("table_roll_nodes", st.table_roll_nodes, 0, Patterns::Integer(0, 1024),
            "Load nodes of the FE compliance table across the active profile, per face node "
            "(count); 0 = automatic: roll distances at most the reference depth d apart, at "
            "least 8 (13 for the paper's pinion at d = 1.08 mm). 1 is refused.");
      s.add("table_half_space_split", st.table_half_space_split, true, Patterns::Bool(),
            "3D compliance table: interpolate only the FE compliance minus the half-space "
            "response of the load patch at depth d, and add that response back at the exact "
            "distance (true), or interpolate the FE compliance itself (false). The half-space "
            "part holds the peak of width d; the remainder is smooth on the tooth's scale, so "
            "the split needs far fewer nodes for the same accuracy (docs/accuracy-stiffness.md). "
            "2D ignores it.");
      s.add("linear_solver", st.linear_solver, "direct", Patterns::Selection("direct|amg-cg"),
            "Linear solver of the FE bodies: direct (MUMPS, factorised once and reused) or amg-cg.");
      s.add("linear_solver_tolerance", st.linear_solver_tolerance, 1.0e-10,
            Patterns::Double(1.0e-16, 1.0e-2),
            "Relative residual tolerance of the iterative linear solver [dimensionless].");
      s.add("load_ladder_percent", st.load_ladder_percent,
            {2.0, 5.0, 10.0, 20.0, 35.0, 50.0, 70.0, 100.0, 140.0, 200.0, 280.0, 400.0},
            Patterns::List(Patterns::Double(-1.0e6, 1.0e4), 0, 64, ","),
            "Loads of the FE load ladder [% of Operating/torque_Nm], comma separated, at least 2, "
            "increasing, each > 0, the last >= 100: the mesh cycle runs again at each on the same "
            "FE bodies when the dynamics use the FE force law (Effects/mesh_force_law = fe-map, or "
            "auto with a Hertzian layer; source = fem), from "
            "near first touch to above the largest dynamic load (docs/dynamics.md, \"The FE force "
            "law\").");
      {
        auto &f                      = st.fourier;
        s.enter("Map", "Load and design map of the FE contact analysis (source = fem): further "
                       "contact cycles on the same FE bodies, written to stiffness_map.csv and "
                       "stiffness.json (docs/user-guide.md, \"Torque maps and misalignment\").");
        s.add("torque_percent", st.map_torque_percent, {},
              Patterns::List(Patterns::Double(-1.0e6, 1.0e4), 0, 64, ","),
              "Torques of the map [% of Operating/torque_Nm], comma separated, each > 0 (for "
              "example 10, 25, 50, 100, 150, 200); empty = no torque map.");
        s.add("crowning_um", st.map_crowning_um, {},
              Patterns::List(Patterns::Double(0.0, 1000.0), 0, 16, ","),
              "Lead crowning variants beta [um] of the map, each applied to both gears (replacing "
              "their crowning_um), each with every torque of torque_percent (or the scene's "
              "torque); empty = the scene's crowning only.");
        s.add("mesh_misalignment_um", st.map_mesh_misalignment_um, {},
              Patterns::List(Patterns::Double(-1000.0, 1000.0), 0, 64, ","),
              "Mesh misalignment variants f_ma [um] of the map (replacing "
              "Operating/mesh_misalignment_um), at the scene's torque, each with every crowning "
              "variant; empty = none.");
        s.add("helix_slope_deviation_um", st.map_helix_slope_deviation_um, {},
              Patterns::List(Patterns::Double(-1000.0, 1000.0), 0, 64, ","),
              "Helix slope deviation variants f_Hbeta [um] of the map, each the pinion's (replacing "
              "Gear pair/Pinion/helix_slope_deviation_um; the gear keeps its own: the contact sees "
              "the sum of the two), at the scene's torque, each with every crowning variant; "
              "empty = none.");
        s.add("combination", st.map_combination, "separate", Patterns::Selection("separate|product"),
              "How the map's lists combine: separate = every torque with every crowning, then each "
              "misalignment and each helix slope variant at the scene's torque with every "
              "crowning; product = every combination of crowning x helix slope x misalignment x "
              "torque (a tolerance study; an empty list keeps the scene's value).");
        s.leave();
        s.enter("Fourier", "Stiffness given as Fourier coefficients (source = fourier): "
                           "k(t) = mean + sum_j a_j cos(j omega_m t - phi_j).");
        s.add("k_rest_mean_N_per_m", f.k_rest_mean_N_per_m, 4.17e8, Patterns::Double(0.0, 1.0e13),
              "Mean structural (rest) mesh stiffness k [N/m] (the paper: 4.17e8 uncrowned, "
              "2.79e8 crowned).");
        s.add("k_rest_amplitudes_N_per_m", f.k_rest_amplitudes_N_per_m, {},
              Patterns::List(Patterns::Double(0.0, 1.0e13), 0, 64, ","),
              "Harmonic amplitudes of k [N/m], comma separated, harmonic 1 first.");
        s.add("k_rest_phases_rad", f.k_rest_phases_rad, {},
              Patterns::List(Patterns::Double(-100.0, 100.0), 0, 64, ","),
              "Harmonic phases of k [rad], one per amplitude.");
        s.add("k_hertz_mean_N_per_m_pow_n", f.k_hertz_mean_N_per_m_pow_n, 0.0,
              Patterns::Double(0.0, 1.0e16),
              "Mean Hertzian stiffness k_mh [N/m^n] of F = k_h delta^n.");
        s.add("k_hertz_amplitudes_N_per_m_pow_n", f.k_hertz_amplitudes_N_per_m_pow_n, {},
              Patterns::List(Patterns::Double(0.0, 1.0e16), 0, 64, ","),
              "Harmonic amplitudes k_hj of k_h [N/m^n], comma separated, harmonic 1 first.");
        s.add("k_hertz_phases_rad", f.k_hertz_phases_rad, {},
              Patterns::List(Patterns::Double(-100.0, 100.0), 0, 64, ","),
              "Harmonic phases phi_j of k_h [rad], one per amplitude.");
        s.leave();
      }
      s.leave();
    }

    void declare_mesh(SceneSchema &s, MeshScene &m)
    {
      s.enter("Mesh", "gmsh meshes of the gear bodies.");
      s.add("body_model", m.body_model, "full-gear", Patterns::Selection("full-gear|sector"),
            "What each FE body is: full-gear = the whole gear clamped at its bore, computed exactly "
            "from one meshed tooth sector by cyclic symmetry; sector = a meshed sector of "
            "teeth_per_sector teeth clamped at its bore and at both cuts (an approximation, stiffer "
            "than the gear; docs/accuracy-stiffness.md measures it).");
      s.add("teeth_per_sector", m.teeth_per_sector, 5, Patterns::Integer(1, 1000),
            "body_model = sector: teeth in the meshed sector of each body (count, odd recommended: "
            "the loaded tooth in the middle); a value >= the number of teeth meshes the full gear "
            "as one body.");
      s.add("face_width_layers", m.face_width_layers, 8, Patterns::Integer(1, 512),
            "Element layers across the face width of 3D meshes at level 0 (count).");
      s.leave();
    }

    void declare_dynamics(SceneSchema &s, DynamicsScene &d)
    {
      s.enter("Dynamics", "Integration of the gear-pair equations.");
      s.add("integrator", d.integrator, "radau-iia",
            Patterns::Selection("rk4|arkode-erk|cvode-bdf|ida|radau-iia"),
            "Time integrator: radau-iia (stiff, adaptive, order 5-13; default: the cheapest at "
            "every accuracy measured in docs/accuracy-dynamics.md), cvode-bdf (stiff, adaptive, "
            "SUNDIALS BDF), ida (DAE form, needed when c = 0), arkode-erk (adaptive explicit RK) "
            "or rk4 (the paper's fixed step).");
      s.add("radau_stages", d.radau_stages, 0, Patterns::Integer(0, 9),
            "Stages s of radau-iia (count: 3, 5, 7 or 9, order 2s - 1; 0 chooses by the tolerance: "
            "3 above 1e-5, 5 down to 1e-10, 7 below; the flows of periodic orbits take 7 below "
            "1e-7).");
      s.add("relative_tolerance", d.relative_tolerance, 1.0e-8, Patterns::Double(1.0e-14, 1.0e-2),
            "Relative tolerance of the adaptive integrators [dimensionless].");
      s.add("absolute_tolerance_m", d.absolute_tolerance_m, 1.0e-13,
            Patterns::Double(1.0e-20, 1.0e-3),
            "Absolute tolerance on the displacements x and delta [m] (velocities are scaled by "
            "the mesh frequency).");
      s.add("steps_per_period", d.steps_per_period, 100, Patterns::Integer(1, 10000000),
            "Fixed steps per mesh period for rk4 (count; the paper: 100).");
      s.add("periods", d.periods, 800, Patterns::Integer(1, 10000000),
            "Mesh periods integrated in all (count; the paper: 800).");
      s.add("transient_periods", d.transient_periods, 600, Patterns::Integer(0, 10000000),
            "Leading mesh periods discarded before steady-state analysis (count); < periods.");
      s.add("samples_per_period", d.samples_per_period, 100, Patterns::Integer(1, 100000),
            "Output samples per mesh period (count; the paper: 100).");
      s.add("initial_state", d.initial_state, "static", Patterns::Selection("static|given"),
            "Initial condition: static (static equilibrium under F_0 with the mean stiffness) or "
            "given (initial_dte_um, initial_dte_rate_m_per_s, initial_penetration_um).");
      s.add("initial_dte_um", d.initial_dte_um, 0.0, Patterns::Double(-1.0e5, 1.0e5),
            "Initial dynamic transmission error x(0) [um] (initial_state = given).");
      s.add("initial_dte_rate_m_per_s", d.initial_dte_rate_m_per_s, 0.0,
            Patterns::Double(-1.0e3, 1.0e3),
            "Initial rate x'(0) [m/s] (initial_state = given).");
      s.add("initial_penetration_um", d.initial_penetration_um, 0.0,
            Patterns::Double(-1.0e5, 1.0e5),
            "Initial Hertzian penetration delta(0) [um] (initial_state = given, dynamic layer).");
      s.add("damping_from", d.damping_from, "ratio", Patterns::Selection("ratio|coefficient"),
            "How the mesh damping c is given: ratio (c = 2 zeta sqrt(k_eq m_e)) or coefficient.");
      s.add("damping_ratio", d.damping_ratio, 0.015, Patterns::Double(0.0, 1.0),
            "Mesh damping ratio zeta [dimensionless] (the paper: 0.015).");
      s.add("damping_coefficient_N_s_per_m", d.damping_coefficient_N_s_per_m, 0.0,
            Patterns::Double(0.0, 1.0e9),
            "Mesh damping coefficient c [N s/m] (damping_from = coefficient; 0 gives the DAE form).");
      s.add("alpha_s_per_m", d.alpha_s_per_m, 0.26, Patterns::Double(0.0, 10.0),
            "Hunt-Crossley coefficient alpha = (1 - e)/v_i [s/m]; mu = 1.5 alpha k_mh "
            "(steel: 0.08 to 0.32; the paper: 0.26).");
      s.add("restitution_coefficient", d.restitution_coefficient, 0.9, Patterns::Double(0.0, 1.0),
            "Coefficient of restitution e for the Lankarani-Nikravesh law [dimensionless].");
      s.add("pinion_inertia_kg_m2", d.pinion_inertia_kg_m2, 0.0, Patterns::Double(0.0, 1.0e6),
            "Polar moment of inertia of the pinion [kg m^2]; 0 = solid disc between bore and "
            "root radius over the face width.");
      s.add("gear_inertia_kg_m2", d.gear_inertia_kg_m2, 0.0, Patterns::Double(0.0, 1.0e6),
            "Polar moment of inertia of the gear [kg m^2]; 0 = solid disc between bore and root "
            "radius over the face width.");
      s.leave();
    }

    void declare_sweep(SceneSchema &s, SweepScene &w)
    {
      s.enter("Sweep", "Speed sweep of the dynamics (hertzgear sweep, or run when enabled).");
      s.add("enabled", w.enabled, false, Patterns::Bool(),
            "Whether `hertzgear run` adds the speed sweep (true/false).");
      s.add("speed_min_rpm", w.speed_min_rpm, 100.0, Patterns::Double(1.0e-3, 1.0e6),
            "Lowest pinion speed of the sweep [rpm].");
      s.add("speed_max_rpm", w.speed_max_rpm, 10000.0, Patterns::Double(1.0e-3, 1.0e6),
            "Highest pinion speed of the sweep [rpm].");
      s.add("points", w.points, 50, Patterns::Integer(2, 100000), "Speeds in the sweep (count).");
      s.add("direction", w.direction, "both", Patterns::Selection("up|down|both"),
            "Continuation direction: up, down or both.");
      s.add("mode", w.mode, "both", Patterns::Selection("continuation|independent|both|shooting"),
            "Time marching: continuation (each point starts from the last state) and/or "
            "independent points from the initial state (for bifurcation diagrams); or shooting: "
            "the periodic orbits themselves, followed over the speed range by arclength "
            "continuation with their stability (Response/*, docs/dynamics.md; writes "
            "response.csv instead of sweep.csv).");
      s.add("periods_per_point", w.periods_per_point, 300, Patterns::Integer(1, 10000000),
            "Mesh periods integrated per sweep point (count).");
      s.add("transient_periods_per_point", w.transient_periods_per_point, 200,
            Patterns::Integer(0, 10000000),
            "Leading mesh periods discarded per sweep point (count); < periods_per_point.");
      s.leave();
    }

    void declare_response(SceneSchema &s, ResponseScene &r)
    {
      s.enter("Response",
              "Periodic orbits found by shooting and followed by pseudo-arclength continuation "
              "(hertzgear response, or hertzgear sweep with Sweep/mode = shooting): stable and "
              "unstable branches, Floquet multipliers, folds, period doublings and "
              "Neimark-Sacker points (docs/dynamics.md).");
      s.add("parameter", r.parameter, "speed_rpm",
            Patterns::Selection("speed_rpm|torque_Nm|damping_ratio"),
            "The continuation parameter: speed_rpm (range Sweep/speed_min_rpm ... "
            "Sweep/speed_max_rpm), torque_Nm (range torque_min_Nm ... torque_max_Nm) or "
            "damping_ratio (range damping_ratio_min ... damping_ratio_max; the mesh damping "
            "from the ratio).");
      s.add("torque_min_Nm", r.torque_min_Nm, 10.0, Patterns::Double(1.0e-6, 1.0e7),
            "Lowest pinion torque of a torque continuation [N m].");
      s.add("torque_max_Nm", r.torque_max_Nm, 500.0, Patterns::Double(1.0e-6, 1.0e7),
            "Highest pinion torque of a torque continuation [N m].");
      s.add("damping_ratio_min", r.damping_ratio_min, 0.001, Patterns::Double(1.0e-6, 2.0),
            "Lowest mesh damping ratio of a damping continuation (dimensionless).");
      s.add("damping_ratio_max", r.damping_ratio_max, 0.1, Patterns::Double(1.0e-6, 2.0),
            "Highest mesh damping ratio of a damping continuation (dimensionless).");
      s.add("start", r.start, "low", Patterns::Selection("low|high"),
            "The end of the range the continuation starts from (its orbit found by shooting "
            "from Dynamics/initial_state): low or high.");
      s.add("step_max", r.step_max, 0.02, Patterns::Double(1.0e-5, 0.5),
            "Largest continuation step, as a fraction of the parameter range in the scaled "
            "arclength (dimensionless).");
      s.add("max_points_per_branch", r.max_points_per_branch, 2000, Patterns::Integer(2, 1000000),
            "Most points on one branch (count).");
      s.add("period_doubling_branches", r.period_doubling_branches, 3, Patterns::Integer(0, 100),
            "Period-doubled branches followed from the period doublings found (count; 0: "
            "none).");
      s.add("newton_tolerance", r.newton_tolerance, 1.0e-6, Patterns::Double(1.0e-14, 1.0e-3),
            "Newton's method stops when its correction is below this fraction of the state's "
            "scale (dimensionless); at least 10 Response/relative_tolerance, since the period "
            "map is only as smooth as its integration across the switching events.");
      s.add("relative_tolerance", r.relative_tolerance, 1.0e-10, Patterns::Double(1.0e-14, 1.0e-4),
            "Relative tolerance of the integration of the period map, its sensitivities and each "
            "orbit's analysis (dimensionless; Dynamics/integrator, its absolute tolerance): the "
            "integration error, amplified by 1 / |1 - mu| near a fold, must stay below "
            "newton_tolerance, else the corrector stalls and folds are mislocated "
            "(docs/dynamics.md, \"Continuation of periodic orbits\").");
      s.add("samples_per_period", r.samples_per_period, 100, Patterns::Integer(8, 100000),
            "Samples per mesh period of each orbit's analysis (RMS DTE; extremes from the dense "
            "output) (count).");
      s.leave();
    }

    void declare_output(SceneSchema &s, OutputScene &out)
    {
      s.enter("Output", "What is written next to the results.");
      s.add("timeseries_periods", out.timeseries_periods, 50, Patterns::Integer(0, 10000000),
            "Last mesh periods written to timeseries.csv (count; 0 = every steady period).");
      s.add("write_fields", out.write_fields, true, Patterns::Bool(),
            "Write .vtu/.pvd fields (displacement, stress, contact pressure) of the FE stage.");
      s.add("report", out.report, true, Patterns::Bool(),
            "Write the HTML report with figures at the end of `hertzgear run`.");
      s.leave();
    }

    void declare_scene(SceneSchema &s, Scene &sc)
    {
      s.enter("Gear pair", "The gear pair: pinion (driving) and gear (driven); spur, or helical "
                           "(helix_angle_deg > 0).");
      declare_gear(s, sc.pinion, "Pinion", 23, 15.0, "right");
      declare_gear(s, sc.gear, "Gear", 34, 20.0, "left");
      s.leave();

      s.enter("Material", "Materials of both bodies.");
      declare_material(s, sc.pinion_material, "Pinion");
      declare_material(s, sc.gear_material, "Gear");
      s.leave();

      declare_operating(s, sc.operating);
      declare_effects(s, sc.effects);
      declare_stiffness(s, sc.stiffness);
      declare_mesh(s, sc.mesh);
      declare_dynamics(s, sc.dynamics);
      declare_sweep(s, sc.sweep);
      declare_response(s, sc.response);
      declare_output(s, sc.output);
    }


    void apply_override(SceneSchema &schema, const std::string &full_text)
    {
      const std::string text = shown(full_text);
      const auto eq = full_text.find('=');
      HG_REQUIRE_INPUT(eq != std::string::npos && eq > 0,
                       "--set \"", text, "\": expected \"Section/Subsection/key=value\"");
      const std::string path  = full_text.substr(0, eq);
      const auto        slash = path.rfind('/');
      HG_REQUIRE_INPUT(slash != std::string::npos,
                       "--set \"", text, "\": the key must name its section, e.g. "
                       "\"Operating/speed_rpm=1000\"");
      const auto trim = [](const std::string &t) {
        const auto b = t.find_first_not_of(" \t");
        const auto e = t.find_last_not_of(" \t");
        return b == std::string::npos ? std::string() : t.substr(b, e - b + 1);
      };
      const std::string section = trim(path.substr(0, slash));
      const std::string key     = trim(path.substr(slash + 1));
      const auto       *entry   = schema.prm.find(section, key);
      HG_REQUIRE_INPUT(entry != nullptr, "--set \"", text, "\": unknown key \"", shown(key),
                       "\" in section \"", shown(section), "\" (see `hertzgear defaults`)");
      const std::string value = trim(full_text.substr(eq + 1));
      HG_REQUIRE_INPUT(value.size() <= ParameterFile::max_value_length, "--set \"", text, "\": ",
                       section, "/", key, ": the value is ", value.size(),
                       " characters long, more than the ", ParameterFile::max_value_length,
                       " characters a scene value can have");

      HG_REQUIRE_INPUT(entry->pattern().match(value), "--set \"", text, "\": value \"",
                       shown(value), "\" for ", section, "/", key,
                       " is not allowed; allowed: ", entry->pattern().description());
      try
        {
          schema.prm.set(section, key, value);
        }
      catch (const ParameterFileError &e)
        {
          throw InputError(msg("--set \"", text, "\": ", e.what()));
        }
    }

    // Cross-field checks that a range pattern cannot express.
    void check_consistency(const Scene &sc)
    {
      const GearScene &p = sc.pinion, &g = sc.gear;
      HG_REQUIRE_INPUT(std::abs(p.module_mm - g.module_mm) <= 1e-12 * p.module_mm,
                       "impossible gear pair: Gear pair/Pinion/module_mm = ", p.module_mm,
                       " differs from Gear pair/Gear/module_mm = ", g.module_mm,
                       "; spur gears in mesh share one module");
      HG_REQUIRE_INPUT(std::abs(p.pressure_angle_deg - g.pressure_angle_deg) <= 1e-12,
                       "impossible gear pair: Gear pair/Pinion/pressure_angle_deg = ",
                       p.pressure_angle_deg, " differs from Gear pair/Gear/pressure_angle_deg = ",
                       g.pressure_angle_deg, "; spur gears in mesh share one pressure angle");
      for (const auto &[name, gear] : {std::pair<const char *, const GearScene *>{"Pinion", &p},
                                       std::pair<const char *, const GearScene *>{"Gear", &g}})
        HG_REQUIRE_INPUT(gear->helix_angle_deg < 45.0, "Gear pair/", name, "/helix_angle_deg = ",
                         gear->helix_angle_deg, " is outside [0, 45) deg");
      HG_REQUIRE_INPUT(p.helix_angle_deg == g.helix_angle_deg,
                       "impossible gear pair: Gear pair/Pinion/helix_angle_deg = ", p.helix_angle_deg,
                       " differs from Gear pair/Gear/helix_angle_deg = ", g.helix_angle_deg,
                       "; the gears of an external helical pair share one helix angle (with "
                       "opposite hands)");
      HG_REQUIRE_INPUT(p.helix_angle_deg == 0 || p.hand != g.hand,
                       "impossible gear pair: Gear pair/Pinion/hand = ", p.hand,
                       " and Gear pair/Gear/hand = ", g.hand, " are the same; an external helical "
                       "pair needs opposite hands (one right, one left)");
      const std::pair<const char *, const GearScene *> gears[] = {{"Pinion", &p}, {"Gear", &g}};
      for (const auto &[name, gear] : gears)
        {
          const double rf = meshing::root_radius_mm(gear_parameters(*gear, name));
          HG_REQUIRE_INPUT(gear->bore_radius_mm < rf,
                           "Gear pair/", name, "/bore_radius_mm = ", gear->bore_radius_mm,
                           " is not inside the root circle (root radius ", rf, " mm)");
          HG_REQUIRE_INPUT(gear->tip_radius_mm == 0.0 || gear->tip_radius_mm > rf,
                           "Gear pair/", name, "/tip_radius_mm = ", gear->tip_radius_mm,
                           " is not outside the root circle (root radius ", rf, " mm)");
          HG_REQUIRE_INPUT((gear->tip_relief_um > 0) == (gear->tip_relief_length_mm > 0),
                           "Gear pair/", name, "/tip_relief_um = ", gear->tip_relief_um,
                           " and tip_relief_length_mm = ", gear->tip_relief_length_mm,
                           ": a tip relief needs both an amount and a length (or neither)");
        }
      HG_REQUIRE_INPUT(sc.operating.center_distance_mm == 0.0 || sc.operating.backlash_mm == 0.0,
                       "Operating/center_distance_mm = ", sc.operating.center_distance_mm,
                       " and Operating/backlash_mm = ", sc.operating.backlash_mm,
                       " are both given; the backlash follows from the centre distance, so set "
                       "one of them to 0");

      const auto &st = sc.stiffness;
      if (st.source == "fem")
        {
          HG_REQUIRE_INPUT(st.positions_per_cycle >= 2 * st.harmonics + 1,
                           "Stiffness/positions_per_cycle = ", st.positions_per_cycle,
                           " is too few for Stiffness/harmonics = ", st.harmonics,
                           "; a Fourier fit needs at least 2 harmonics + 1 = ",
                           2 * st.harmonics + 1, " positions");
          HG_REQUIRE_INPUT(st.fe_dimension == 3 || (p.crowning_um == 0 && g.crowning_um == 0),
                           "Stiffness/fe_dimension = 2 (plane strain) cannot represent lead "
                           "crowning (Gear pair/*/crowning_um > 0); use fe_dimension = 3");
        }
      if (st.source == "table" || sc.effects.ste_excitation == "table")
        {
          HG_REQUIRE_INPUT(!st.table_file.empty(),
                           "Stiffness/table_file is empty but Stiffness/source = table or "
                           "Effects/ste_excitation = table needs a stiffness JSON file");
        }
      HG_REQUIRE_INPUT(sc.effects.mesh_force_law != "fe-map" || st.source == "fem" ||
                         st.source == "table",
                       "Effects/mesh_force_law = fe-map needs the load ladder of an FE contact "
                       "analysis, which Stiffness/source = fem makes (or source = table with a "
                       "table that holds one); Stiffness/source = ", st.source, " makes none");
      if (st.source == "fourier")
        {
          HG_REQUIRE_INPUT(st.fourier.k_hertz_amplitudes_N_per_m_pow_n.size() ==
                             st.fourier.k_hertz_phases_rad.size(),
                           "Stiffness/Fourier: ", st.fourier.k_hertz_amplitudes_N_per_m_pow_n.size(),
                           " entries in k_hertz_amplitudes_N_per_m_pow_n but ",
                           st.fourier.k_hertz_phases_rad.size(), " in k_hertz_phases_rad");
          HG_REQUIRE_INPUT(st.fourier.k_rest_amplitudes_N_per_m.size() ==
                             st.fourier.k_rest_phases_rad.size(),
                           "Stiffness/Fourier: ", st.fourier.k_rest_amplitudes_N_per_m.size(),
                           " entries in k_rest_amplitudes_N_per_m but ",
                           st.fourier.k_rest_phases_rad.size(), " in k_rest_phases_rad");
          HG_REQUIRE_INPUT(st.fourier.k_rest_mean_N_per_m > 0,
                           "Stiffness/Fourier/k_rest_mean_N_per_m must be > 0 for source = fourier");
          HG_REQUIRE_INPUT(sc.effects.hertzian_layer == "off" ||
                             st.fourier.k_hertz_mean_N_per_m_pow_n > 0,
                           "Stiffness/Fourier/k_hertz_mean_N_per_m_pow_n must be > 0 for source = "
                           "fourier with a Hertzian layer (Effects/hertzian_layer)");
        }
      const auto &d = sc.dynamics;
      HG_REQUIRE_INPUT(d.transient_periods < d.periods, "Dynamics/transient_periods = ",
                       d.transient_periods, " must be less than Dynamics/periods = ", d.periods);
      const auto &w = sc.sweep;
      HG_REQUIRE_INPUT(w.speed_min_rpm < w.speed_max_rpm, "Sweep/speed_min_rpm = ",
                       w.speed_min_rpm, " must be less than Sweep/speed_max_rpm = ",
                       w.speed_max_rpm);
      const auto &r = sc.response;
      HG_REQUIRE_INPUT(r.torque_min_Nm < r.torque_max_Nm, "Response/torque_min_Nm = ",
                       r.torque_min_Nm, " must be less than Response/torque_max_Nm = ",
                       r.torque_max_Nm);
      HG_REQUIRE_INPUT(r.damping_ratio_min < r.damping_ratio_max, "Response/damping_ratio_min = ",
                       r.damping_ratio_min, " must be less than Response/damping_ratio_max = ",
                       r.damping_ratio_max);
      HG_REQUIRE_INPUT(w.transient_periods_per_point < w.periods_per_point,
                       "Sweep/transient_periods_per_point = ", w.transient_periods_per_point,
                       " must be less than Sweep/periods_per_point = ", w.periods_per_point);
    }

    // Whether `entry` stays out of the scene hash: a helix key of a spur gear (helix_angle_deg = 0)
    // of `sc`, whichever hand it names and however it writes 0, and a key of the tolerance study
    // (Stiffness/Map/helix_slope_deviation_um, combination) at its default, which changes nothing.
    // A scene keeps the hash it had before those keys existed (stiffness tables and run.json
    // record it).
    bool stays_out_of_hash(const Scene &sc, const ParameterFile::Entry &entry)
    {
      if (entry.section() == "Stiffness/Map" &&
          (entry.key() == "helix_slope_deviation_um" || entry.key() == "combination"))
        return entry.text() == entry.default_text();
      const GearScene *gear = entry.section() == "Gear pair/Pinion" ? &sc.pinion :
                              entry.section() == "Gear pair/Gear"   ? &sc.gear :
                                                                      nullptr;
      return gear != nullptr && gear->helix_angle_deg == 0 &&
             (entry.key() == "helix_angle_deg" || entry.key() == "hand");
    }
  } // namespace

  Scene load_scene(const fs::path &file, const std::vector<std::string> &overrides)
  {
    Scene       sc;
    SceneSchema schema;
    declare_scene(schema, sc);

    if (!file.empty())
      {
        HG_REQUIRE_INPUT(fs::exists(file), "scene file ", file.string(), " does not exist");
        HG_REQUIRE_INPUT(fs::is_regular_file(file), "scene file ", file.string(),
                         " is not a regular file");
        const std::string ext = file.extension().string();
        HG_REQUIRE_INPUT(ext == ".prm" || ext == ".json",
                         "scene file ", file.string(), ": unknown format \"", ext,
                         "\" (expected .prm or .json)");
        {
          std::ifstream probe(file);
          HG_REQUIRE_INPUT(probe.good(), "scene file ", file.string(), " cannot be read");
        }
        try
          {
            if (ext == ".json")
              {
                const nlohmann::json tree = read_json_file(file, "scene file");
                HG_REQUIRE_INPUT(tree.is_object(), "scene file ", file.string(),
                                 ": a JSON scene must be an object of sections");
                schema.prm.parse_json(tree, file.string() + " (as .prm)");
              }
            else
              schema.prm.parse_file(file);
          }
        catch (const ParameterFileError &e)
          {
            // e names the source and the line
            throw InputError(msg("scene file ", e.what()));
          }
        catch (const InputError &)
          {
            throw; // already names the scene file
          }
        catch (const std::exception &e)
          {
            throw InputError(msg("scene file ", file.string(), ": ", e.what()));
          }
        sc.file = fs::absolute(file);
      }
    for (const auto &o : overrides)
      apply_override(schema, o);

    sc.stiffness.table_file = sc.stiffness.table_file_entry;
    if (!sc.stiffness.table_file.empty() && sc.stiffness.table_file.is_relative() && !sc.file.empty())
      sc.stiffness.table_file = sc.file.parent_path() / sc.stiffness.table_file;

    check_consistency(sc);

    sc.used_parameters_prm = schema.prm.print(ParameterFile::Style::documented);
    sc.hash = hash_hex(schema.prm.print(ParameterFile::Style::short_form,
                                        ParameterFile::Order::alphabetical,
                                        [&sc](const ParameterFile::Entry &e) {
                                          return stays_out_of_hash(sc, e);
                                        }));
    return sc;
  }

  std::string default_scene_prm()
  {
    Scene       sc;
    SceneSchema schema;
    declare_scene(schema, sc);
    return "# hertzgear default scene: every entry with its unit, allowed range and meaning.\n"
           "# Lines starting with '#' are comments; `hertzgear check FILE` validates a scene.\n" +
           schema.prm.print(ParameterFile::Style::documented);
  }

  std::string scene_reference_markdown()
  {
    Scene       sc;
    SceneSchema schema;
    declare_scene(schema, sc);
    std::ostringstream md;
    md << "# Scene reference\n\n"
       << "Generated by `hertzgear defaults --markdown` from the parameter declarations in "
          "`app/scene.cc`; a test fails when this file and the declarations differ. Regenerate with\n"
          "`build/app/hertzgear defaults --markdown > docs/scenes.md`.\n\n"
       << "A scene is a parameter file (`.prm`: `subsection NAME`, `set key = value` and `end` "
          "lines, `#` comments; or the same tree as `.json`). Every value can be overridden on the command line with "
          "`--set \"Section/Subsection/key=value\"`. Units are in the key names; counts and "
          "dimensionless coefficients say so in their meaning.\n";
    md << schema.prm.markdown();
    return md.str();
  }

  bool makes_load_ladder(const Scene &scene)
  {
    const auto &law = scene.effects.mesh_force_law;
    return scene.stiffness.source == "fem" &&
           (law == "fe-map" || (law == "auto" && scene.effects.hertzian_layer != "off"));
  }

  std::string scene_values_for(const Scene &scene, const std::vector<std::string> &prefixes,
                               const std::vector<std::string> &drop)
  {
    const auto starts_with = [](const std::string &path, const std::string &prefix) {
      return path.rfind(prefix, 0) == 0;
    };
    std::vector<std::string> lines;
    for (const auto &[path, value] : parameter_values(scene.used_parameters_prm))
      for (const auto &prefix : prefixes)
        if (starts_with(path, prefix) &&
            std::none_of(drop.begin(), drop.end(),
                         [&](const std::string &d) { return starts_with(path, d); }))
          {
            lines.push_back(path + " = " + value);
            break;
          }
    std::sort(lines.begin(), lines.end());
    std::string out;
    for (const auto &l : lines)
      out += l + "\n";
    return out;
  }
} // namespace hertzgear
