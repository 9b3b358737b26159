// `hertzgear validate hertz [SCENE] [--case NAME] [--coarse] --out DIR`: the Hertz closed forms
// (contact/hertz) and the TCA's hybrid local compliance (contact/mesh_cycle) against resolved FE contact
// (fem/resolved_contact), per canonical case of data/scenes/validation/. Writes
// hertz_validation.csv (case, quantity, closed_form, fe, relative_error, level, dofs,
// wall_time_s), hertz_rates.csv, pressure_profiles.csv, the used parameters and, when
// /usr/bin/python3 has matplotlib, the figures of scripts/plot_hertz_validation.py.
// Method and measured numbers: docs/validation-hertz.md.
#include "app/cmd_validate_hertz.h"

#include "app/meshing_setup.h"
#include "app/stiffness_setup.h"
#include "stiffness/fe_tca.h"
#include "app/scripts.h"
#include "app/scene.h"
#include "app/validation_scene.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/progress.h"
#include "contact/half_space.h"
#include "contact/hertz.h"
#include "contact/mesh_cycle.h"
#include "fem/resolved_contact.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

namespace hertzgear
{
  namespace fs = std::filesystem;

  namespace
  {
    struct Row
    {
      std::string        case_name, quantity;
      double             closed_form = 0, fe = 0;
      unsigned int       level       = 0;
      unsigned long long dofs        = 0;
      double             wall_time_s = 0;
      double             contact_cell_mm = 0;
    };

    struct Study
    {
      std::vector<Row> rows;
      std::ostringstream profiles; // case, axis, coordinate_mm, fe_pressure_MPa, hertz_pressure_MPa
      std::ostringstream notes;    // per case, for run.json-like provenance
    };

    bool is_root() { return dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0; }

    void say(const std::string &text)
    {
      if (is_root())
        progress_line("validate", text);
    }

    std::string percent(const double closed, const double fe)
    {
      std::ostringstream os;
      os << std::showpos << std::fixed << std::setprecision(3) << 100.0 * (fe - closed) / closed
         << " %";
      return os.str();
    }

    // Displacement (into the body) on the axis at depth d of a half-space of modulus E, Poisson's
    // ratio nu, under the Hertz pressure p0 sqrt(1 - x^2/a^2 - y^2/b^2): Boussinesq's point load
    // integrated numerically (x = a r cos t, y = b r sin t, r = sin s: the integrand is smooth;
    // Gauss-Legendre in s, the periodic trapezoidal rule in t).
    double hertz_displacement_at_depth(const double p0, const double a, const double b,
                                       const double depth, const double E, const double nu)
    {
      const dealii::QGauss<1> gauss(64);
      const unsigned int      n_t = 256;
      double                  u   = 0;
      for (unsigned int q = 0; q < gauss.size(); ++q)
        {
          const double s  = 0.5 * M_PI * gauss.point(q)[0];
          const double ws = 0.5 * M_PI * gauss.weight(q);
          const double r = std::sin(s), dr = std::cos(s);
          const double p = p0 * std::cos(s);
          for (unsigned int k = 0; k < n_t; ++k)
            {
              const double t = 2.0 * M_PI * (k + 0.5) / n_t;
              const double x = a * r * std::cos(t), y = b * r * std::sin(t);
              u += p * a * b * r * dr * ws * (2.0 * M_PI / n_t) *
                   half_space::point_load_displacement(std::hypot(x, y), depth, 1.0, E, nu);
            }
        }
      return u;
    }

