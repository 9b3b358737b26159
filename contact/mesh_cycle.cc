#include "contact/mesh_cycle.h"

#include "common/errors.h"
#include "contact/half_space.h"
#include "contact/hertz.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hertzgear::contact
{
  namespace
  {
    // Cells of a pair that lie beyond a tip or below the form circle of either flank carry no
    // load: they get this gap [mm], far larger than any elastic approach.
    constexpr double no_flank_gap_mm = 1.0e3;

    // Contact half-width across the profile of the whole load on one pair at the pitch point,
    // from Hertz: line contact when uncrowned, elliptical when crowned (whichever is wider).
    double hertz_half_width_mm(const meshing::PairKinematics &kin, const Material m[2],
                               const double load_N)
    {
      const auto   c    = kin.point('C');
      const double E    = hertz::contact_modulus(m[0], m[1]);
      const double R    = hertz::effective_radius(c.rho_pinion_mm, c.rho_gear_mm);
      const double b    = std::min(kin.pinion().face_width_mm(), kin.gear().face_width_mm());
      double       half = hertz::line_contact(load_N / b, R, E).half_width;
      const double kappa_face = [&] {
        double k = 0;
        for (unsigned int body = 0; body < 2; ++body)
          {
            const double rc = kin.body(body).crowning_radius_mm();
            if (std::isfinite(rc) && rc > 0)
              k += 1.0 / rc;
          }
        return k;
      }();
      if (kappa_face > 0)
        {
          const auto ell = hertz::elliptical_contact(load_N, 1.0 / R, kappa_face, E);
          half           = std::max(half, ell.major_axis_along_x ? ell.semi_major : ell.semi_minor);
        }
      return half;
    }
  } // namespace

  struct MeshCycle::Grid
  {
    std::vector<int>    pairs;     // pair index per block
    std::vector<double> roll_mm;   // contact-line pinion roll per block
    unsigned int        n_u = 0, n_z = 0;
    double              du = 0, dz = 0, face_width = 0;
    // per cell (block-major, then i_u + n_u * i_z as half_space::ContactGrid numbers them)
    std::vector<int>        cell_block;
    std::vector<FlankPoint> pinion_point, gear_point;
    std::vector<double>     u_mm, z_mm;
    std::vector<bool>       on_flank;
    Eigen::VectorXd         gap, area;
    Eigen::MatrixXd         compliance; // per unit pressure [mm/MPa]
    Eigen::MatrixXd         local;      // local part only (block diagonal)

    unsigned int n_cells() const { return static_cast<unsigned int>(cell_block.size()); }
  };

  MeshCycle::MeshCycle(const meshing::PairKinematics &kinematics,
                       const Material &pinion_material, const Material &gear_material,
                       const FlankCompliance &pinion_compliance,
                       const FlankCompliance &gear_compliance, const MeshCycleSettings &settings)
    : kinematics(kinematics)
    , materials{pinion_material, gear_material}
    , compliances{&pinion_compliance, &gear_compliance}
    , settings(settings)
  {
    HG_REQUIRE_INPUT(settings.n_positions >= 2 * settings.n_harmonics + 1,
                     "{positions_per_cycle} = ", settings.n_positions,
                     " is too few for {harmonics} = ", settings.n_harmonics,
                     "; a Fourier fit needs at least ", 2 * settings.n_harmonics + 1);
    HG_REQUIRE_INPUT(settings.profile_cells >= 4, "the contact grid needs at least 4 cells "
                                                  "across the profile, got ",
                     settings.profile_cells);
    HG_REQUIRE_INPUT(settings.face_cells >= 1, "the contact grid needs at least 1 face cell");
    HG_REQUIRE_INPUT(std::abs(pinion_compliance.reference_depth_mm() -
                              gear_compliance.reference_depth_mm()) < 1e-12,
                     "both bodies must read their compliance at the same reference depth");
  }

  double MeshCycle::band_half_width(const double load_N) const
  {
    return settings.band_half_width_mm > 0 ? settings.band_half_width_mm :
                                             3.0 * hertz_half_width_mm(kinematics, materials, load_N);
  }

  MeshCycle::Grid MeshCycle::build_grid(const double mesh_phase, const double w) const
  {
    Grid         g;
    const double s_A = kinematics.point('A').roll_distance_mm;
    const double s_E = kinematics.point('E').roll_distance_mm;
    const double p_b = kinematics.base_pitch_mm();
    const double ext = settings.extended_contact_pitches * p_b;
    for (int pair = -3; pair <= 3; ++pair)
      {
        const double s = kinematics.contact_roll_distance_mm(pair, mesh_phase);
        if (s >= s_A - ext - 1e-12 && s <= s_E + ext + 1e-12)
          {
            g.pairs.push_back(pair);
            g.roll_mm.push_back(s);
          }
      }
    HG_REQUIRE_NUMERIC(!g.pairs.empty(), "no tooth pair in contact at mesh phase ", mesh_phase);
    for (const int pair : g.pairs)
      HG_REQUIRE_INPUT(compliances[0]->covers_tooth(pair) && compliances[1]->covers_tooth(-pair),
                       "tooth pair ", pair, " can be in contact at mesh phase ", mesh_phase,
                       " but its teeth are not in the FE compliance table; mesh more teeth per "
                       "sector ({teeth_per_sector})");

    const auto  &pinion = kinematics.pinion();
    const auto  &gear   = kinematics.gear();
    const double r_b1   = pinion.base_radius_mm();
    g.face_width        = std::min(pinion.face_width_mm(), gear.face_width_mm());
    g.n_u               = settings.profile_cells;
    g.n_z               = settings.plane_strain ? 1 : settings.face_cells;
    g.du                = 2.0 * w / g.n_u;
    g.dz                = g.face_width / g.n_z;

    // Flank extents as roll distances: form circle to tip circle of each body.
    const auto roll_at = [](const meshing::GearGeometry &gg, const double radius) {
      return std::sqrt(std::max(0.0, radius * radius - gg.base_radius_mm() * gg.base_radius_mm()));
    };
    const double pinion_roll_min = roll_at(pinion, pinion.form_radius_mm());
    const double pinion_roll_max = roll_at(pinion, pinion.tip_radius_mm());
    const double gear_roll_min   = roll_at(gear, gear.form_radius_mm());
    const double gear_roll_max   = roll_at(gear, gear.tip_radius_mm());

    const unsigned int n_block = g.n_u * g.n_z;
    const unsigned int n       = n_block * static_cast<unsigned int>(g.pairs.size());
    g.gap.resize(n);
    g.area.setConstant(n, g.du * g.dz);
    for (unsigned int b = 0; b < g.pairs.size(); ++b)
      for (unsigned int iz = 0; iz < g.n_z; ++iz)
        for (unsigned int iu = 0; iu < g.n_u; ++iu)
          {
            const double u  = -w + (iu + 0.5) * g.du; // surface distance across the profile
            const double z  = -0.5 * g.face_width + (iz + 0.5) * g.dz;
            const double sc = g.roll_mm[b];
            // involute arc length from the base circle is s^2 / (2 r_b): invert it exactly
            const double s2 = sc * sc + 2.0 * r_b1 * u;
            const double s  = std::sqrt(std::max(s2, 0.0));
            const double sg = kinematics.gear_roll_at_mm(g.pairs[b], mesh_phase, s);
            const bool   on_flanks = s2 > 0 && s >= pinion_roll_min && s <= pinion_roll_max &&
                                   sg >= gear_roll_min && sg <= gear_roll_max;
            const unsigned int k = b * n_block + iu + g.n_u * iz;
            g.cell_block.push_back(static_cast<int>(b));
            g.u_mm.push_back(u);
            g.z_mm.push_back(z);
            g.pinion_point.push_back({g.pairs[b], s, z});
            g.gear_point.push_back({-g.pairs[b], sg, z});
            g.on_flank.push_back(on_flanks);
            g.gap(k) = on_flanks ? kinematics.unloaded_gap_mm(g.pairs[b], mesh_phase, s, z) :
                                   no_flank_gap_mm;
          }

    // Local part: per pair, both bodies, surface minus reference depth (the FE counts the rest).
    const double depth = compliances[0]->reference_depth_mm();
    const auto   grid  = half_space::ContactGrid::covering(-w, w, -0.5 * g.face_width,
                                                        0.5 * g.face_width, g.n_u, g.n_z);
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(n_block, n_block);
    for (unsigned int body = 0; body < 2; ++body)
      {
        const double E  = materials[body].youngs_modulus_MPa;
        const double nu = materials[body].poisson_ratio;
        block += half_space::influence_matrix(grid, 0.0, E, nu) -
                 half_space::influence_matrix(grid, depth, E, nu);
      }
    g.local = Eigen::MatrixXd::Zero(n, n);
    for (unsigned int b = 0; b < g.pairs.size(); ++b)
      g.local.block(b * n_block, b * n_block, n_block, n_block) = block;

    // Structural part of both bodies, per unit pressure on cell j (force = p A_j).
    g.compliance = g.local;
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        g.compliance(i, j) +=
          g.area(j) * (compliances[0]->compliance_mm_per_N(g.pinion_point[i], g.pinion_point[j]) +
                       compliances[1]->compliance_mm_per_N(g.gear_point[i], g.gear_point[j]));
    return g;
  }

  ContactSolution MeshCycle::solve_contact(const Grid &g, const double load_N) const
  {
    ContactProblem problem;
    problem.compliance = g.compliance;
    problem.gap        = g.gap;
    problem.area       = g.area;
    problem.load       = load_N;
    ContactSettings contact_settings;
    contact_settings.max_iterations = settings.max_contact_iterations;
    return ContactSolver(contact_settings).solve(problem);
  }

  namespace
  {
    // The vertex value of the separable quadratic through the cell `peak` of block b and its
    // loaded neighbours along u and z (a direction without two loaded neighbours, or without
    // curvature, contributes no correction).
    template <typename Grid, typename Value>
    double value_at_contact_centre(const Grid &g, const unsigned int b, const unsigned int peak,
                                   const Eigen::VectorXd &pressure, const Value &value)
    {
      const unsigned int n_block = g.n_u * g.n_z;
      const unsigned int local   = peak - b * n_block;
      const unsigned int iu = local % g.n_u, iz = local / g.n_u;
      const double       f0 = value(peak);
      double             centre = f0;
      const auto correct = [&](const bool inside, const unsigned int minus, const unsigned int plus) {
        if (!inside || pressure(minus) <= 0 || pressure(plus) <= 0)
          return;
        const double fm = value(minus), fp = value(plus);
        const double curvature = fm - 2 * f0 + fp;
        if (curvature < 0)
          centre -= (fm - fp) * (fm - fp) / (8 * curvature);
      };
      correct(iu > 0 && iu + 1 < g.n_u, peak - 1, peak + 1);
      correct(iz > 0 && iz + 1 < g.n_z, peak - g.n_u, peak + g.n_u);
      return centre;
    }
  } // namespace

  PositionResult MeshCycle::solve_position(const double mesh_phase, const double load_N) const
  {
    HG_REQUIRE_INPUT(load_N > 0, "the mesh load must be positive ({torque_Nm} > 0), got ",
                     load_N, " N");
    const Grid            g   = build_grid(mesh_phase, band_half_width(load_N));
    const ContactSolution sol = solve_contact(g, load_N);

    PositionResult r;
    r.mesh_phase      = mesh_phase;
    // The kinematics put the smallest gap on the contact lines at 0; with profile modifications
    // the first point to touch may lie slightly off them, which the grid resolves: the unloaded
    // STE of the discrete flanks is the kinematic one plus the smallest cell gap.
    const double rigid = kinematics.rigid_approach_mm(mesh_phase);
    r.unloaded_ste_mm  = rigid + g.gap.minCoeff();
    r.ste_mm           = rigid + sol.approach;
    r.approach_mm      = r.ste_mm - r.unloaded_ste_mm;
    r.n_cells         = g.n_cells();
    r.n_active        = sol.n_active();
    r.n_iterations    = sol.n_iterations;
    r.k_total_secant_N_per_mm = load_N / r.approach_mm;

    // Tangent stiffness by a central difference in the load.
    const double h      = settings.tangent_step;
    const double d_plus = solve_contact(g, load_N * (1 + h)).approach;
    const double d_minus = solve_contact(g, load_N * (1 - h)).approach;
    r.k_total_tangent_N_per_mm = 2.0 * h * load_N / (d_plus - d_minus);

    const unsigned int n_block = g.n_u * g.n_z;
    const Eigen::VectorXd local_displacement = g.local * sol.pressure;
    double weighted_penetration               = 0;
    for (unsigned int b = 0; b < g.pairs.size(); ++b)
      {
        PairState ps;
        ps.pair    = g.pairs[b];
        ps.roll_mm = g.roll_mm[b];
        unsigned int peak = b * n_block;
        for (unsigned int k = b * n_block; k < (b + 1) * n_block; ++k)
          {
            ps.force_N += sol.pressure(k) * g.area(k);
            if (sol.pressure(k) > sol.pressure(peak))
              peak = k;
          }
        ps.load_share = ps.force_N / load_N;
        if (ps.force_N > 0)
          {
            // The contact centre lies anywhere inside the peak cell. Inside a Hertz contact both
            // the local displacement (delta - A u^2 - B z^2) and the squared pressure
            // (p0^2 (1 - u^2/a^2 - z^2/b^2)) are quadratics with axes along u and z, so the
            // parabola through the peak cell and its loaded neighbours along each axis gives their
            // value at the centre exactly; reading the peak cell itself would be up to half a cell
            // off (3 % low in penetration on the paper's crowned flank at 24 x 16 cells).
            ps.peak_pressure_MPa =
              std::sqrt(value_at_contact_centre(g, b, peak, sol.pressure, [&](const unsigned int k) {
                return sol.pressure(k) * sol.pressure(k);
              }));
            ps.hertz_penetration_mm = value_at_contact_centre(
              g, b, peak, sol.pressure, [&](const unsigned int k) { return local_displacement(k); });
            // Semi-axis across the profile from the force per length of the peak's face column,
            // for an elliptical (Hertz) distribution: F' = pi a p0 / 2.
            const unsigned int iz     = (peak - b * n_block) / g.n_u;
            double             column = 0;
            for (unsigned int iu = 0; iu < g.n_u; ++iu)
              column += sol.pressure(b * n_block + iu + g.n_u * iz) * g.du;
            ps.contact_a_mm = 2.0 * column / (M_PI * ps.peak_pressure_MPa);
            // Along the face: the loaded extent; for an ellipse inside the face, from
            // F = 2/3 pi a b p0.
            int z_first = -1, z_last = -1;
            for (unsigned int jz = 0; jz < g.n_z; ++jz)
              {
                double row = 0;
                for (unsigned int iu = 0; iu < g.n_u; ++iu)
                  row += sol.pressure(b * n_block + iu + g.n_u * jz);
                if (row > 0)
                  {
                    if (z_first < 0)
                      z_first = static_cast<int>(jz);
                    z_last = static_cast<int>(jz);
                  }
              }
            const bool reaches_edges = z_first == 0 && z_last == static_cast<int>(g.n_z) - 1;
            ps.contact_b_mm = reaches_edges ?
                                0.5 * g.face_width :
                                3.0 * ps.force_N / (2.0 * M_PI * ps.contact_a_mm * ps.peak_pressure_MPa);
          }
        weighted_penetration += ps.load_share * ps.hertz_penetration_mm;
        r.pairs.push_back(ps);
      }
    const double n       = settings.hertz_exponent;
    r.hertz_penetration_mm = weighted_penetration;
    HG_REQUIRE_NUMERIC(weighted_penetration > 0, "no Hertzian penetration at mesh phase ",
                       mesh_phase, " (contact grid too coarse for the contact band?)");
    r.k_hertz = load_N / std::pow(weighted_penetration, n);
    // F = k_h d^n: dF/dd = n F / d.
    const double k_hertz_tangent = n * load_N / weighted_penetration;
    r.k_rest_N_per_mm            = 1.0 / (1.0 / r.k_total_tangent_N_per_mm - 1.0 / k_hertz_tangent);

    // Where the load sits (the columns of a torque map).
    double force = 0, moment = 0;
    for (unsigned int k = 0; k < g.n_cells(); ++k)
      {
        if (!(sol.pressure(k) > 0))
          continue;
        force += sol.pressure(k) * g.area(k);
        moment += sol.pressure(k) * g.area(k) * g.z_mm[k];
        const unsigned int local = k % n_block, iu = local % g.n_u, iz = local / g.n_u;
        if (g.n_z > 1 && (iz == 0 || iz + 1 == g.n_z))
          r.face_end_contact = true;
        if ((iu > 0 && !g.on_flank[k - 1]) || (iu + 1 < g.n_u && !g.on_flank[k + 1]))
          r.tip_contact = true;
      }
    r.contact_centre_z_mm = force > 0 ? moment / force : 0.0;

    r.cell_pair.reserve(g.n_cells());
    for (unsigned int k = 0; k < g.n_cells(); ++k)
      {
        r.cell_pair.push_back(g.pairs[g.cell_block[k]]);
        r.cell_u_mm.push_back(g.u_mm[k]);
        r.cell_z_mm.push_back(g.z_mm[k]);
        r.cell_pressure_MPa.push_back(sol.pressure(k));
        r.cell_pinion_roll_mm.push_back(g.pinion_point[k].roll_mm);
        r.cell_gear_roll_mm.push_back(g.gear_point[k].roll_mm);
        r.cell_area_mm2.push_back(g.area(k));
      }
    return r;
  }

  MeshCycleResult
  MeshCycle::run(const double load_N,
                 const std::function<void(unsigned int, const PositionResult &)> &progress) const
  {
    HG_REQUIRE_INPUT(load_N > 0, "the mesh load must be positive ({torque_Nm} > 0), got ",
                     load_N, " N");
    MeshCycleResult result;
    result.load_N = load_N;
    result.band_half_width_mm = band_half_width(load_N);

    std::vector<double> phase, k_h, k_t, ste;
    double              k_rest_sum = 0;
    for (unsigned int i = 0; i < settings.n_positions; ++i)
      {
        const double tau = static_cast<double>(i) / settings.n_positions;
        result.positions.push_back(solve_position(tau, load_N));
        const auto &p = result.positions.back();
        phase.push_back(tau);
        k_h.push_back(p.k_hertz);
        k_t.push_back(p.k_total_secant_N_per_mm);
        ste.push_back(p.ste_mm);
        k_rest_sum += p.k_rest_N_per_mm;
        if (progress)
          progress(i, p);
      }
    result.k_hertz              = fit_fourier_series(phase, k_h, settings.n_harmonics);
    result.k_total              = fit_fourier_series(phase, k_t, settings.n_harmonics);
    result.ste_mm               = fit_fourier_series(phase, ste, settings.n_harmonics);
    result.mean_k_rest_N_per_mm = k_rest_sum / settings.n_positions;
    return result;
  }
} // namespace hertzgear::contact
