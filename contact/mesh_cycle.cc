#include "contact/mesh_cycle.h"

#include "common/errors.h"
#include "contact/half_space.h"
#include "contact/hertz.h"
#include "meshing/flank_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace hertzgear::contact
{
  namespace
  {
    // Cells of a pair that lie beyond a tip or below the form circle of either flank carry no
    // load: they get this gap [mm], far larger than any elastic approach.
    constexpr double no_flank_gap_mm = 1.0e3;

    // Relative curvature of the two flanks along the face [1/mm]: the sum of their lead crowning
    // curvatures (0 uncrowned: line contact).
    double face_curvature_per_mm(const meshing::PairKinematics &kin)
    {
      double k = 0;
      for (unsigned int body = 0; body < 2; ++body)
        {
          const double rc = kin.body(body).crowning_radius_mm();
          if (std::isfinite(rc) && rc > 0)
            k += 1.0 / rc;
        }
      return k;
    }

    // Hertz's elliptical contact of the whole load on one pair at the pitch point (crowned
    // flanks: kappa_face > 0). load_N along the transverse line of action; a helical flank's
    // normal curvature across the contact line is the transverse one times cos(beta_b) and the
    // normal force load_N / cos(beta_b) (both exact no-ops for a spur pair).
    hertz::EllipticalContact pitch_point_ellipse(const meshing::PairKinematics &kin,
                                                 const Material m[2], const double load_N,
                                                 const double kappa_face)
    {
      const auto   c = kin.point('C');
      const double E = hertz::contact_modulus(m[0], m[1]);
      const double R = hertz::effective_radius(c.rho_pinion_mm, c.rho_gear_mm);
      const double cb = kin.cos_base_helix();
      return hertz::elliptical_contact(load_N / cb, cb / R, kappa_face, E);
    }

    // Contact half-width across the profile of the whole load on one pair at the pitch point,
    // from Hertz: line contact when uncrowned, elliptical when crowned (whichever is wider).
    double hertz_half_width_mm(const meshing::PairKinematics &kin, const Material m[2],
                               const double load_N)
    {
      // Helical: the normal load load_N / cos(beta_b) on a line of length b / cos(beta_b) is
      // load_N / b per length, and the normal radius is the transverse one / cos(beta_b).
      const auto   c    = kin.point('C');
      const double E    = hertz::contact_modulus(m[0], m[1]);
      const double R    = hertz::effective_radius(c.rho_pinion_mm, c.rho_gear_mm) / kin.cos_base_helix();
      const double b    = std::min(kin.pinion().face_width_mm(), kin.gear().face_width_mm());
      double       half = hertz::line_contact(load_N / b, R, E).half_width;
      const double kappa_face = face_curvature_per_mm(kin);
      if (kappa_face > 0)
        {
          const auto ell = pitch_point_ellipse(kin, m, load_N, kappa_face);
          half           = std::max(half, ell.major_axis_along_x ? ell.semi_major : ell.semi_minor);
        }
      return half;
    }
  } // namespace

  struct MeshCycle::Grid
  {
    std::vector<int>    pairs;     // pair index per block
    std::vector<double> roll_mm;   // contact-line pinion roll per block, at mid-face
    // The band centre of each face column, block-major: the contact line's roll at the column's
    // z (s_j + slope z; spur: roll_mm of the block in every column), and whether it lies on the
    // path of contact (extended by extended_contact_pitches): a column whose line lies beyond it
    // carries no load, as a spur pair beyond it is not on the grid.
    std::vector<double> column_roll_mm;
    std::vector<bool>   column_in_path;
    unsigned int        n_u = 0, n_z = 0;
    double              du = 0, dz = 0, face_width = 0;
    // Face extent of the cells [mm] (the whole face: -face_width/2 .. face_width/2), and whether
    // its ends are the face's ends.
    double              z_min = 0, z_max = 0;
    bool                z_min_is_face_end = true, z_max_is_face_end = true;
    // The middle of face column iz [mm].
    double column_z(const unsigned int iz) const { return z_min + (iz + 0.5) * dz; }
    // per cell (block-major, then i_u + n_u * i_z as half_space::ContactGrid numbers them)
    std::vector<int>        cell_block;
    std::vector<FlankPoint> pinion_point, gear_point;
    std::vector<double>     u_mm, z_mm;
    // Width of each cell across the profile [mm]: du, or less for a cell cut at a flank end
    // (cut_at_flank_ends).
    std::vector<double>     cell_du;
    bool                    cut_at_flank_ends = false;
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
    // Spur or helical: a helical pair's band follows its inclined contact lines column by column
    // (build_grid), the contact problem is normal to the flanks and the load and approach are
    // along the transverse line of action (docs/theory-tca.md, "Helical pairs on the contact
    // grid").
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

  bool MeshCycle::face_band_follows_load() const
  {
    // A spur pair's crowned contact only: a helical pair's contacts lie along inclined lines
    // whose smallest gap moves along the face with the line, which a band around the vertex of
    // the lead gap does not follow (docs/theory-tca.md, "Helical pairs").
    return !settings.plane_strain && settings.face_extent == MeshCycleSettings::FaceExtent::load &&
           kinematics.helix_angle_rad() == 0 && face_curvature_per_mm(kinematics) > 0;
  }

  MeshCycle::FaceBand MeshCycle::face_band(const double load_N) const
  {
    // The grid's face extent follows the load where the contact is a point contact, for the
    // same reason as the band across the profile does: a grid whose cells keep their size while
    // the contact grows lets the contact's edges cross cell boundaries one by one, and each
    // crossing changes the discretisation error in a step (on the paper's crowned pair over the
    // whole face with 16 cells: log-log slopes of the Hertzian part 0.83-0.87 up to 1166 N, 1.78
    // to 1296 N, then 0.41-0.55; docs/theory-tca.md). A band that scales with the contact keeps
    // the contact on about the same cells at every load, so that error is smooth in the load.
    //  - Scale: b, Hertz's semi-axis along the face of the whole load on one pair at the pitch
    //    point, the same contact whose other semi-axis sets the band across the profile. It grows
    //    as F^(1/3), as the contact does; the structural compliance lengthens the loaded zone
    //    beyond b (on the crowned paper pair 0.85-1.2 b from 2 to 400 % of the nominal load),
    //    hence c = face_band_semi_axes = 2 by default: the contact then spans about half the
    //    band's cells (8 of 16; 3 a across the profile puts it on 8 of 24).
    //  - Centre: where the unloaded gap along the face is smallest. The gap separates into a
    //    profile part and a lead part (lead modifications of both flanks and the misalignment,
    //    PairKinematics::lead_gap_mm), so that place is the same for every pair and position.
    //  - Clipped to the face: a band that would leave it ends at the face end, and from the load
    //    at which c b reaches half the face width on (about 280 % of the nominal load on the
    //    crowned paper pair) the band is the whole face, the face-width grid.
    // Where the contact still reaches an inner edge of the band (misalignment, relieved ends, a
    // load carried by one pair far beyond b), solve_position enlarges the band and solves again.
    const double half_face = 0.5 * kinematics.face_width_mm();
    const double kappa     = face_curvature_per_mm(kinematics);
    if (!face_band_follows_load())
      return {-half_face, half_face};
    const auto   ell    = pitch_point_ellipse(kinematics, materials, load_N, kappa);
    const double b_face = ell.major_axis_along_x ? ell.semi_minor : ell.semi_major;
    const double centre = kinematics.smallest_lead_gap_mm().first;
    const double half   = settings.face_band_semi_axes * b_face;
    return {std::max(-half_face, centre - half), std::min(half_face, centre + half)};
  }

  bool MeshCycle::on_extended_path(const double roll_mm) const
  {
    const double ext = settings.extended_contact_pitches * kinematics.base_pitch_mm();
    return roll_mm >= kinematics.point('A').roll_distance_mm - ext - 1e-12 &&
           roll_mm <= kinematics.point('E').roll_distance_mm + ext + 1e-12;
  }

  MeshCycle::Grid MeshCycle::grid_frame(const double mesh_phase, const double w, const FaceBand &face) const
  {
    Grid         g;
    const double p_b    = kinematics.base_pitch_mm();
    const auto  &pinion = kinematics.pinion();
    const auto  &gear   = kinematics.gear();
    const double slope  = kinematics.contact_line_slope(); // 0 spur
    g.face_width        = std::min(pinion.face_width_mm(), gear.face_width_mm());
    g.n_u               = settings.profile_cells;
    g.n_z               = settings.plane_strain ? 1 : settings.face_cells;
    g.du                = 2.0 * w / g.n_u;
    const double tol    = 1e-9 * g.face_width;
    g.z_min             = std::max(face.min_mm, -0.5 * g.face_width);
    g.z_max             = std::min(face.max_mm, 0.5 * g.face_width);
    HG_REQUIRE_NUMERIC(g.z_max > g.z_min, "empty face band of the contact grid");
    g.z_min_is_face_end = g.z_min <= -0.5 * g.face_width + tol;
    g.z_max_is_face_end = g.z_max >= 0.5 * g.face_width - tol;
    g.dz                = (g.z_max - g.z_min) / g.n_z;

    // The pairs whose contact line lies on the (extended) path of contact in some face column of
    // the grid (spur: at its one roll s_j).
    const double reach   = std::abs(slope) * std::max(std::abs(g.z_min), std::abs(g.z_max));
    const int    n_reach = static_cast<int>(std::ceil(reach / p_b));
    for (int pair = -3 - n_reach; pair <= 3 + n_reach; ++pair)
      {
        const double s = kinematics.contact_roll_distance_mm(pair, mesh_phase);
        bool         any = on_extended_path(s);
        if (slope != 0)
          {
            any = false;
            for (unsigned int iz = 0; iz < g.n_z; ++iz)
              any = any || on_extended_path(kinematics.contact_roll_distance_mm(pair, mesh_phase, g.column_z(iz)));
          }
        if (any)
          {
            g.pairs.push_back(pair);
            g.roll_mm.push_back(s);
          }
      }
    return g;
  }

  unsigned int MeshCycle::grid_cells(const double mesh_phase, const double load_N) const
  {
    const Grid g = grid_frame(mesh_phase, band_half_width(load_N), face_band(load_N));
    return static_cast<unsigned int>(g.pairs.size()) * g.n_u * g.n_z;
  }

  MeshCycle::Grid MeshCycle::build_grid(const double mesh_phase, const double w,
                                        const FaceBand &face) const
  {
    Grid         g      = grid_frame(mesh_phase, w, face);
    const auto  &pinion = kinematics.pinion();
    const auto  &gear   = kinematics.gear();
    const double r_b1   = pinion.base_radius_mm();
    const double slope  = kinematics.contact_line_slope(); // 0 spur
    const double cos_bb = kinematics.cos_base_helix();     // 1 spur
    HG_REQUIRE_NUMERIC(!g.pairs.empty(), "no tooth pair in contact at mesh phase ", mesh_phase);
    for (const int pair : g.pairs)
      HG_REQUIRE_INPUT(compliances[0]->covers_tooth(pair) && compliances[1]->covers_tooth(-pair),
                       "tooth pair ", pair, " can be in contact at mesh phase ", mesh_phase,
                       " but its teeth are not in the FE compliance table; mesh more teeth per "
                       "sector ({teeth_per_sector})");
    for (unsigned int b = 0; b < g.pairs.size(); ++b)
      for (unsigned int iz = 0; iz < g.n_z; ++iz)
        {
          const double sc = slope == 0 ? g.roll_mm[b] :
                                         kinematics.contact_roll_distance_mm(g.pairs[b], mesh_phase,
                                                                             g.column_z(iz));
          g.column_roll_mm.push_back(sc);
          g.column_in_path.push_back(on_extended_path(sc));
        }

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
    // The cell's area on the flank: du dz / cos(beta_b), the helicoid's area element in (U, z)
    // (FlankSurface::developed_offset_mm; exactly du dz for a spur flank).
    g.area.setConstant(n, g.du * g.dz / cos_bb);
    // Where the band follows the load (face_band_follows_load), a cell that a flank end crosses
    // (a tip, or the form circle, of either flank) is cut at it: the cell keeps its part on the
    // flanks, its point moves to that part's middle and its area shrinks with it. The cells
    // scale with the load while the flank ends stay put, so a cell kept or dropped whole by its
    // centre would enter and leave the grid in steps as the load grows (the contact of a pair
    // at a tip: docs/theory-tca.md, "Face extent of the grid"); a cut cell changes with the load
    // continuously. Elsewhere a cell is on the flanks where its centre is.
    g.cut_at_flank_ends = face_band_follows_load();
    for (unsigned int b = 0; b < g.pairs.size(); ++b)
      for (unsigned int iz = 0; iz < g.n_z; ++iz)
        {
          const double z  = g.column_z(iz);
          const double sc = g.column_roll_mm[b * g.n_z + iz];
          // Pinion and gear roll of the flank point at surface distance u across the profile
          // (the involute arc length from the base circle is s^2 / (2 r_b): inverted exactly),
          // and whether both flanks are there.
          const auto at = [&](const double u, double &s, double &sg) {
            const double s2 = sc * sc + 2.0 * r_b1 * u;
            s               = std::sqrt(std::max(s2, 0.0));
            sg              = kinematics.gear_roll_at_mm(g.pairs[b], mesh_phase, s, z);
            return g.column_in_path[b * g.n_z + iz] && s2 > 0 && s >= pinion_roll_min &&
                   s <= pinion_roll_max && sg >= gear_roll_min && sg <= gear_roll_max;
          };
          // The flanks' common extent along u is one interval; its end between a (on) and c
          // (off) by bisection to round-off.
          const auto flank_end = [&](double a, double c) {
            double ds, dsg;
            for (int it = 0; it < 200 && std::abs(c - a) > 1e-15 * (std::abs(a) + std::abs(c) + g.du); ++it)
              {
                const double m = 0.5 * (a + c);
                (at(m, ds, dsg) ? a : c) = m;
              }
            return a;
          };
          for (unsigned int iu = 0; iu < g.n_u; ++iu)
            {
              double u = -w + (iu + 0.5) * g.du; // surface distance across the profile
              double s = 0, sg = 0, width = g.du;
              bool   on_flanks = at(u, s, sg);
              if (g.cut_at_flank_ends)
                {
                  // A cell with one end on the flanks and one off is cut at the flanks' end.
                  double       lo = -w + iu * g.du, hi = lo + g.du, ds, dsg;
                  const bool   on_lo = at(lo, ds, dsg), on_hi = at(hi, ds, dsg);
                  if (on_lo != on_hi)
                    {
                      const double edge = on_lo ? flank_end(lo, hi) : flank_end(hi, lo);
                      if (on_lo)
                        hi = edge;
                      else
                        lo = edge;
                      width     = hi - lo;
                      u         = 0.5 * (lo + hi);
                      on_flanks = width > 1e-9 * g.du && at(u, s, sg);
                      if (on_flanks)
                        g.area(b * n_block + iu + g.n_u * iz) = width * g.dz / cos_bb;
                      else
                        width = g.du;
                    }
                  else if (!on_lo)
                    on_flanks = false; // no part of the cell on both flanks
                }
              const unsigned int k = b * n_block + iu + g.n_u * iz;
              g.cell_block.push_back(static_cast<int>(b));
              g.u_mm.push_back(u);
              g.z_mm.push_back(z);
              g.cell_du.push_back(width);
              g.pinion_point.push_back({g.pairs[b], s, z});
              g.gear_point.push_back({-g.pairs[b], sg, z});
              g.on_flank.push_back(on_flanks);
              // Normal to the flanks (PairKinematics::unloaded_gap_mm), as the compliances.
              g.gap(k) = on_flanks ? kinematics.unloaded_gap_mm(g.pairs[b], mesh_phase, s, z) :
                                     no_flank_gap_mm;
            }
        }

    // Local part: per pair, both bodies, surface minus reference depth (the FE counts the rest).
    const double depth = compliances[0]->reference_depth_mm();
    g.local            = Eigen::MatrixXd::Zero(n, n);
    const meshing::FlankSurface flank = pinion.flank();
    const bool same_material = materials[0].youngs_modulus_MPa == materials[1].youngs_modulus_MPa &&
                               materials[0].poisson_ratio == materials[1].poisson_ratio;
    // The local displacement at cell i per unit pressure on cell j (same pair), a rectangle of
    // the flank's area width_j x dz / cos(beta_b) about j's point: offsets in the developed
    // pinion flank (FlankSurface::developed_offset_mm; (du, dz) on a spur flank). A centred
    // rectangle's field is even in the offset, so entry (j, i) differs from (i, j) only by j's
    // and i's widths.
    const auto local_entry = [&](const unsigned int ki, const unsigned int kj) {
      const Eigen::Vector2d d =
        slope == 0 ? Eigen::Vector2d(g.u_mm[ki] - g.u_mm[kj], g.z_mm[ki] - g.z_mm[kj]) :
                     flank.developed_offset_mm(g.pinion_point[ki], g.pinion_point[kj]);
      const double hu = 0.5 * g.cell_du[kj], hz = 0.5 * g.dz / cos_bb;
      double       c  = 0;
      for (unsigned int body = 0; body < (same_material ? 1u : 2u); ++body)
        {
          const double E  = materials[body].youngs_modulus_MPa;
          const double nu = materials[body].poisson_ratio;
          c += half_space::rectangle_displacement_at_depth(d.x(), d.y(), 0.0, hu, hz, 1.0, E, nu) -
               half_space::rectangle_displacement_at_depth(d.x(), d.y(), depth, hu, hz, 1.0, E, nu);
        }
      return same_material ? 2 * c : c;
    };
    if (slope == 0)
      {
        // Spur: the cells of every pair form one regular grid in (u, z), the development of the
        // extruded involute.
        const auto grid = half_space::ContactGrid::covering(-w, w, g.z_min, g.z_max, g.n_u, g.n_z);
        Eigen::MatrixXd block = Eigen::MatrixXd::Zero(n_block, n_block);
        for (unsigned int body = 0; body < 2; ++body)
          {
            const double E  = materials[body].youngs_modulus_MPa;
            const double nu = materials[body].poisson_ratio;
            block += half_space::influence_matrix(grid, 0.0, E, nu) -
                     half_space::influence_matrix(grid, depth, E, nu);
          }
        for (unsigned int b = 0; b < g.pairs.size(); ++b)
          g.local.block(b * n_block, b * n_block, n_block, n_block) = block;
        // Cells cut at a flank end: their rows and columns from their own rectangles.
        for (unsigned int k = 0; k < n; ++k)
          if (g.cell_du[k] != g.du)
            {
              const unsigned int first = g.cell_block[k] * n_block;
              for (unsigned int i = first; i < first + n_block; ++i)
                {
                  g.local(i, k) = local_entry(i, k);
                  g.local(k, i) = local_entry(k, i);
                }
            }
      }
    else
      {
        // Helical: the columns are shifted against each other along the profile (each on its
        // inclined contact line), so the offsets between cells are taken in the developed
        // pinion flank, each cell a rectangle there (a development of the cell to first order).
        // The block is symmetric where the two cells are equally wide: each such pair of cells
        // is evaluated once, and once for both bodies when they are of one material.
        for (unsigned int b = 0; b < g.pairs.size(); ++b)
          for (unsigned int i = 0; i < n_block; ++i)
            for (unsigned int j = i; j < n_block; ++j)
              {
                const unsigned int ki = b * n_block + i, kj = b * n_block + j;
                g.local(ki, kj)       = local_entry(ki, kj);
                g.local(kj, ki) = g.cell_du[ki] == g.cell_du[kj] ? g.local(ki, kj) : local_entry(kj, ki);
              }
      }

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
    // The normal force on the flanks: load_N is along the transverse line of action.
    problem.load       = load_N / kinematics.cos_base_helix();
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
      // Along u a neighbour may be a cell cut at a flank end, whose point is nearer: the
      // parabola through the three points at their own abscissae.
      const auto correct_u = [&](const unsigned int minus, const unsigned int plus) {
        if (g.cell_du[minus] == g.cell_du[peak] && g.cell_du[plus] == g.cell_du[peak])
          return correct(true, minus, plus);
        if (pressure(minus) <= 0 || pressure(plus) <= 0)
          return;
        const double xm = g.u_mm[minus] - g.u_mm[peak], xp = g.u_mm[plus] - g.u_mm[peak];
        const double dm = (value(minus) - f0) / xm, dp = (value(plus) - f0) / xp;
        const double c2 = (dp - dm) / (xp - xm); // f = f0 + c1 x + c2 x^2
        const double c1 = dm - c2 * xm;
        if (c2 < 0)
          centre -= c1 * c1 / (4 * c2);
      };
      if (iu > 0 && iu + 1 < g.n_u)
        correct_u(peak - 1, peak + 1);
      correct(iz > 0 && iz + 1 < g.n_z, peak - g.n_u, peak + g.n_u);
      return centre;
    }
  } // namespace

  PositionResult MeshCycle::solve_position(const double mesh_phase, const double load_N) const
  {
    HG_REQUIRE_INPUT(load_N > 0, "the mesh load must be positive ({torque_Nm} > 0), got ",
                     load_N, " N");
    // The grid of a load and the contact on it. The contact must not be truncated by the grid's
    // face band: a loaded cell in a band's outermost column whose edge is not a face end means
    // the band cut the contact short. The band then grows by half about its centre (clipped to
    // the face) and the load is solved again; a whole-face band is never enlarged, so
    // face_end_contact keeps meaning the real face end.
    struct Solved
    {
      std::optional<Grid> grid;
      ContactSolution     sol;
      unsigned int        enlargements = 0;
    };
    const auto solve_on_own_grid = [&](const double load) {
      Solved       out;
      FaceBand     face = face_band(load);
      const double w    = band_half_width(load);
      for (;;)
        {
          out.grid.emplace(build_grid(mesh_phase, w, face));
          out.sol        = solve_contact(*out.grid, load);
          const auto &gg = *out.grid;
          bool cut_min = false, cut_max = false;
          for (unsigned int k = 0; k < gg.n_cells(); ++k)
            if (out.sol.pressure(k) > 0 && gg.n_z > 1)
              {
                const unsigned int iz = (k % (gg.n_u * gg.n_z)) / gg.n_u;
                cut_min = cut_min || (iz == 0 && !gg.z_min_is_face_end);
                cut_max = cut_max || (iz + 1 == gg.n_z && !gg.z_max_is_face_end);
              }
          if (!cut_min && !cut_max)
            return out;
          const double centre = 0.5 * (face.min_mm + face.max_mm);
          const double half   = 0.75 * (face.max_mm - face.min_mm);
          face                = {std::max(-0.5 * gg.face_width, centre - half),
                                 std::min(0.5 * gg.face_width, centre + half)};
          ++out.enlargements;
        }
    };
    // Helical pairs: the contact problem is normal to the flanks (gaps, compliances, pressures,
    // its approach); load_N and every approach and stiffness reported are along the transverse
    // line of action: a normal approach is delta_n / cos(beta_b) there (cos(beta_b) = 1 spur).
    const double           cos_bb  = kinematics.cos_base_helix();
    const Solved           at_load = solve_on_own_grid(load_N);
    const Grid            &g       = *at_load.grid;
    const ContactSolution &sol     = at_load.sol;

    PositionResult r;
    r.face_band_min_mm       = g.z_min;
    r.face_band_max_mm       = g.z_max;
    r.face_band_enlargements = at_load.enlargements;
    r.mesh_phase      = mesh_phase;
    // The kinematics put the smallest gap on the contact lines at 0; with profile modifications
    // the first point to touch may lie slightly off them, which the grid resolves: the unloaded
    // STE of the discrete flanks is the kinematic one plus the smallest cell gap.
    const double rigid = kinematics.rigid_approach_mm(mesh_phase);
    r.unloaded_ste_mm  = (rigid + g.gap.minCoeff()) / cos_bb;
    r.ste_mm           = (rigid + sol.approach) / cos_bb;
    r.approach_mm      = r.ste_mm - r.unloaded_ste_mm;
    r.n_cells         = g.n_cells();
    r.n_active        = sol.n_active();
    r.n_iterations    = sol.n_iterations;
    r.k_total_secant_N_per_mm = load_N / r.approach_mm;

    // Tangent stiffness by a central difference in the load. On a grid that stays put the
    // difference is taken on the grid of this load. Where the face band follows the load, the
    // elastic approach of a load is the one on that load's own grid (the load ladder and the
    // torque map are made of those), and so is the difference: on one fixed grid of a point
    // contact the active set hardly changes over +-2 % of the load, and the incremental
    // stiffness is that of the loaded cells as a flat punch, whose size lags the contact's by
    // up to a cell at each edge. On the crowned paper pair (3D, level 0, 16 face cells) that
    // made the fixed-grid tangent 5-7 % softer than the slope of the approach over the load at
    // the first position and 2-4 % at the fourth, while the slope over the load agreed with the
    // fixed-grid tangent of a 64-cell grid within that one's own scatter (docs/theory-tca.md).
    const double h = settings.tangent_step;
    if (!settings.tangent)
      r.k_total_tangent_N_per_mm = 0;
    else if (face_band_follows_load())
      {
        const auto approach_at = [&](const double load) {
          const Solved s = solve_on_own_grid(load);
          return (s.sol.approach - s.grid->gap.minCoeff()) / cos_bb;
        };
        r.k_total_tangent_N_per_mm =
          2.0 * h * load_N / (approach_at(load_N * (1 + h)) - approach_at(load_N * (1 - h)));
      }
    else
      {
        const double d_plus  = solve_contact(g, load_N * (1 + h)).approach;
        const double d_minus = solve_contact(g, load_N * (1 - h)).approach;
        r.k_total_tangent_N_per_mm = 2.0 * h * load_N / ((d_plus - d_minus) / cos_bb);
      }

    const unsigned int n_block = g.n_u * g.n_z;
    const Eigen::VectorXd local_displacement = g.local * sol.pressure;
    double weighted_penetration               = 0;
    for (unsigned int b = 0; b < g.pairs.size(); ++b)
      {
        PairState ps;
        ps.pair    = g.pairs[b];
        ps.roll_mm = g.roll_mm[b];
        // The cell of largest pressure, and the loaded cell of largest local displacement (the
        // deepest; where the Hertzian penetration is read, below).
        unsigned int peak = b * n_block, deepest = b * n_block;
        double       normal_force = 0; // on the flanks; its transverse part is the load's measure
        for (unsigned int k = b * n_block; k < (b + 1) * n_block; ++k)
          {
            normal_force += sol.pressure(k) * g.area(k);
            if (sol.pressure(k) > sol.pressure(peak))
              peak = k;
            if (sol.pressure(k) > 0 &&
                (sol.pressure(deepest) <= 0 || local_displacement(k) > local_displacement(deepest)))
              deepest = k;
          }
        ps.force_N    = normal_force * cos_bb;
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
            // The Hertzian penetration is the vertex of the local displacement, read about the
            // loaded cell where that displacement is largest. Inside a Hertz contact that is the
            // peak-pressure cell or its neighbour (the same vertex to the fit's error), but the
            // pressure can also peak in a single cell at the rim of the contact (a face column
            // with one or two loaded cells, where the contact ends on the grid), whose local
            // displacement is far below the centre's: anchored there, the Hertzian part of a
            // crowned helical pair halved between two loads (docs/theory-tca.md, "What each
            // position reports").
            ps.hertz_penetration_mm = value_at_contact_centre(
              g, b, deepest, sol.pressure, [&](const unsigned int k) { return local_displacement(k); }) /
              cos_bb;
            // Semi-axis across the profile from the force per length of the peak's face column,
            // for an elliptical (Hertz) distribution: F' = pi a p0 / 2.
            const unsigned int iz     = (peak - b * n_block) / g.n_u;
            double             column = 0;
            for (unsigned int iu = 0; iu < g.n_u; ++iu)
              column += sol.pressure(b * n_block + iu + g.n_u * iz) * g.cell_du[b * n_block + iu + g.n_u * iz];
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
            // (Both edges of the grid's face extent are then the face's ends: a band is enlarged
            // until the contact stays inside it.)
            const bool reaches_edges = z_first == 0 && z_last == static_cast<int>(g.n_z) - 1;
            // Both lengths on the flank (developed): the face extent over cos(beta_b), the normal force.
            ps.contact_b_mm = reaches_edges ?
                                0.5 * (g.z_max - g.z_min) / cos_bb :
                                3.0 * normal_force / (2.0 * M_PI * ps.contact_a_mm * ps.peak_pressure_MPa);
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
    r.k_rest_N_per_mm = settings.tangent ?
                          1.0 / (1.0 / r.k_total_tangent_N_per_mm - 1.0 / k_hertz_tangent) :
                          0.0;

    // Where the load sits (the columns of a torque map).
    double force = 0, moment = 0;
    for (unsigned int k = 0; k < g.n_cells(); ++k)
      {
        if (!(sol.pressure(k) > 0))
          continue;
        force += sol.pressure(k) * g.area(k);
        moment += sol.pressure(k) * g.area(k) * g.z_mm[k];
        const unsigned int local = k % n_block, iu = local % g.n_u, iz = local / g.n_u;
        if (g.n_z > 1 && ((iz == 0 && g.z_min_is_face_end) || (iz + 1 == g.n_z && g.z_max_is_face_end)))
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

  double MeshCycle::phase_of_position(const unsigned int i) const
  {
    return static_cast<double>(i) / settings.n_positions;
  }

  MeshCycleResult
  MeshCycle::run(const double load_N,
                 const std::function<void(unsigned int, const PositionResult &)> &progress) const
  {
    std::vector<PositionResult> positions;
    for (unsigned int i = 0; i < settings.n_positions; ++i)
      {
        positions.push_back(solve_position(phase_of_position(i), load_N));
        if (progress)
          progress(i, positions.back());
      }
    return assemble(load_N, std::move(positions));
  }

  MeshCycleResult MeshCycle::assemble(const double load_N, std::vector<PositionResult> positions) const
  {
    if (positions.size() != settings.n_positions)
      throw std::logic_error(msg("a mesh cycle of ", settings.n_positions,
                                 " positions cannot be assembled from ", positions.size()));
    MeshCycleResult result;
    result.load_N = load_N;
    result.band_half_width_mm = band_half_width(load_N);
    const auto face           = face_band(load_N);
    result.face_band_min_mm   = face.min_mm;
    result.face_band_max_mm   = face.max_mm;
    result.face_band_follows_load = face_band_follows_load();
    result.positions              = std::move(positions);

    std::vector<double> phase, k_h, k_t, ste;
    double              k_rest_sum = 0;
    for (const auto &p : result.positions)
      {
        phase.push_back(p.mesh_phase);
        k_h.push_back(p.k_hertz);
        k_t.push_back(p.k_total_secant_N_per_mm);
        ste.push_back(p.ste_mm);
        k_rest_sum += p.k_rest_N_per_mm;
      }
    result.k_hertz              = fit_fourier_series(phase, k_h, settings.n_harmonics);
    result.k_total              = fit_fourier_series(phase, k_t, settings.n_harmonics);
    result.ste_mm               = fit_fourier_series(phase, ste, settings.n_harmonics);
    result.mean_k_rest_N_per_mm = k_rest_sum / settings.n_positions;
    return result;
  }
} // namespace hertzgear::contact
