#include "fem/hertz_validation.h"

#include "common/errors.h"
#include "contact/half_space.h"
#include "contact/half_space_flank_compliance.h"
#include "contact/hertz.h"
#include "meshing/pair_kinematics.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>

namespace hertzgear::fem
{
  namespace
  {
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

    // The crowned-flank case: the paper pair's contact at its pitch point, one equivalent body.
    void crowned_flank_case(const HertzCaseInput &v, HertzCase &c)
    {
      auto &f = c.fe;
      const auto                   &g   = v.gear;
      const meshing::PairKinematics kin(g.pair);
      const auto                    C     = kin.point('C');
      const Material &m1 = g.pinion_material, &m2 = g.gear_material;
      HG_REQUIRE_INPUT(std::abs(m1.poisson_ratio - m2.poisson_ratio) < 1e-12 &&
                         std::abs(m1.youngs_modulus_MPa - m2.youngs_modulus_MPa) <=
                           1e-12 * m1.youngs_modulus_MPa,
                       v.name, ": the crowned-flank check models both bodies by one "
                       "equivalent body, exact for equal materials only; the gear scene has "
                       "different pinion and gear materials");
      const double rc1 = kin.pinion().crowning_radius_mm();
      const double rc2 = kin.gear().crowning_radius_mm();
      HG_REQUIRE_INPUT(std::isfinite(rc1) || std::isfinite(rc2), g.source,
                       ": the crowned-flank check needs crowning on at least one gear");
      f.radius_x_mm = C.rho_pinion_mm * C.rho_gear_mm / (C.rho_pinion_mm + C.rho_gear_mm);
      f.radius_y_mm = 1.0 / ((std::isfinite(rc1) ? 1.0 / rc1 : 0.0) +
                             (std::isfinite(rc2) ? 1.0 / rc2 : 0.0));
      const double E_star = hertz::contact_modulus(m1, m2);
      f.poisson_ratio      = m1.poisson_ratio;
      f.youngs_modulus_MPa = E_star * (1 - f.poisson_ratio * f.poisson_ratio);
      f.load = g.torque_Nm * 1.0e3 / kin.pinion().base_radius_mm();
      f.half_width_y_mm =
        0.5 * std::min(g.pair.pinion.face_width_mm, g.pair.gear.face_width_mm);
      f.contact_may_reach_y_end = true;

      const double depth = g.reference_depth_mm;
      HG_REQUIRE_INPUT(depth < f.depth_mm, v.name, ": Body/depth_mm = ", f.depth_mm,
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
      const contact::MeshCycleSettings &cs = g.grid;
      const Material &b1 = m1, &b2 = m2;
      const contact::RigidFlankCompliance rigid_body(depth);
      const contact::MeshCycle rigid_cycle(kin, b1, b2, rigid_body, rigid_body, cs);
      const double w     = rigid_cycle.band_half_width(f.load);
      const double face  = std::min(kin.pinion().face_width_mm(), kin.gear().face_width_mm());
      const contact::HalfSpaceFlankCompliance hs1(b1, depth, kin.pinion().flank(),
                                         w / cs.profile_cells, 0.5 * face / cs.face_cells);
      const contact::HalfSpaceFlankCompliance hs2(b2, depth, kin.gear().flank(),
                                         w / cs.profile_cells, 0.5 * face / cs.face_cells);
      const contact::MeshCycle cycle(kin, b1, b2, hs1, hs2, cs);
      const double tau = (C.roll_distance_mm - kin.point('A').roll_distance_mm) / kin.base_pitch_mm();
      const auto pair_0 = [&](const contact::PositionResult &pos) {
        for (const auto &p : pos.pairs)
          if (p.pair == 0)
            {
              HG_REQUIRE_NUMERIC(p.load_share > 0.999, "the pitch point is not in single "
                                 "tooth contact in ", g.source);
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

  } // namespace

  HertzCase make_hertz_case(const HertzCaseInput &v)
  {
    HertzCase c;
    c.fe     = v.fe;
    auto &f  = c.fe;
    const Material rigid{1e300, 0.0};

    if (v.kind == "crowned-flank")
      crowned_flank_case(v, c);

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
            {depth_name(d), c.approach - half_space::hertz_pressure_displacement_at_depth(c.p0, c.a_x, c.a_y, d,
                                                                     f.youngs_modulus_MPa,
                                                                     f.poisson_ratio)});
      }
    return c;
  }

void HertzValidationStudy::add_level(const std::string &name, const HertzCase &c,
                                     const ResolvedContactLevel &l)
  {
    const auto add = [&](const std::string &q, const double closed, const double fe) {
      rows.push_back({name, q, closed, fe, l.level, l.n_dofs, l.wall_time_s, l.contact_cell_mm});
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

void HertzValidationStudy::add_profiles(const std::string &name, const HertzCase &c,
                                        const ResolvedContactLevel &l)
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
    profiles << std::setprecision(10);
    for (const auto &p : l.profile_x)
      if (p.coordinate_mm <= 2.0 * c.a_x)
        profiles << name << ",x," << p.coordinate_mm << ',' << p.pressure_MPa << ','
                       << hertz_x(p.coordinate_mm) << '\n';
    for (const auto &p : l.profile_y)
      if (c.line || p.coordinate_mm <= 2.0 * c.a_y)
        profiles << name << ",y," << p.coordinate_mm << ',' << p.pressure_MPa << ','
                       << hertz_y(p.coordinate_mm) << '\n';
  }

  std::string HertzValidationStudy::results_csv() const
  {
    std::ostringstream csv;
    csv << "case,quantity,closed_form,fe,relative_error,level,dofs,wall_time_s\n"
        << std::setprecision(10);
    for (const auto &r : rows)
      csv << r.case_name << ',' << r.quantity << ',' << r.closed_form << ',' << r.fe << ','
          << (r.fe - r.closed_form) / r.closed_form << ',' << r.level << ',' << r.dofs << ','
          << r.wall_time_s << '\n';
    return csv.str();
  }

std::string HertzValidationStudy::rates_csv() const
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

  namespace
  {
    // The FE value's deviation from the closed form, "+1.234 %".
    std::string percent(const double closed, const double fe)
    {
      std::ostringstream os;
      os << std::showpos << std::fixed << std::setprecision(3) << 100.0 * (fe - closed) / closed
         << " %";
      return os.str();
    }
  } // namespace

  void HertzValidationStudy::run_case(const HertzCaseInput                           &input,
                                      const std::function<void(const std::string &)> &say)
  {
    const std::string &name = input.name;
    const HertzCase    c    = make_hertz_case(input);
    if (!c.notes.empty())
      say(name + ": " + c.notes);
    say(msg(name, ": Hertz ", c.line ? "b " : "a_x ", c.a_x, " mm",
            c.line ? std::string() : msg(", a_y ", c.a_y, " mm"), ", p0 ", c.p0, " MPa; block ",
            c.fe.half_width_x_mm / c.a_x, " a_x wide, ", c.fe.depth_mm / c.a_x, " a_x deep"));
    const auto report = [&](const ResolvedContactLevel &l) {
      add_level(name, c, l);
      say(msg(name, " level ", l.level, ": ", l.n_dofs, " dofs, ", l.n_active, " active nodes, ",
              l.n_iterations, " active-set iterations, contact cell ", l.contact_cell_mm, " mm; ",
              c.line ? "b " : "a_x ", percent(c.a_x, l.semi_axis_x_mm),
              c.line ? std::string() : ", a_y " + percent(c.a_y, l.semi_axis_y_mm), ", p0 ",
              percent(c.p0, l.peak_pressure_MPa), "  (", l.wall_time_s, " s)"));
    };
    const auto levels = c.dim == 2 ? solve_resolved_contact<2>(c.fe, report) :
                                     solve_resolved_contact<3>(c.fe, report);
    add_profiles(name, c, levels.back());
  }

  std::vector<std::string> HertzValidationStudy::acceptance_rates() const
  {
    std::vector<std::string> lines;
    std::istringstream       in(rates_csv());
    std::string              line;
    std::getline(in, line); // the header
    while (std::getline(in, line))
      if (line.find(",semi_axis_x,") != std::string::npos ||
          line.find(",semi_axis_y,") != std::string::npos ||
          line.find(",half_width,") != std::string::npos ||
          line.find(",peak_pressure,") != std::string::npos)
        lines.push_back(line);
    return lines;
  }
} // namespace hertzgear::fem