    // A body whose structural compliance at the reference depth is the half-space's: the
    // displacement at depth d below flank point `reading` of a unit force spread uniformly over
    // the TCA grid cell centred at flank point `load` (Boussinesq-Love, exact), at their offset
    // in the developed flank (contact::developed_offset_mm).
    class HalfSpaceFlankCompliance : public contact::FlankCompliance
    {
    public:
      HalfSpaceFlankCompliance(const Material &material, const double depth_mm,
                               const double base_radius_mm, const double half_cell_u_mm,
                               const double half_cell_z_mm)
        : material(material), depth(depth_mm), r_b(base_radius_mm), hu(half_cell_u_mm)
        , hz(half_cell_z_mm)
      {}
      double compliance_mm_per_N(const contact::FlankPoint &reading, const contact::FlankPoint &load) const override
      {
        if (reading.tooth != load.tooth)
          return 0.0;
        const Eigen::Vector2d offset = contact::developed_offset_mm(reading, load, r_b);
        return half_space::rectangle_displacement_at_depth(offset.x(), offset.y(), depth, hu, hz,
                                                           1.0 / (4.0 * hu * hz),
                                                           material.youngs_modulus_MPa,
                                                           material.poisson_ratio);
      }
      double reference_depth_mm() const override { return depth; }

    private:
      Material material;
      double            depth, r_b, hu, hz;
    };

    // Pieces of one case: FE settings and the closed forms to compare with.
    struct CaseSetup
    {
      int                            dim = 3;
      fem::ResolvedContactSettings   fe;
      double                         contact_modulus = 0;
      // Closed forms.
      double a_x = 0, a_y = 0, p0 = 0, approach = 0; // a_y = 0: line contact
      bool   line = false;
      double load_per_length = 0; // line contacts
      double roller_half_length = 0; // finite-cylinder
      // Per reading depth: the closed-form compression between surface and depth, and its name.
      std::vector<std::pair<std::string, double>> depth_references;
      // Extra rows computed once per level from the FE compression at a depth: (quantity,
      // closed form, index of the reading depth).
      struct Extra
      {
        std::string  quantity;
        double       closed_form;
        unsigned int depth_index;
      };
      std::vector<Extra> extras;
      std::string        notes;
    };

    unsigned int depth_index(std::vector<double> &depths, const double d)
    {
      for (unsigned int k = 0; k < depths.size(); ++k)
        if (std::abs(depths[k] - d) <= 1e-12 * d)
          return k;
      depths.push_back(d);
      return static_cast<unsigned int>(depths.size() - 1);
    }

    std::string depth_name(const double d)
    {
      std::ostringstream os;
      os << "compression_to_depth_" << d << "mm";
      return os.str();
    }

