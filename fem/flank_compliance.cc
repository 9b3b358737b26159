#include "fem/flank_compliance.h"

#include "common/errors.h"

#include <algorithm>
#include <cmath>

namespace hertzgear::fem
{
  template <int dim>
  unsigned int TabulatedFlankCompliance<dim>::node(const unsigned int tooth_index,
                                                   const unsigned int i_roll,
                                                   const unsigned int i_face) const
  {
    return (tooth_index * roll_nodes.size() + i_roll) * face_nodes.size() + i_face;
  }

  template <int dim>
  TabulatedFlankCompliance<dim>::TabulatedFlankCompliance(const BodyCompliance<dim>   &body,
                                                          const meshing::GearGeometry &gear,
                                                          const int                  central_tooth,
                                                          const FlankTableSettings  &settings)
    : geometry(&gear), flank(gear.flank()), settings(settings)
  {
    (void)central_tooth; // the body frame already centres the central tooth on +x
    std::vector<PatchLoad<dim>>    loads;
    std::vector<PointReading<dim>> readings;
    set_up_nodes(&loads, &readings);
    const dealii::FullMatrix<double> c = body.compliance(loads, readings);
    table.resize(c.m(), c.n());
    for (unsigned int i = 0; i < c.m(); ++i)
      for (unsigned int j = 0; j < c.n(); ++j)
        table(i, j) = c(i, j) * scale;
    finish(body.youngs_modulus(), body.poisson_ratio());
  }

  template <int dim>
  TabulatedFlankCompliance<dim>::TabulatedFlankCompliance(const Eigen::MatrixXd &raw,
                                                          const double youngs_modulus,
                                                          const double poisson_ratio,
                                                          const meshing::GearGeometry &gear,
                                                          const FlankTableSettings  &settings)
    : geometry(&gear), flank(gear.flank()), settings(settings)
  {
    set_up_nodes(nullptr, nullptr);
    HG_REQUIRE_INPUT(raw.rows() == static_cast<Eigen::Index>(node_points.size()) &&
                       raw.cols() == static_cast<Eigen::Index>(node_points.size()),
                     "flank table: a ", raw.rows(), " x ", raw.cols(), " table for ",
                     node_points.size(), " nodes");
    table = raw;
    finish(youngs_modulus, poisson_ratio);
  }

  template <int dim>
  void TabulatedFlankCompliance<dim>::set_up_nodes(std::vector<PatchLoad<dim>>    *loads,
                                                   std::vector<PointReading<dim>> *readings)
  {
    HG_REQUIRE_INPUT(settings.n_roll >= 2, "flank table: at least 2 roll nodes");
    HG_REQUIRE_INPUT(settings.roll_max_mm > settings.roll_min_mm,
                     "flank table: empty active profile (roll ", settings.roll_min_mm, " to ",
                     settings.roll_max_mm, " mm)");
    HG_REQUIRE_INPUT(settings.reference_depth_mm > settings.patch_radius_mm,
                     "flank table: the reference depth (", settings.reference_depth_mm,
                     " mm) must exceed the load patch radius (", settings.patch_radius_mm, " mm)");
    for (unsigned int i = 0; i < settings.n_roll; ++i)
      roll_nodes.push_back(settings.roll_min_mm + (settings.roll_max_mm - settings.roll_min_mm) *
                                                    i / (settings.n_roll - 1.0));
    const double b = geometry->face_width_mm();
    if (dim == 2)
      {
        face_nodes = {0.0};
        scale      = 1.0 / b;
      }
    else
      {
        HG_REQUIRE_INPUT(settings.n_face >= 2, "flank table: at least 2 face nodes in 3D");
        // Nodes inset by the patch radius so that each patch lies on the flank, and on a helical
        // flank also by the reading's axial drift: the inward normal has the axial component
        // sin(beta_b), so the reading point d below a node lies d sin(beta_b) nearer one face
        // end (0 for a spur flank, whose nodes are unchanged).
        const double cos_bb = flank.cos_base_helix();
        const double inset  = settings.patch_radius_mm +
                             settings.reference_depth_mm * std::sqrt(std::max(0.0, 1.0 - cos_bb * cos_bb));
        const double z0     = -0.5 * b + inset;
        for (unsigned int i = 0; i < settings.n_face; ++i)
          face_nodes.push_back(z0 + (b - 2 * inset) * i / (settings.n_face - 1.0));
      }
    HG_REQUIRE_INPUT(!settings.split_half_space || dim == 3,
                     "flank table: the half-space split is a 3D option");
    for (const int t : settings.teeth)
      for (const double roll : roll_nodes)
        for (const double z : face_nodes)
          {
            node_points.push_back({t, roll, z});
            if (loads == nullptr)
              continue;
            const PatchLoad<dim> load = patch_load({t, roll, z});
            PointReading<dim>    reading;
            reading.point     = load.centre + settings.reference_depth_mm * load.direction;
            reading.direction = load.direction;
            loads->push_back(load);
            readings->push_back(reading);
          }
  }

  template <int dim>
  void TabulatedFlankCompliance<dim>::finish(const double youngs_modulus, const double poisson_ratio)
  {
    interpolated = table;
    if (settings.split_half_space)
      {
        kernel = std::make_unique<half_space::PatchLoadKernel>(
          settings.reference_depth_mm, settings.patch_radius_mm, youngs_modulus, poisson_ratio);
        for (Eigen::Index i = 0; i < table.rows(); ++i)
          for (Eigen::Index j = 0; j < table.cols(); ++j)
            interpolated(i, j) -= half_space_part(node_points[i], node_points[j]);
      }
  }

