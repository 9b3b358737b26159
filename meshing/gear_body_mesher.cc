// Every gmsh call of hertzgear lives in this file (built-in "geo" kernel: exact control of the
// points, deterministic, no OpenCASCADE needed).
#include "meshing/gear_body_mesher.h"
#include "meshing/pair_kinematics.h"

#include "common/atomic_file.h"
#include "common/errors.h"
#include "meshing/field_names.h"
#include "meshing/flank_surface.h"

#include <Eigen/Geometry>
#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace hertzgear::meshing
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
    int              n_live_meshers = 0;

    enum class Role
    {
      drive_flank,
      coast_flank,
      drive_fillet,
      coast_fillet,
      root,
      tip,
      bore,
      cut_start,
      cut_end
    };

    struct BoundaryCurve
    {
      int  tag;
      Role role;
      int  tooth;
      bool active; // part of the flank that carries contact (size field)
    };

    // Builds one body in the current gmsh model.
    class BodyBuilder
    {
    public:
      BodyBuilder(const GearGeometry &gear, const MeshSettings &settings, const double r_active)
        : g(gear), s(settings), r_active(r_active)
      {
        n_teeth = std::min(settings.teeth_per_sector, gear.n_teeth());
        // Physical tags 100 + k ... 400 + k must not overlap (the FE stage relies on them).
        HG_REQUIRE_INPUT(n_teeth <= 100, gear.parameters().name, ": ", n_teeth,
                         " teeth in one mesh; at most 100 (set {teeth_per_sector} <= 100)");
        full    = settings.teeth_per_sector >= gear.n_teeth();
        central = GearBodyMesher::central_tooth(n_teeth);
        z0      = settings.dimension == 3 ? -0.5 * gear.face_width_mm() : 0.0;
      }

      const GearGeometry       &g;
      const MeshSettings       &s;
      const double              r_active;
      int                       n_teeth = 0, central = 0;
      bool                      full = false;
      double                    z0   = 0;
      int                       origin = 0, surface = 0, volume = 0, top = 0;
      int                       cut_start_curve = 0, cut_end_curve = 0; // sector only
      double                    cut_angle_rad   = 0;
      std::vector<BoundaryCurve> curves;
      std::map<int, int>        lateral_of_curve; // 3D: curve tag -> extruded surface tag

      double tooth_angle(const int k) const { return (k - central) * g.angular_pitch_rad(); }

      int point(const Eigen::Vector2d &p) { return gmsh::model::geo::addPoint(p.x(), p.y(), z0); }
      int polar_point(const double radius, const double angle)
      {
        return point({radius * std::cos(angle), radius * std::sin(angle)});
      }

      // A spline through `pts` (rotated by `angle`, mirrored first if `mirror`), reusing the
      // given end point tags.
      int spline(std::vector<Eigen::Vector2d> pts, const bool mirror, const double angle,
                 const int first, const int last, const bool reverse)
      {
        if (mirror)
          for (auto &p : pts)
            p.y() = -p.y();
        if (reverse)
          std::reverse(pts.begin(), pts.end());
        std::vector<int> tags{first};
        for (std::size_t i = 1; i + 1 < pts.size(); ++i)
          tags.push_back(point(GearGeometry::rotate(pts[i], angle)));
        tags.push_back(last);
        return gmsh::model::geo::addSpline(tags);
      }

      void add(const int tag, const Role role, const int tooth = -1, const bool active = false)
      {
        curves.push_back({tag, role, tooth, active});
      }

      std::vector<Eigen::Vector2d> flank_points(const double u0, const double u1, const int n) const
      {
        std::vector<Eigen::Vector2d> pts;
        for (int i = 0; i <= n; ++i)
          pts.push_back(g.involute_point(u0 + (u1 - u0) * i / n));
        return pts;
      }

      void build()
      {
        namespace geo = gmsh::model::geo;
        origin        = geo::addPoint(0, 0, z0);
        const double r_f = g.root_radius_mm(), r_b = g.base_radius_mm();
        const double half_pitch = 0.5 * g.angular_pitch_rad();
        const double a1         = g.root_fillet_angle_rad();
        HG_REQUIRE_INPUT(half_pitch - a1 > 1e-9, g.parameters().name,
                         ": the fillets of neighbouring teeth meet on the root circle; meshing "
                         "needs a root arc between them (reduce the cutter tip radius, ",
                         field(g.parameters(), "cutter_tip_radius_coefficient"), ")");
        const double u_F = g.form_roll_angle(), u_a = g.tip_roll_angle();
        const double u_S = std::clamp(g.roll_angle_at_radius(std::max(r_active, r_b)), u_F, u_a);
        const bool   split = (u_S - u_F) > 1e-3 * (u_a - u_F);
        std::vector<Eigen::Vector2d> fillet;
        for (int i = 0; i <= 24; ++i)
          fillet.push_back(g.fillet_point(i / 24.0));
        const auto lower  = flank_points(u_F, u_S, 12);
        const auto active = flank_points(split ? u_S : u_F, u_a, 40);
        const double tip_angle = g.flank_polar_angle_rad(g.tip_radius_mm());

        std::vector<int> outer;
        const int first_space = polar_point(r_f, tooth_angle(0) - half_pitch);
        int       space       = first_space;
        for (int k = 0; k < n_teeth; ++k)
          {
            const double t = tooth_angle(k);
            // coast (-theta) side, counter-clockwise: root arc, fillet, flank, then the tip land
            const int fb_m   = polar_point(r_f, t - a1);
            const int form_m = point(GearGeometry::rotate({fillet.back().x(), -fillet.back().y()}, t));
            const int sap_m  = split ? point(GearGeometry::rotate({lower.back().x(), -lower.back().y()}, t)) : form_m;
            const int tip_m  = polar_point(g.tip_radius_mm(), t - tip_angle);
            const int tip_p  = polar_point(g.tip_radius_mm(), t + tip_angle);
            const int sap_p  = split ? point(GearGeometry::rotate(lower.back(), t)) : -1;
            const int form_p = point(GearGeometry::rotate(fillet.back(), t));
            const int fb_p   = polar_point(r_f, t + a1);
            const bool last  = k == n_teeth - 1;
            const int next_space = (last && full) ? first_space : polar_point(r_f, t + half_pitch);

            int c = geo::addCircleArc(space, origin, fb_m);
            add(c, Role::root), outer.push_back(c);
            c = spline(fillet, true, t, fb_m, form_m, false);
            add(c, Role::coast_fillet, k), outer.push_back(c);
            if (split)
              {
                c = spline(lower, true, t, form_m, sap_m, false);
                add(c, Role::coast_flank, k, false), outer.push_back(c);
              }
            c = spline(active, true, t, sap_m, tip_m, false);
            add(c, Role::coast_flank, k, true), outer.push_back(c);
            c = geo::addCircleArc(tip_m, origin, tip_p);
            add(c, Role::tip), outer.push_back(c);
            c = spline(active, false, t, tip_p, split ? sap_p : form_p, true);
            add(c, Role::drive_flank, k, true), outer.push_back(c);
            if (split)
              {
                c = spline(lower, false, t, sap_p, form_p, true);
                add(c, Role::drive_flank, k, false), outer.push_back(c);
              }
            c = spline(fillet, false, t, form_p, fb_p, true);
            add(c, Role::drive_fillet, k), outer.push_back(c);
            c = geo::addCircleArc(fb_p, origin, next_space);
            add(c, Role::root), outer.push_back(c);
            space = next_space;
          }

        const double r_bore = g.bore_radius_mm();
        HG_REQUIRE_INPUT(r_bore > 0 && r_bore < r_f - 0.1 * g.module_mm(), g.parameters().name,
                         ": meshing needs a bore (the body is clamped there) with a rim of at "
                         "least 0.1 m below the root circle: bore radius ", r_bore,
                         " mm, root radius ", r_f, " mm (", field(g.parameters(), "bore_radius_mm"), ")");
        if (full)
          {
            const int loop = geo::addCurveLoop(outer);
            std::vector<int> bore_pts, bore;
            for (int i = 0; i < 4; ++i)
              bore_pts.push_back(polar_point(r_bore, i * 0.5 * pi));
            for (int i = 0; i < 4; ++i)
              {
                const int c = geo::addCircleArc(bore_pts[i], origin, bore_pts[(i + 1) % 4]);
                add(c, Role::bore), bore.push_back(c);
              }
            const int hole = geo::addCurveLoop(bore);
            surface        = geo::addPlaneSurface({loop, hole});
          }
        else
          {
            const double a_start = tooth_angle(0) - half_pitch;
            const double a_end    = tooth_angle(n_teeth - 1) + half_pitch;
            const int    b_end    = polar_point(r_bore, a_end);
            int          c        = geo::addLine(space, b_end);
            add(c, Role::cut_end), outer.push_back(c);
            cut_end_curve = c;
            // Circle arcs of the built-in kernel must stay below pi: split the bore.
            const int n_pieces = int(std::ceil((a_end - a_start) / (0.5 * pi) - 1e-12));
            int       prev     = b_end;
            int       b_start  = -1;
            for (int i = 1; i <= n_pieces; ++i)
              {
                const int next = polar_point(r_bore, a_end - (a_end - a_start) * i / n_pieces);
                c              = geo::addCircleArc(prev, origin, next);
                add(c, Role::bore), outer.push_back(c);
                prev = b_start = next;
              }
            c = geo::addLine(b_start, first_space);
            add(c, Role::cut_start), outer.push_back(c);
            surface = geo::addPlaneSurface({geo::addCurveLoop(outer)});
            cut_start_curve = c;
            cut_angle_rad   = a_end - a_start;
          }

        if (s.dimension == 3)
          {
            const int n_layers = s.face_width_layers << s.refinement_level;
            gmsh::vectorpair out;
            geo::extrude({{2, surface}}, 0, 0, g.face_width_mm(), out, {n_layers}, {}, true);
            top    = out[0].second;
            volume = out[1].second;
          }
        geo::synchronize();
        if (!full)
          {
            // The end cut is the start cut turned by the sector angle, node for node: the cyclic
            // model ties the two faces DoF by DoF (3D: the extruded faces inherit the match).
            const double c = std::cos(cut_angle_rad), s_ = std::sin(cut_angle_rad);
            gmsh::model::mesh::setPeriodic(1, {cut_end_curve}, {cut_start_curve},
                                           {c, -s_, 0, 0, s_, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
          }
        if (s.dimension == 3)
          {
            std::vector<std::pair<int, int>> surfaces;
            gmsh::model::getEntities(surfaces, 2);
            for (const auto &[dim, tag] : surfaces)
              {
                if (tag == surface || tag == top)
                  continue;
                gmsh::vectorpair bnd;
                gmsh::model::getBoundary({{dim, tag}}, bnd, false, false, false);
                for (const auto &b : bnd)
                  lateral_of_curve[std::abs(b.second)] = tag;
              }
          }
      }

      void size_fields(const double scale)
      {
        namespace field = gmsh::model::mesh::field;
        const double f = scale * std::ldexp(1.0, -s.refinement_level) * g.module_mm();
        std::vector<double> active, fillets;
        for (const auto &c : curves)
          {
            if (c.active)
              active.push_back(c.tag);
            if (c.role == Role::drive_fillet || c.role == Role::coast_fillet)
              fillets.push_back(c.tag);
          }
        const double m = g.module_mm();
        field::add("Distance", 1);
        field::setNumbers(1, "CurvesList", active);
        field::setNumber(1, "NumPointsPerCurve", 200);
        field::add("Threshold", 2);
        field::setNumber(2, "InField", 1);
        field::setNumber(2, "SizeMin", s.band_size_modules * f);
        field::setNumber(2, "SizeMax", s.far_size_modules * f);
        field::setNumber(2, "DistMin", s.band_depth_modules * m);
        field::setNumber(2, "DistMax", s.band_depth_modules * m + 2 * s.far_size_modules * m);
        field::add("Distance", 3);
        field::setNumbers(3, "CurvesList", fillets);
        field::setNumber(3, "NumPointsPerCurve", 100);
        field::add("Threshold", 4);
        field::setNumber(4, "InField", 3);
        field::setNumber(4, "SizeMin", s.fillet_size_modules * f);
        field::setNumber(4, "SizeMax", s.far_size_modules * f);
        field::setNumber(4, "DistMin", 0.1 * m);
        field::setNumber(4, "DistMax", 0.1 * m + 2 * s.far_size_modules * m);
        field::add("Min", 5);
        field::setNumbers(5, "FieldsList", {2, 4});
        field::setAsBackgroundMesh(5);
      }

      void physical_groups(std::vector<std::string> &names)
      {
        const int dim = s.dimension - 1; // boundary entities
        std::map<std::string, std::pair<int, std::vector<int>>> groups; // name -> (tag, entities)
        auto entity = [&](const int curve) {
          return s.dimension == 2 ? curve : lateral_of_curve.at(curve);
        };
        for (const auto &c : curves)
          {
            std::string name;
            int         tag = 0;
            switch (c.role)
              {
                case Role::drive_flank: name = "drive_flank_" + std::to_string(c.tooth), tag = physical_tag::drive_flank + c.tooth; break;
                case Role::coast_flank: name = "coast_flank_" + std::to_string(c.tooth), tag = physical_tag::coast_flank + c.tooth; break;
                case Role::drive_fillet: name = "drive_fillet_" + std::to_string(c.tooth), tag = physical_tag::drive_fillet + c.tooth; break;
                case Role::coast_fillet: name = "coast_fillet_" + std::to_string(c.tooth), tag = physical_tag::coast_fillet + c.tooth; break;
                case Role::root: name = "root", tag = physical_tag::root; break;
                case Role::tip: name = "tip_land", tag = physical_tag::tip_land; break;
                case Role::bore: name = "bore", tag = physical_tag::bore; break;
                case Role::cut_start: name = "sector_cut_start", tag = physical_tag::sector_cut_start; break;
                case Role::cut_end: name = "sector_cut_end", tag = physical_tag::sector_cut_end; break;
              }
            groups[name].first = tag;
            groups[name].second.push_back(entity(c.tag));
          }
        if (s.dimension == 3)
          {
            groups["face_back"]  = {13, {surface}};
            groups["face_front"] = {14, {top}};
          }
        // Sorted by tag: a stable order in the file.
        std::vector<std::pair<int, std::string>> order;
        for (const auto &[name, group] : groups)
          order.emplace_back(group.first, name);
        std::sort(order.begin(), order.end());
        for (const auto &[tag, name] : order)
          {
            gmsh::model::addPhysicalGroup(dim, groups[name].second, tag);
            gmsh::model::setPhysicalName(dim, tag, name);
            names.push_back(name);
          }
        const int body = s.dimension == 2 ? surface : volume;
        gmsh::model::addPhysicalGroup(s.dimension, {body}, 1);
        gmsh::model::setPhysicalName(s.dimension, 1, "body");
        names.push_back("body");
      }
    };

    // Scaled Jacobian of a corner spanned by edge vectors (2D: signed area ratio).
    double corner_jacobian_2d(const Eigen::Vector3d &a, const Eigen::Vector3d &b)
    {
      return (a.x() * b.y() - a.y() * b.x()) / (a.norm() * b.norm());
    }
    double corner_jacobian_3d(const Eigen::Vector3d &a, const Eigen::Vector3d &b,
                              const Eigen::Vector3d &c)
    {
      return a.cross(b).dot(c) / (a.norm() * b.norm() * c.norm());
    }
  } // namespace

  GearBodyMesher::GearBodyMesher()
  {
    HG_REQUIRE_NUMERIC(n_live_meshers == 0, "only one GearBodyMesher may exist at a time");
    ++n_live_meshers;
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 1);
    gmsh::option::setNumber("General.NumThreads", 1); // deterministic
  }

  GearBodyMesher::~GearBodyMesher()
  {
    gmsh::finalize();
    --n_live_meshers;
  }

  namespace
  {
    // The twist check's quantities (require_layers_for_twist).
    struct TwistCheck
    {
      double layers = 0, d_psi = 0, h = 0, twist_sag = 0, section_sag = 0, needed = 0;
    };
    TwistCheck twist_check(const GearGeometry &gear, const MeshSettings &settings,
                           const double active_start_radius_mm)
    {
      // A helical body is the straight extrusion with every node turned by its section angle
      // psi(z): its layers are straight between the section planes, chords of the helices the
      // flank points follow. Their chord error, r Dpsi^2 / 8 at radius r for the twist Dpsi of
      // one layer, must stay within the chord error the section's own straight element edges
      // make on the active involute where it is most curved, h^2 / (8 rho) with h the band
      // element size and rho the involute's radius of curvature (its roll distance) at the start
      // of the active profile: the twist then adds no coarser geometry than the section already
      // has. Checked at the tip circle, where the helix's chord error is largest.
      TwistCheck         c;
      const FlankSurface flank = gear.flank();
      c.layers = settings.face_width_layers * std::ldexp(1.0, settings.refinement_level);
      c.d_psi  = std::abs(flank.section_angle_rad(gear.face_width_mm() / c.layers));
      c.h      = settings.band_element_size_mm(gear.module_mm());
      const double r_b = gear.base_radius_mm();
      const double rho = std::sqrt(std::max(active_start_radius_mm * active_start_radius_mm - r_b * r_b, 0.0));
      c.twist_sag   = gear.tip_radius_mm() * c.d_psi * c.d_psi / 8.0;
      c.section_sag = c.h * c.h / (8.0 * std::max(rho, 1e-3 * r_b));
      c.needed      = std::ceil(settings.face_width_layers * std::sqrt(c.twist_sag / c.section_sag) - 1e-9);
      return c;
    }
  } // namespace

  unsigned int layers_needed_for_twist(const GearGeometry &gear, const MeshSettings &settings,
                                       const double active_start_radius_mm)
  {
    if (settings.dimension != 3 || gear.helix_angle_rad() == 0)
      return 1;
    return static_cast<unsigned int>(std::max(1.0, twist_check(gear, settings, active_start_radius_mm).needed));
  }

  void require_layers_for_twist(const GearGeometry &gear, const MeshSettings &settings,
                                const double active_start_radius_mm)
  {
    if (settings.dimension != 3 || gear.helix_angle_rad() == 0)
      return;
    const TwistCheck c = twist_check(gear, settings, active_start_radius_mm);
    HG_REQUIRE_INPUT(c.twist_sag <= c.section_sag, gear.parameters().name, ": ", c.layers,
                     " hexahedral layers ({face_width_layers} = ", settings.face_width_layers,
                     " at refinement level ", settings.refinement_level, ") over the face width of ",
                     gear.face_width_mm(), " mm cannot carry the helix: a layer turns the section by ", c.d_psi,
                     " rad, its chord departs ", 1e3 * c.twist_sag,
                     " um from the helicoid at the tip circle, more than the section's own "
                     "flank chords (", 1e3 * c.section_sag, " um at band elements of ", c.h,
                     " mm); set {face_width_layers} >= ", c.needed, " (",
                     field(gear.parameters(), "helix_angle_rad"), ", ",
                     field(gear.parameters(), "face_width_mm"), ")");
  }

  void require_layers_for_twist(const PairKinematics &pair, const MeshSettings &settings)
  {
    const double r[2] = {pair.active_profile_start_radius_mm(0), pair.active_profile_start_radius_mm(1)};
    const unsigned int first =
      layers_needed_for_twist(pair.body(1), settings, r[1]) > layers_needed_for_twist(pair.body(0), settings, r[0]) ? 1 : 0;
    require_layers_for_twist(pair.body(first), settings, r[first]);
    require_layers_for_twist(pair.body(1 - first), settings, r[1 - first]);
  }

  MeshQuality GearBodyMesher::mesh(const GearGeometry &gear, const MeshSettings &settings,
                                   const double active_start_radius_mm,
                                   const std::filesystem::path &msh_file)
  {
    HG_REQUIRE_INPUT(settings.dimension == 2 || settings.dimension == 3,
                     "mesh dimension must be 2 or 3, not ", settings.dimension);
    HG_REQUIRE_INPUT(settings.teeth_per_sector >= 1, "teeth per sector must be >= 1");
    HG_REQUIRE_INPUT(settings.face_width_layers >= 1, "{face_width_layers} = ",
                     settings.face_width_layers, " is less than one layer");
    require_layers_for_twist(gear, settings, active_start_radius_mm);
    HG_REQUIRE_INPUT(settings.refinement_level >= 0 && settings.refinement_level <= 6,
                     "mesh refinement level ", settings.refinement_level, " is outside 0..6");

    MeshQuality q;
    q.dimension = settings.dimension;
    std::vector<BoundaryCurve> curves;
    int                        quad_type = settings.dimension == 2 ? 3 : 5; // quad4 / hex8
    BodyBuilder               *used      = nullptr;
    std::unique_ptr<BodyBuilder> builder;

    // deal.II needs quadrilaterals. First try: frontal-Delaunay triangulation recombined by the
    // "blossom full-quad" algorithm (gmsh 4.8's "frontal-Delaunay for quads" crashes with a
    // background size field; plain blossom leaves triangles where the fillet meets the involute
    // and the root arc). Should a triangle survive, mesh again with the all-quad subdivision at
    // twice the sizes (subdivision halves them again).
    for (const bool subdivide : {false, true})
      {
        gmsh::clear();
        gmsh::model::add(gear.parameters().name);
        gmsh::option::setNumber("Mesh.Algorithm", 6);
        gmsh::option::setNumber("Mesh.RecombineAll", 1);
        gmsh::option::setNumber("Mesh.RecombinationAlgorithm", 3);
        gmsh::option::setNumber("Mesh.SubdivisionAlgorithm", subdivide ? 1 : 0);
        gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
        gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
        gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
        gmsh::option::setNumber("Mesh.ElementOrder", 1);
        gmsh::option::setNumber("Mesh.MshFileVersion", 2.2);
        gmsh::option::setNumber("Mesh.Binary", 0);
        gmsh::option::setNumber("Mesh.SaveAll", 0);
        builder = std::make_unique<BodyBuilder>(gear, settings, active_start_radius_mm);
        builder->build();
        builder->size_fields(subdivide ? 2.0 : 1.0);
        q.physical_groups.clear();
        builder->physical_groups(q.physical_groups);
        gmsh::model::mesh::generate(settings.dimension);

        std::vector<int>                      types;
        std::vector<std::vector<std::size_t>> tags, nodes;
        gmsh::model::mesh::getElements(types, tags, nodes, settings.dimension, -1);
        std::size_t n_other = 0;
        for (std::size_t i = 0; i < types.size(); ++i)
          if (types[i] != quad_type)
            n_other += tags[i].size();
        q.subdivided      = subdivide;
        q.n_other_elements = n_other;
        if (n_other == 0)
          break;
      }
    used = builder.get();
    HG_REQUIRE_NUMERIC(q.n_other_elements == 0, gear.parameters().name, ": gmsh left ",
                       q.n_other_elements, " non-quadrilateral elements");

    // Exact flank and modifications, node by node.
    const BodyBuilder &b   = *used;
    const double       r_b = gear.base_radius_mm(), r_F = gear.form_radius_mm(),
                 r_f = gear.root_radius_mm(), r_a = gear.tip_radius_mm();
    const double half_pitch = 0.5 * gear.angular_pitch_rad();
    const double phi_F      = gear.flank_polar_angle_rad(r_F);
    const FlankSurface flank = gear.flank();
    std::map<std::size_t, int> flank_side; // node tag -> +1 drive, -1 coast
    for (const auto &c : b.curves)
      if (c.role == Role::drive_flank || c.role == Role::coast_flank)
        {
          std::vector<std::size_t> tags;
          std::vector<double>      xyz, par;
          const int dim = settings.dimension - 1;
          const int ent = settings.dimension == 2 ? c.tag : b.lateral_of_curve.at(c.tag);
          gmsh::model::mesh::getNodes(tags, xyz, par, dim, ent, true, false);
          for (const auto t : tags)
            flank_side[t] = c.role == Role::drive_flank ? 1 : -1;
        }
    std::vector<std::size_t> all_tags;
    std::vector<double>      all_xyz, all_par;
    gmsh::model::mesh::getNodes(all_tags, all_xyz, all_par, -1, -1, false, false);
    std::map<std::size_t, Eigen::Vector3d> coords;
    double max_error = 0;
    for (std::size_t i = 0; i < all_tags.size(); ++i)
      {
        Eigen::Vector3d x(all_xyz[3 * i], all_xyz[3 * i + 1], all_xyz[3 * i + 2]);
        const double    radius = std::hypot(x.x(), x.y());
        const double    theta  = std::atan2(x.y(), x.x());
        const long      k_rel  = std::lround(theta / gear.angular_pitch_rad());
        const double    t_k    = k_rel * gear.angular_pitch_rad();
        double          phi    = theta - t_k;
        const auto      side   = flank_side.find(all_tags[i]);
        const bool      on_flank = side != flank_side.end();
        double          r_node = radius;
        if (on_flank)
          {
            // The spline through analytic points is within ~1e-6 mm of the involute; put the
            // node on the involute itself at its radius.
            r_node = std::clamp(radius, r_F, r_a);
            phi    = side->second * gear.flank_polar_angle_rad(r_node);
          }
        if (settings.apply_modifications)
          {
            const double z     = x.z();
            const double xi    = r_node >= r_F ? r_b * gear.roll_angle_at_radius(r_node) : 0.0;
            const double delta = flank.transverse_removal_mm(xi, z);
            double       w     = 0; // -1 .. 1 across the tooth, 0 on the centre line
            if (r_node >= r_F)
              w = on_flank ? side->second : std::clamp(phi / gear.flank_polar_angle_rad(r_node), -1.0, 1.0);
            else if (std::abs(phi) <= phi_F)
              w = phi / phi_F;
            else
              w = (phi > 0 ? 1 : -1) * std::max(0.0, (half_pitch - std::abs(phi)) / (half_pitch - phi_F));
            const double h = r_node >= r_F ? 1.0 : std::clamp((r_node - r_f) / (r_F - r_f), 0.0, 1.0);
            phi -= delta / r_b * w * h;
            if (on_flank)
              {
                const double measured = r_b * (gear.flank_polar_angle_rad(r_node) - std::abs(phi));
                max_error = std::max(max_error, std::abs(measured - delta));
              }
          }
        // Helical: the section at z turned by psi(z) (exactly 0 for a spur gear, which keeps its
        // nodes bit for bit).
        const double          turn = t_k + phi + flank.section_angle_rad(x.z());
        const Eigen::Vector3d y(r_node * std::cos(turn), r_node * std::sin(turn), x.z());
        if ((y - x).norm() > 0)
          gmsh::model::mesh::setNode(all_tags[i], {y.x(), y.y(), y.z()}, {});
        coords[all_tags[i]] = y;
      }
    q.max_flank_modification_error_mm = max_error;

    // Quality: scaled Jacobian at every corner of every element.
    {
      std::vector<std::size_t> etags, enodes;
      gmsh::model::mesh::getElementsByType(quad_type, etags, enodes, -1);
      q.n_elements   = etags.size();
      // Nodes used by the elements (gmsh may keep unused ones from the full-quad split).
      q.n_nodes = std::set<std::size_t>(enodes.begin(), enodes.end()).size();
      double min_sj  = 1;
      const int  nn  = settings.dimension == 2 ? 4 : 8;
      for (std::size_t e = 0; e < etags.size(); ++e)
        {
          const std::size_t *n = &enodes[nn * e];
          if (settings.dimension == 2)
            for (int c = 0; c < 4; ++c)
              {
                const auto &p = coords[n[c]];
                min_sj = std::min(min_sj, corner_jacobian_2d(coords[n[(c + 1) % 4]] - p,
                                                             coords[n[(c + 3) % 4]] - p));
              }
          else
            {
              // Hexahedron corners: bottom 0-3, top 4-7 (gmsh order); edges from each corner
              // to its three neighbours, ordered to give a right-handed frame.
              static const int nb[8][3] = {{1, 3, 4}, {2, 0, 5}, {3, 1, 6}, {0, 2, 7},
                                           {7, 5, 0}, {4, 6, 1}, {5, 7, 2}, {6, 4, 3}};
              for (int c = 0; c < 8; ++c)
                {
                  const auto &p = coords[n[c]];
                  min_sj = std::min(min_sj, corner_jacobian_3d(coords[n[nb[c][0]]] - p,
                                                               coords[n[nb[c][1]]] - p,
                                                               coords[n[nb[c][2]]] - p));
                }
            }
        }
      q.min_scaled_jacobian = min_sj;
      std::vector<int>                      types;
      std::vector<std::vector<std::size_t>> tags, nodes;
      gmsh::model::mesh::getElements(types, tags, nodes, settings.dimension - 1, -1);
      for (const auto &t : tags)
        q.n_boundary_elements += t.size();
    }

    // Size in the contact band: edges along the active flank curves (transverse section).
    {
      double max_edge = 0, sum = 0;
      int    n_edges  = 0;
      for (const auto &c : b.curves)
        if (c.active)
          {
            std::vector<std::size_t> tags;
            std::vector<double>      xyz, par;
            gmsh::model::mesh::getNodes(tags, xyz, par, 1, c.tag, true, false);
            std::vector<std::pair<double, Eigen::Vector2d>> pts;
            for (const auto t : tags)
              {
                const auto &y = coords[t];
                pts.push_back({std::hypot(y.x(), y.y()), {y.x(), y.y()}});
              }
            std::sort(pts.begin(), pts.end(), [](const auto &l, const auto &r) { return l.first < r.first; });
            for (std::size_t i = 1; i < pts.size(); ++i)
              {
                const double d = (pts[i].second - pts[i - 1].second).norm();
                max_edge       = std::max(max_edge, d);
                sum += d, ++n_edges;
              }
          }
      q.contact_band_max_edge_mm  = max_edge;
      q.contact_band_mean_edge_mm = n_edges ? sum / n_edges : 0;
      q.contact_band_target_size_mm = settings.band_element_size_mm(gear.module_mm());
    }
    q.n_teeth_meshed = b.n_teeth;
    q.central_tooth  = b.central;
    q.full_gear      = b.full;

    produce_file_atomically(msh_file, [](const std::filesystem::path &tmp) {
      // gmsh picks the format from the extension: write "<tmp>.msh", then take its name.
      const std::filesystem::path with_ext = tmp.string() + ".msh";
      gmsh::write(with_ext.string());
      std::filesystem::rename(with_ext, tmp);
    });
    gmsh::clear();
    return q;
  }

  nlohmann::json mesh_quality_json(const MeshQuality &q)
  {
    return {{"dimension", q.dimension},
            {"elements", q.n_elements},
            {"nodes", q.n_nodes},
            {"boundary_elements", q.n_boundary_elements},
            {"non_quad_elements", q.n_other_elements},
            {"min_scaled_jacobian", q.min_scaled_jacobian},
            {"contact_band_target_size_mm", q.contact_band_target_size_mm},
            {"contact_band_max_edge_mm", q.contact_band_max_edge_mm},
            {"contact_band_mean_edge_mm", q.contact_band_mean_edge_mm},
            {"teeth_meshed", q.n_teeth_meshed},
            {"central_tooth", q.central_tooth},
            {"full_gear", q.full_gear},
            {"subdivided", q.subdivided},
            {"max_flank_modification_error_mm", q.max_flank_modification_error_mm},
            {"physical_groups", q.physical_groups}};
  }
} // namespace hertzgear::meshing