    CaseSetup make_case(const ValidationScene &v, const bool coarse)
    {
      CaseSetup c;
      auto     &f                    = c.fe;
      f.youngs_modulus_MPa           = v.youngs_modulus_MPa;
      f.poisson_ratio                = v.poisson_ratio;
      f.radius_x_mm                  = v.radius_x_mm;
      f.radius_y_mm                  = v.radius_y_mm;
      f.half_width_x_mm              = v.half_width_x_mm;
      f.half_width_y_mm              = v.half_width_y_mm;
      f.depth_mm                     = v.depth_mm;
      f.reading_depths_mm            = v.reading_depths_mm;
      f.initial_cells_per_semi_axis  = static_cast<unsigned int>(v.initial_cells_per_semi_axis);
      f.n_levels                     = static_cast<unsigned int>(coarse ? v.ci_levels : v.levels);
      f.kelly_fraction               = v.kelly_fraction;
      f.max_active_set_iterations    = static_cast<unsigned int>(v.max_active_set_iterations);
      const Material rigid{1e300, 0.0};

      if (v.kind == "crowned-flank")
        {
          const Scene                   scene = load_scene(v.gear_scene);
          const meshing::PairKinematics kin   = make_pair(scene);
          const auto                    C     = kin.point('C');
          const Material &m1 = scene.pinion_material, &m2 = scene.gear_material;
          HG_REQUIRE_INPUT(std::abs(m1.poisson_ratio - m2.poisson_ratio) < 1e-12 &&
                             std::abs(m1.youngs_modulus_MPa - m2.youngs_modulus_MPa) <=
                               1e-12 * m1.youngs_modulus_MPa,
                           v.file.string(), ": the crowned-flank check models both bodies by one "
                           "equivalent body, exact for equal materials only; the gear scene has "
                           "different pinion and gear materials");
          const double rc1 = kin.pinion().crowning_radius_mm();
          const double rc2 = kin.gear().crowning_radius_mm();
          HG_REQUIRE_INPUT(std::isfinite(rc1) || std::isfinite(rc2), v.gear_scene.string(),
                           ": the crowned-flank check needs crowning on at least one gear");
          f.radius_x_mm = C.rho_pinion_mm * C.rho_gear_mm / (C.rho_pinion_mm + C.rho_gear_mm);
          f.radius_y_mm = 1.0 / ((std::isfinite(rc1) ? 1.0 / rc1 : 0.0) +
                                 (std::isfinite(rc2) ? 1.0 / rc2 : 0.0));
          const double E_star = hertz::contact_modulus(m1, m2);
          f.poisson_ratio      = m1.poisson_ratio;
          f.youngs_modulus_MPa = E_star * (1 - f.poisson_ratio * f.poisson_ratio);
          f.load = scene.operating.torque_Nm * 1.0e3 / kin.pinion().base_radius_mm();
          f.half_width_y_mm =
            0.5 * std::min(scene.pinion.face_width_mm, scene.gear.face_width_mm);
          f.contact_may_reach_y_end = true;

          // The TCA's reference depth (the FE source's rule, stiffness/fe_tca.h).
          const double depth = stiffness::fe_reference_depth_mm(stiffness_input(scene).fe,
                                                                kin.pinion().module_mm());
          HG_REQUIRE_INPUT(depth < f.depth_mm, v.file.string(), ": Body/depth_mm = ", f.depth_mm,
                           " must exceed the TCA reference depth ", depth, " mm");
          const unsigned int k = depth_index(f.reading_depths_mm, depth);

          // The hybrid at the pitch point with an ideal structural part: each body's "FE"
          // compliance at the reference depth is the exact half-space one (Boussinesq-Love, the
          // uniform pressure of a grid cell read at depth d). The total compliance is then the
          // half-space surface compliance, the TCA's pressure is Hertz's on its grid, and
          // hertz_penetration_mm is exactly the TCA's local part (surface minus depth d) of that
          // pressure: the quantity the resolved FE contact checks. With rigid bodies instead, the
          // local part alone would couple cells only within about d and the pressure would not
          // be Hertz's (also reported, for the record).
          contact::MeshCycleSettings cs;
          cs.profile_cells          = static_cast<unsigned int>(scene.stiffness.contact_grid_profile_points);
          cs.face_cells             = static_cast<unsigned int>(scene.stiffness.contact_grid_face_points);
          cs.hertz_exponent         = scene.stiffness.hertz_exponent;
          cs.plane_strain           = false;
          cs.max_contact_iterations = static_cast<unsigned int>(scene.stiffness.contact_max_iterations);
          const Material &b1 = m1, &b2 = m2;
          const contact::RigidFlankCompliance rigid_body(depth);
          const contact::MeshCycle rigid_cycle(kin, b1, b2, rigid_body, rigid_body, cs);
          const double w     = rigid_cycle.band_half_width(f.load);
          const double face  = std::min(kin.pinion().face_width_mm(), kin.gear().face_width_mm());
          const HalfSpaceFlankCompliance hs1(b1, depth, kin.pinion().base_radius_mm(),
                                             w / cs.profile_cells, 0.5 * face / cs.face_cells);
          const HalfSpaceFlankCompliance hs2(b2, depth, kin.gear().base_radius_mm(),
                                             w / cs.profile_cells, 0.5 * face / cs.face_cells);
          const contact::MeshCycle cycle(kin, b1, b2, hs1, hs2, cs);
          const double tau = (C.roll_distance_mm - kin.point('A').roll_distance_mm) / kin.base_pitch_mm();
          const auto pair_0 = [&](const contact::PositionResult &pos) {
            for (const auto &p : pos.pairs)
              if (p.pair == 0)
                {
                  HG_REQUIRE_NUMERIC(p.load_share > 0.999, "the pitch point is not in single "
                                     "tooth contact in ", v.gear_scene.string());
                  return p;
                }
            throw NumericalError("tooth pair 0 is not in contact at the pitch point");
          };
          const contact::PositionResult pos   = cycle.solve_position(tau, f.load);
          const contact::PairState      pair0 = pair_0(pos);
          const contact::PairState      rigid = pair_0(rigid_cycle.solve_position(tau, f.load));
          c.extras.push_back({"penetration_vs_tca_hybrid", pair0.hertz_penetration_mm, k});
          std::ostringstream notes;
          notes << std::setprecision(6) << "rho_1 " << C.rho_pinion_mm << " mm, rho_2 "
                << C.rho_gear_mm << " mm, R_x " << f.radius_x_mm << " mm, crowning radii "
                << rc1 << ", " << rc2 << " mm, R_y " << f.radius_y_mm << " mm, F " << f.load
                << " N, E* " << E_star << " MPa, reference depth " << depth
                << " mm; TCA grid " << pos.n_cells << " cells: a " << pair0.contact_a_mm
                << " mm, b " << pair0.contact_b_mm << " mm, p0 " << pair0.peak_pressure_MPa
                << " MPa, local penetration " << pair0.hertz_penetration_mm
                << " mm; with rigid bodies (local part only): a " << rigid.contact_a_mm
                << " mm, b " << rigid.contact_b_mm << " mm, p0 " << rigid.peak_pressure_MPa
                << " MPa, local penetration " << rigid.hertz_penetration_mm << " mm";
          c.notes = notes.str();
        }

      c.contact_modulus = f.youngs_modulus_MPa / (1 - f.poisson_ratio * f.poisson_ratio);
      const Material body{f.youngs_modulus_MPa, f.poisson_ratio};
      if (v.kind == "cylinder-2d" || v.kind == "finite-cylinder")
        {
          c.line = true;
          c.dim  = v.kind == "cylinder-2d" ? 2 : 3;
          f.radius_y_mm = 0;
          if (c.dim == 2)
            {
              c.load_per_length = v.load_per_length_N_per_mm;
              f.load            = c.load_per_length;
            }
          else
            {
              f.load = v.load_N;
              // The roller's length: the elastic body's (it ends), or the rigid roller's on
              // a wider elastic raceway.
              const double half_length  = v.roller_half_length_mm > 0 ? v.roller_half_length_mm :
                                                                        f.half_width_y_mm;
              f.contact_may_reach_y_end = v.roller_half_length_mm == 0;
              f.rigid_end_y_mm          = v.roller_half_length_mm;
              c.roller_half_length      = half_length;
              c.load_per_length         = v.load_N / (2.0 * half_length);
            }
          const auto lc = hertz::line_contact(c.load_per_length, f.radius_x_mm, c.contact_modulus);
          c.a_x      = lc.half_width;
          c.p0       = lc.peak_pressure;
          f.design_semi_axis_x_mm = c.a_x;
          f.design_semi_axis_y_mm = c.dim == 3 ? c.roller_half_length : c.a_x;
          // Weber & Banaschek: compression between the surface and depth h, one body (the other
          // rigid). The formula holds only below the contact (depth > half-width); a load that
          // large leaves the modelled surface anyway, which the FE solve reports (exit 3).
          // Entries stay aligned with the reading depths; NaN marks "no closed form".
          const auto weber = [&](const double d) {
            return d > c.a_x ? hertz::line_approach_weber(c.load_per_length, c.a_x, d, body, 1.0, rigid) :
                               std::numeric_limits<double>::quiet_NaN();
          };
          for (const double d : std::vector<double>(f.reading_depths_mm))
            c.depth_references.push_back({depth_name(d) + "_weber", weber(d)});
          if (c.dim == 3)
            {
              // A roller of radius R: its axis lies at depth R. Johnson's axis approach and
              // Palmgren's empirical total approach against the FE compression to that depth.
              const unsigned int k = depth_index(f.reading_depths_mm, f.radius_x_mm);
              if (k == c.depth_references.size())
                c.depth_references.push_back(
                  {depth_name(f.radius_x_mm) + "_weber", weber(f.radius_x_mm)});
              c.extras.push_back({"axis_approach_vs_johnson",
                                  hertz::line_approach_johnson(c.load_per_length, f.radius_x_mm,
                                                               body, 1e300, rigid),
                                  k});
              c.extras.push_back({"axis_approach_vs_palmgren",
                                  hertz::line_approach_palmgren_mm(f.load, 2.0 * c.roller_half_length,
                                                                   c.contact_modulus),
                                  k});
            }
        }
      else
        {
          c.dim = 3;
          if (v.kind == "sphere")
            {
              f.radius_y_mm = f.radius_x_mm;
              f.load        = v.load_N;
              const auto cc = hertz::circular_contact(f.load, f.radius_x_mm, c.contact_modulus);
              c.a_x = c.a_y = cc.semi_major;
              c.p0          = cc.peak_pressure;
              c.approach    = cc.approach;
            }
          else
            {
              if (v.kind == "ellipsoid")
                f.load = v.load_N;
              const auto ec = hertz::elliptical_contact(f.load, 1.0 / f.radius_x_mm,
                                                        1.0 / f.radius_y_mm, c.contact_modulus);
              c.a_x      = ec.major_axis_along_x ? ec.semi_major : ec.semi_minor;
              c.a_y      = ec.major_axis_along_x ? ec.semi_minor : ec.semi_major;
              c.p0       = ec.peak_pressure;
              c.approach = ec.approach;
            }
          f.design_semi_axis_x_mm = c.a_x;
          f.design_semi_axis_y_mm = c.a_y;
          for (const double d : std::vector<double>(f.reading_depths_mm))
            c.depth_references.push_back(
              {depth_name(d), c.approach - hertz_displacement_at_depth(c.p0, c.a_x, c.a_y, d,
                                                                       f.youngs_modulus_MPa,
                                                                       f.poisson_ratio)});
        }
      return c;
    }

