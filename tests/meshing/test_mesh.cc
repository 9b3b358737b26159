// Requirements on the gmsh meshes of the gear bodies, checked by reading them back with
// deal.II's GridIn (the FE stage's reader), independently of the mesher's own bookkeeping:
//   - every cell is a quadrilateral/hexahedron with a positive Jacobian determinant at every
//     vertex and quadrature point,
//   - every named physical group arrives as a boundary id,
//   - the crowned 3D flank nodes are removed from the nominal involute by exactly
//     Delta(z) = beta (2z/b)^2 (1e-9 mm: the .msh file stores 16 significant digits, i.e.
//     ~1e-14 mm here, and the involute evaluation adds rounding of the same order),
//   - the same scene gives the same mesh file.
#include "tests/support/run_command.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/tria.h>

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>

using namespace hertzgear::testing;
namespace fs = std::filesystem;

namespace
{
  constexpr double pi = 3.14159265358979323846;

  template <int dim>
  void read(dealii::Triangulation<dim> &tria, const fs::path &file)
  {
    dealii::GridIn<dim> in;
    in.attach_triangulation(tria);
    std::ifstream stream(file);
    in.read_msh(stream);
  }

  // Positive Jacobian determinant at the vertices (trapezoidal points) and Gauss points.
  template <int dim>
  double min_jacobian(const dealii::Triangulation<dim> &tria)
  {
    dealii::FE_Q<dim>     fe(1);
    dealii::MappingQ1<dim> mapping;
    double                 min_det = 1e300;
    for (const auto &quadrature : {dealii::Quadrature<dim>(dealii::QTrapezoid<1>()),
                                   dealii::Quadrature<dim>(dealii::QGauss<dim>(2))})
      {
        dealii::FEValues<dim> fv(mapping, fe, quadrature, dealii::update_jacobians);
        for (const auto &cell : tria.active_cell_iterators())
          {
            fv.reinit(cell);
            for (unsigned int q = 0; q < quadrature.size(); ++q)
              min_det = std::min(min_det, double(fv.jacobian(q).determinant()));
          }
      }
    return min_det;
  }