  template <int dim>
  double TabulatedFlankCompliance<dim>::flank_distance_mm(const FlankPoint &a,
                                                          const FlankPoint &b) const
  {
    const Eigen::Vector2d offset = flank.developed_offset_mm(a, b);
    return std::hypot(offset.x(), offset.y());
  }

  template <int dim>
  double TabulatedFlankCompliance<dim>::half_space_part(const FlankPoint &reading,
                                                        const FlankPoint &load) const
  {
    if (!kernel || reading.tooth != load.tooth)
      return 0.0;
    return (*kernel)(flank_distance_mm(reading, load)) * scale;
  }

  template <int dim>
  typename ElasticBody<dim>::PatchLoad
  TabulatedFlankCompliance<dim>::patch_load(const FlankPoint &f) const
  {
    const double    pitch = 2.0 * M_PI / geometry->n_teeth();
    // The modified flank (micro-geometry) lies Delta inside the nominal one. 3D: the flank
    // surface; 2D: the transverse involute with the tip relief only.
    Eigen::Vector3d p, n;
    if constexpr (dim == 3)
      {
        n = flank.normal(f.roll_mm, f.z_mm);
        p = flank.modified_point(f.roll_mm, f.z_mm);
      }
    else
      {
        const double    r_b = geometry->base_radius_mm();
        const double    u   = f.roll_mm / r_b;
        Eigen::Vector2d p2  = geometry->involute_point(u);
        Eigen::Vector2d n2  = geometry->involute_normal(u);
        p2 -= geometry->tip_relief_mm(f.roll_mm) * n2;
        p << p2, 0.0;
        n << n2, 0.0;
      }
    // Tooth f.tooth: the flank of tooth 0 turned about the axis.
    const Eigen::Vector2d pr = meshing::GearGeometry::rotate(p.head<2>(), f.tooth * pitch);
    const Eigen::Vector2d nr = meshing::GearGeometry::rotate(n.head<2>(), f.tooth * pitch);
    typename ElasticBody<dim>::PatchLoad load;
    for (unsigned int c = 0; c < 2; ++c)
      {
        load.centre[c]    = pr[c];
        load.direction[c] = -nr[c];
      }
    if constexpr (dim == 3)
      {
        load.centre[2]    = p.z();
        load.direction[2] = 0.0 - n.z(); // +0, not -0, for a spur flank (n.z() = +0)
      }
    load.radius = settings.patch_radius_mm;
    return load;
  }

  template <int dim>
  bool TabulatedFlankCompliance<dim>::covers_tooth(const int tooth) const
  {
    return std::find(settings.teeth.begin(), settings.teeth.end(), tooth) != settings.teeth.end();
  }

  template <int dim>
  bool TabulatedFlankCompliance<dim>::weights(const FlankPoint &p, unsigned int nodes[4],
                                              double w[4]) const
  {
    const auto it = std::find(settings.teeth.begin(), settings.teeth.end(), p.tooth);
    if (it == settings.teeth.end())
      return false;
    const unsigned int t = static_cast<unsigned int>(it - settings.teeth.begin());
    // Linear in roll (clamped to the active profile), linear in z (3D).
    const auto bracket = [](const std::vector<double> &x, const double v, unsigned int &i0,
                            double &f) {
      if (x.size() == 1)
        {
          i0 = 0;
          f  = 0;
          return;
        }
      const double c = std::clamp(v, x.front(), x.back());
      i0 = static_cast<unsigned int>(
        std::min<std::size_t>(std::upper_bound(x.begin(), x.end(), c) - x.begin(), x.size() - 1) - 1);
      f = (c - x[i0]) / (x[i0 + 1] - x[i0]);
    };
    unsigned int ir, iz;
    double       fr, fz;
    bracket(roll_nodes, p.roll_mm, ir, fr);
    bracket(face_nodes, p.z_mm, iz, fz);
    const unsigned int ir1 = std::min<unsigned int>(ir + 1, roll_nodes.size() - 1);
    const unsigned int iz1 = std::min<unsigned int>(iz + 1, face_nodes.size() - 1);
    nodes[0] = node(t, ir, iz);
    nodes[1] = node(t, ir1, iz);
    nodes[2] = node(t, ir, iz1);
    nodes[3] = node(t, ir1, iz1);
    w[0]     = (1 - fr) * (1 - fz);
    w[1]     = fr * (1 - fz);
    w[2]     = (1 - fr) * fz;
    w[3]     = fr * fz;
    return true;
  }

  template <int dim>
  double TabulatedFlankCompliance<dim>::compliance_mm_per_N(const FlankPoint &reading,
                                                            const FlankPoint &load) const
  {
    unsigned int ni[4], nj[4];
    double       wi[4], wj[4];
    // A tooth outside the table is far from the loaded teeth: its coupling is neglected.
    if (!weights(reading, ni, wi) || !weights(load, nj, wj))
      return 0.0;
    double c = half_space_part(reading, load);
    for (unsigned int a = 0; a < 4; ++a)
      for (unsigned int b = 0; b < 4; ++b)
        c += wi[a] * wj[b] * interpolated(ni[a], nj[b]);
    return c;
  }

  template class TabulatedFlankCompliance<2>;
  template class TabulatedFlankCompliance<3>;
} // namespace hertzgear::fem