    void add_level_rows(Study &study, const std::string &name, const CaseSetup &c,
                        const fem::ResolvedContactLevel &l)
    {
      const auto add = [&](const std::string &q, const double closed, const double fe) {
        study.rows.push_back({name, q, closed, fe, l.level, l.n_dofs, l.wall_time_s, l.contact_cell_mm});
      };
      add(c.line ? "half_width" : "semi_axis_x", c.a_x, l.semi_axis_x_mm);
      add(c.line ? "half_width_active_set" : "semi_axis_x_active_set", c.a_x, l.active_semi_axis_x_mm);
      if (!c.line)
        {
          add("semi_axis_y", c.a_y, l.semi_axis_y_mm);
          add("semi_axis_y_active_set", c.a_y, l.active_semi_axis_y_mm);
        }
      add("peak_pressure", c.p0, l.peak_pressure_MPa);
      if (!c.line)
        add("approach_of_block", c.approach, l.approach_mm);
      for (std::size_t k = 0; k < c.depth_references.size(); ++k)
        if (!std::isnan(c.depth_references[k].second))
          add(c.depth_references[k].first, c.depth_references[k].second, l.depth_approach_mm[k]);
      for (const auto &e : c.extras)
        add(e.quantity, e.closed_form, l.depth_approach_mm[e.depth_index]);
      if (c.line && c.dim == 3)
        {
          // Hertz's line contact has the same peak pressure all along; a roller of finite length
          // does not (end relief or end peaks): the largest nodal pressure along the roller.
          double p_max = 0;
          for (const auto &p : l.profile_y)
            p_max = std::max(p_max, p.pressure_MPa);
          add("max_pressure_along_length", c.p0, p_max);
        }
      add("total_force", c.line && c.dim == 2 ? c.load_per_length : c.fe.load, l.total_force);
    }