  template <int dim>
  std::set<unsigned int> boundary_ids(const dealii::Triangulation<dim> &tria)
  {
    std::set<unsigned int> ids;
    for (const auto &cell : tria.active_cell_iterators())
      for (const auto f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          ids.insert(cell->face(f)->boundary_id());
    return ids;
  }

  std::set<unsigned int> expected_ids(const int n_teeth, const bool three_d)
  {
    std::set<unsigned int> ids = {10, 11, 12, 15, 16};
    if (three_d)
      ids.insert({13, 14});
    for (int k = 0; k < n_teeth; ++k)
      ids.insert({100u + k, 200u + k, 300u + k, 400u + k});
    return ids;
  }

  // Calls f(tooth, vertex) for every vertex of every drive and coast flank face (boundary ids
  // 100 + k and 200 + k); a vertex shared by faces is visited once per face.
  template <typename F>
  void for_each_flank_vertex(const dealii::Triangulation<3> &tria, const F &f)
  {
    for (const auto &cell : tria.active_cell_iterators())
      for (const auto face : cell->face_indices())
        if (cell->face(face)->at_boundary())
          {
            const unsigned int id = cell->face(face)->boundary_id();
            if (id < 100 || id >= 300)
              continue;
            for (const auto v : cell->face(face)->vertex_indices())
              f(int(id % 100), cell->face(face)->vertex(v));
          }
  }

  nlohmann::json mesh(const std::string &scene, const std::string &extra, const fs::path &out)
  {
    const auto r = run_hertzgear("mesh " + scene_path(scene) + " --out " + out.string() +
                                 " --set 'Stiffness/fe_level=0' --set Mesh/body_model=sector"
                                 " --set 'Mesh/teeth_per_sector=3'" + extra);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(slurp(out / "mesh_quality.json"));
  }
} // namespace

TEST(BodyMesh, TwoDimensionalMeshesReadByDealiiWithAllGroupsAndPositiveJacobians)
{
  const fs::path out = fresh_temp_dir("mesh2d");
  const auto     q   = mesh("paper_uncrowned.prm", " --set 'Stiffness/fe_dimension=2'", out);
  for (const char *body : {"pinion", "gear"})
    {
      dealii::Triangulation<2> tria;
      read(tria, out / (std::string(body) + ".msh"));
      EXPECT_EQ(tria.n_active_cells(), q.at(body).at("elements").get<std::size_t>());
      EXPECT_EQ(q.at(body).at("non_quad_elements").get<int>(), 0);
      EXPECT_GT(min_jacobian(tria), 0.0) << body;
      EXPECT_GT(q.at(body).at("min_scaled_jacobian").get<double>(), 0.0);
      EXPECT_EQ(boundary_ids(tria), expected_ids(3, false)) << body;
      for (const auto &cell : tria.active_cell_iterators())
        EXPECT_EQ(cell->material_id(), 1u);
    }
  // Same scene, same mesh: byte-identical files.
  const fs::path again = fresh_temp_dir("mesh2d_again");
  mesh("paper_uncrowned.prm", " --set 'Stiffness/fe_dimension=2'", again);
  EXPECT_EQ(slurp(out / "pinion.msh"), slurp(again / "pinion.msh"));
}

TEST(BodyMesh, CrownedThreeDimensionalMeshHasExactCrowningAtFlankNodes)
{
  const fs::path out = fresh_temp_dir("mesh3d");
  const auto     q   = mesh("paper_crowned.prm", " --set 'Mesh/face_width_layers=4'", out);
  // Independent flank data by hand (paper pinion, thinned for 0.1172 mm backlash): psi_b =
  // s/(2r) + inv(alpha), s = pi m / 2 - 0.1172 / (2 cos alpha).
  const double alpha = 20 * pi / 180, m = 3, b = 20, beta = 0.08;
  const int    z[2] = {23, 34};
  const char  *body[2] = {"pinion", "gear"};
  for (int i = 0; i < 2; ++i)
    {
      dealii::Triangulation<3> tria;
      read(tria, out / (std::string(body[i]) + ".msh"));
      EXPECT_EQ(tria.n_active_cells(), q.at(body[i]).at("elements").get<std::size_t>());
      EXPECT_GT(min_jacobian(tria), 0.0) << body[i];
      EXPECT_EQ(boundary_ids(tria), expected_ids(3, true)) << body[i];

      const double r  = 0.5 * m * z[i], rb = r * std::cos(alpha);
      const double s  = pi * m / 2 - 0.1172 / (2 * std::cos(alpha));
      const double psi = s / (2 * r) + std::tan(alpha) - alpha;
      const int    central = 1; // 3 teeth: teeth 0, 1, 2; tooth 1 on the +x axis
      double       max_err = 0;
      std::size_t  n_checked = 0;
      for_each_flank_vertex(tria, [&](const int tooth, const dealii::Point<3> &p) {
        const double radius = std::hypot(p[0], p[1]);
        const double phi    = std::atan2(p[1], p[0]) - (tooth - central) * 2 * pi / z[i];
        const double a_r    = std::acos(rb / radius);
        // Removal normal to the flank = r_b times the angular offset from the nominal involute
        // (an involute moved by Delta along its normal turns by Delta / r_b).
        const double removal  = rb * (psi - (std::tan(a_r) - a_r) - std::abs(phi));
        const double expected = beta * std::pow(2 * p[2] / b, 2);
        max_err = std::max(max_err, std::abs(removal - expected));
        ++n_checked;
      });
      EXPECT_GT(n_checked, 100u);
      EXPECT_LT(max_err, 1e-9) << body[i] << ": crowning error at the flank nodes";
    }
}

// Requirement: the body of the default (full-gear) model is one tooth sector whose end cut is its
// start cut turned by one pitch, vertex for vertex (gmsh periodic curves; the 3D faces are
// extruded from them), which is what the cyclic model ties. Tolerance 1e-9 of the radius: the
// periodic copy is an exact affine map of gmsh's nodes, off by round-off only.
TEST(BodyMesh, FullGearModelMeshesOneToothWithPeriodicCutFaces)
{
  for (const int dim : {2, 3})
    {
      const fs::path out = fresh_temp_dir("mesh_periodic");
      const auto     r   = run_hertzgear("mesh " + scene_path("paper_crowned.prm") + " --out " + out.string() +
                                   " --set Stiffness/fe_level=0 --set Mesh/face_width_layers=2"
                                   " --set Stiffness/fe_dimension=" + std::to_string(dim) +
                                   (dim == 2 ? " --set 'Gear pair/Pinion/crowning_um=0'"
                                               " --set 'Gear pair/Gear/crowning_um=0'" : ""));
      ASSERT_EQ(r.exit_code, 0) << r.err;
      for (const auto &[body, z] : {std::pair<std::string, int>{"pinion", 23}, {"gear", 34}})
        {
          std::vector<std::vector<double>> start, end; // vertices of the cut faces
          const auto collect = [&](auto &tria) {
            for (const auto &face : tria.active_face_iterators())
              if (face->at_boundary() && (face->boundary_id() == 11 || face->boundary_id() == 12))
                for (unsigned int v = 0; v < face->n_vertices(); ++v)
                  {
                    std::vector<double> x;
                    for (unsigned int d = 0; d < face->vertex(v).dimension; ++d)
                      x.push_back(face->vertex(v)[d]);
                    (face->boundary_id() == 11 ? start : end).push_back(x);
                  }
            for (const auto &face : tria.active_face_iterators())
              if (face->at_boundary() && face->boundary_id() >= 100 && face->boundary_id() < 200)
                {
                  EXPECT_EQ(face->boundary_id(), 100u) << body << ": one tooth, tooth 0";
                }
          };
          if (dim == 2)
            {
              dealii::Triangulation<2> tria;
              read(tria, out / (body + ".msh"));
              collect(tria);
            }
          else
            {
              dealii::Triangulation<3> tria;
              read(tria, out / (body + ".msh"));
              collect(tria);
            }
          ASSERT_FALSE(start.empty());
          const double angle = 2 * pi / z, c = std::cos(angle), s = std::sin(angle);
          double       worst = 0, radius = 0;
          for (const auto &x : start)
            {
              std::vector<double> y = x;
              y[0] = c * x[0] - s * x[1];
              y[1] = s * x[0] + c * x[1];
              double best = 1e300;
              for (const auto &e : end)
                {
                  double d = 0;
                  for (std::size_t k = 0; k < e.size(); ++k)
                    d += (e[k] - y[k]) * (e[k] - y[k]);
                  best = std::min(best, std::sqrt(d));
                }
              worst  = std::max(worst, best);
              radius = std::max(radius, std::hypot(x[0], x[1]));
            }
          EXPECT_LT(worst, 1e-9 * radius) << dim << "D " << body;
        }
    }
}

// Requirement: a helical body is the transverse section turned by psi(z) = +-z tan(beta) / r along
// the face (docs/geometry.md, "Flank surface"): on both flanks of every tooth of the paper's
// helical pair (beta = 15 deg, pinion right hand, gear left hand; 3D sector of three teeth, level
// 0, uncrowned), the node's polar angle less its tooth's angle and psi(z) is the involute of its
// radius offset by one half-thickness angle, the same for all nodes of a body. The reference is
// built here from the transverse module and pressure angle (ISO 21771), not from the mesher's
// geometry. Tolerance 1e-9 rad: the .msh file's 16 digits and the involute's rounding (1e-14).
// A straight (untwisted) body would be off by up to b tan(beta) / (2 r) = 0.075 rad at the faces.
TEST(BodyMesh, HelicalThreeDimensionalMeshIsTheSectionTurnedAlongTheFace)
{
  const fs::path out = fresh_temp_dir("mesh3d_helical");
  const auto     q   = mesh("paper_helical.prm", " --set Stiffness/fe_dimension=3", out);
  const double   beta = 15 * pi / 180, m_t = 3 / std::cos(beta);
  const double   alpha_t = std::atan(std::tan(20 * pi / 180) / std::cos(beta));
  const int      z[2]    = {23, 34};
  const double   hand[2] = {1, -1};
  const char    *body[2] = {"pinion", "gear"};
  for (int i = 0; i < 2; ++i)
    {
      dealii::Triangulation<3> tria;
      read(tria, out / (std::string(body[i]) + ".msh"));
      EXPECT_EQ(tria.n_active_cells(), q.at(body[i]).at("elements").get<std::size_t>());
      EXPECT_GT(min_jacobian(tria), 0.0) << body[i];
      const double r = 0.5 * m_t * z[i], rb = r * std::cos(alpha_t);
      const int    central = 1;
      double       lo = 1e300, hi = -1e300;
      std::size_t  n_checked = 0;
      for_each_flank_vertex(tria, [&](const int tooth, const dealii::Point<3> &p) {
        const double radius = std::hypot(p[0], p[1]);
        if (radius < rb)
          return; // the fillet's end of a flank curve below the base circle
        const double psi_z = hand[i] * p[2] * std::tan(beta) / r;
        const double phi   = std::atan2(p[1], p[0]) - (tooth - central) * 2 * pi / z[i] - psi_z;
        const double a_r   = std::acos(rb / radius);
        const double half_angle = std::abs(phi) + (std::tan(a_r) - a_r);
        lo = std::min(lo, half_angle), hi = std::max(hi, half_angle);
        ++n_checked;
      });
      EXPECT_GT(n_checked, 100u);
      EXPECT_LT(hi - lo, 1e-9) << body[i] << ": flank nodes off the turned involute";
      EXPECT_GT(q.at(body[i]).at("min_scaled_jacobian").get<double>(), 0.0);
    }
}