    void add_profiles(Study &study, const std::string &name, const CaseSetup &c,
                      const fem::ResolvedContactLevel &l)
    {
      const auto hertz_x = [&](const double x) {
        const double t = 1 - x * x / (c.a_x * c.a_x);
        return t > 0 ? c.p0 * std::sqrt(t) : 0.0;
      };
      const auto hertz_y = [&](const double y) {
        if (c.line)
          return (c.dim == 2 || y <= c.roller_half_length * (1 + 1e-12)) ? c.p0 : 0.0;
        const double t = 1 - y * y / (c.a_y * c.a_y);
        return t > 0 ? c.p0 * std::sqrt(t) : 0.0;
      };
      study.profiles << std::setprecision(10);
      for (const auto &p : l.profile_x)
        if (p.coordinate_mm <= 2.0 * c.a_x)
          study.profiles << name << ",x," << p.coordinate_mm << ',' << p.pressure_MPa << ','
                         << hertz_x(p.coordinate_mm) << '\n';
      for (const auto &p : l.profile_y)
        if (c.line || p.coordinate_mm <= 2.0 * c.a_y)
          study.profiles << name << ",y," << p.coordinate_mm << ',' << p.pressure_MPa << ','
                         << hertz_y(p.coordinate_mm) << '\n';
    }

    std::vector<fs::path> case_files(const CommandContext &ctx, const std::string &only)
    {
      if (!ctx.scene_file.empty())
        return {fs::path(ctx.scene_file)};
      const fs::path dir = fs::path(HERTZGEAR_SOURCE_DIR) / "data" / "scenes" / "validation";
      HG_REQUIRE_INPUT(fs::is_directory(dir), "the validation scenes folder ", dir.string(),
                       " does not exist");
      std::vector<fs::path> files;
      for (const auto &e : fs::directory_iterator(dir))
        if (e.path().extension() == ".prm" && e.path().stem().string().rfind("bad_", 0) != 0)
          files.push_back(e.path());
      std::sort(files.begin(), files.end());
      if (only.empty())
        return files;
      std::string names;
      for (const auto &f : files)
        {
          if (f.stem() == only)
            return {f};
          names += (names.empty() ? "" : ", ") + f.stem().string();
        }
      throw InputError(msg("--case ", only, ": no such validation case (available: ", names, ")"));
    }

    std::string rates_table(const std::vector<Row> &rows)
    {
      // Observed rates between successive levels of one case and quantity: against the number
      // of DOFs and against the contact cell size.
      std::ostringstream out;
      out << "case,quantity,level,dofs,relative_error,rate_dofs,rate_h\n" << std::setprecision(6);
      for (std::size_t i = 0; i < rows.size(); ++i)
        {
          const Row   &r = rows[i];
          const double e = std::abs((r.fe - r.closed_form) / r.closed_form);
          double       rate_dofs = NAN, rate_h = NAN;
          for (std::size_t j = i; j-- > 0;)
            if (rows[j].case_name == r.case_name && rows[j].quantity == r.quantity &&
                rows[j].level + 1 == r.level)
              {
                const double e0 = std::abs((rows[j].fe - rows[j].closed_form) / rows[j].closed_form);
                rate_dofs = std::log(e0 / e) / std::log(double(r.dofs) / double(rows[j].dofs));
                rate_h    = std::log(e0 / e) / std::log(rows[j].contact_cell_mm / r.contact_cell_mm);
                break;
              }
          out << r.case_name << ',' << r.quantity << ',' << r.level << ',' << r.dofs << ',' << e
              << ',' << rate_dofs << ',' << rate_h << '\n';
        }
      return out.str();
    }

    int run_validate_hertz(const CommandContext &ctx, const std::string &only, const bool coarse)
    {
      PhaseTimer            timer;
      std::vector<ValidationScene> scenes;
      {
        PhaseTimer::Scope scope(timer, "scenes");
        for (const auto &f : case_files(ctx, only))
          scenes.push_back(load_validation_scene(f, ctx.overrides));
      }
      Study study;
      study.profiles << "case,axis,coordinate_mm,fe_pressure_MPa,hertz_pressure_MPa\n";
      std::ostringstream used;
      for (const auto &v : scenes)
        {
          PhaseTimer::Scope scope(timer, v.name);
          const CaseSetup   c = make_case(v, coarse);
          if (!c.notes.empty())
            say(v.name + ": " + c.notes);
          say(msg(v.name, ": Hertz ", c.line ? "b " : "a_x ", c.a_x, " mm",
                  c.line ? std::string() : msg(", a_y ", c.a_y, " mm"), ", p0 ", c.p0, " MPa; block ",
                  c.fe.half_width_x_mm / c.a_x, " a_x wide, ", c.fe.depth_mm / c.a_x, " a_x deep"));
          const auto report = [&](const fem::ResolvedContactLevel &l) {
            add_level_rows(study, v.name, c, l);
            say(msg(v.name, " level ", l.level, ": ", l.n_dofs, " dofs, ", l.n_active,
                    " active nodes, ", l.n_iterations, " active-set iterations, contact cell ",
                    l.contact_cell_mm, " mm; ", c.line ? "b " : "a_x ",
                    percent(c.a_x, l.semi_axis_x_mm),
                    c.line ? std::string() : ", a_y " + percent(c.a_y, l.semi_axis_y_mm),
                    ", p0 ", percent(c.p0, l.peak_pressure_MPa), "  (", l.wall_time_s, " s)"));
          };
          const auto levels = c.dim == 2 ? fem::solve_resolved_contact<2>(c.fe, report) :
                                           fem::solve_resolved_contact<3>(c.fe, report);
          add_profiles(study, v.name, c, levels.back());
          used << "# ---- case " << v.name << " (" << v.file.string() << ")\n"
               << v.used_parameters_prm;
        }

      std::ostringstream csv;
      csv << "case,quantity,closed_form,fe,relative_error,level,dofs,wall_time_s\n"
          << std::setprecision(10);
      for (const auto &r : study.rows)
        csv << r.case_name << ',' << r.quantity << ',' << r.closed_form << ',' << r.fe << ','
            << (r.fe - r.closed_form) / r.closed_form << ',' << r.level << ',' << r.dofs << ','
            << r.wall_time_s << '\n';
      const std::string rates = rates_table(study.rows);
      if (is_root())
        {
          // Observed rates of the quantities of the acceptance, on stderr.
          std::istringstream in(rates);
          std::string        line;
          std::getline(in, line);
          while (std::getline(in, line))
            if (line.find(",semi_axis_x,") != std::string::npos ||
                line.find(",semi_axis_y,") != std::string::npos ||
                line.find(",half_width,") != std::string::npos ||
                line.find(",peak_pressure,") != std::string::npos)
              say("rate " + line);
        }

      if (is_root())
        {
          if (ctx.out_dir.empty())
            std::cout << csv.str();
          else
            {
              PhaseTimer::Scope scope(timer, "write");
              const fs::path    dir(ctx.out_dir);
              fs::create_directories(dir);
              write_file_atomically(dir / "hertz_validation.csv", csv.str());
              write_file_atomically(dir / "hertz_rates.csv", rates);
              write_file_atomically(dir / "pressure_profiles.csv", study.profiles.str());
              write_file_atomically(dir / "used_parameters.prm",
                                    "# " + ctx.command_line + "\n" + used.str());
              draw_figure("plot_hertz_validation.py", {dir.string()});
            }
          timer.print_summary(progress_stream());
        }
      return 0;
    }
  } // namespace

  void add_validation_commands(CommandRegistry &registry, CLI::App &top)
  {
    CLI::App *validate = command_group(top, "validate", "Validation studies against closed forms");
    auto only   = std::make_shared<std::string>();
    auto coarse = std::make_shared<bool>(false);
    CLI::App *hertz = registry.add_command(
      {"hertz",
       "Hertz closed forms and the TCA's local compliance against resolved FE contact "
       "(data/scenes/validation/, or the one SCENE given)",
       false, true},
      [only, coarse](const CommandContext &ctx) { return run_validate_hertz(ctx, *only, *coarse); },
      validate);
    hertz->add_option("--case", *only, "Run only this case (a file stem in data/scenes/validation)");
    hertz->add_flag("--coarse", *coarse, "Solve only the Refinement/ci_levels coarse levels");
  }
} // namespace hertzgear
