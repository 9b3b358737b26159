#include "fem/body_fields.h"

#include "common/errors.h"

#include <deal.II/numerics/data_component_interpretation.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <cmath>
#include <fstream>

namespace hertzgear::fem
{
  using namespace dealii;

  namespace
  {
    // von Mises stress of the linear elastic (plane strain in 2D) material.
    template <int dim>
    class VonMises : public DataPostprocessorScalar<dim>
    {
    public:
      VonMises(const double lambda, const double mu)
        : DataPostprocessorScalar<dim>("von_mises_stress", update_gradients), lambda(lambda), mu(mu)
      {}

      void evaluate_vector_field(const DataPostprocessorInputs::Vector<dim> &inputs,
                                 std::vector<Vector<double>> &computed) const override
      {
        for (unsigned int q = 0; q < inputs.solution_gradients.size(); ++q)
          {
            double eps[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
            for (unsigned int i = 0; i < dim; ++i)
              for (unsigned int j = 0; j < dim; ++j)
                eps[i][j] = 0.5 * (inputs.solution_gradients[q][i][j] + inputs.solution_gradients[q][j][i]);
            const double tr = eps[0][0] + eps[1][1] + eps[2][2];
            double       s[3][3];
            for (unsigned int i = 0; i < 3; ++i)
              for (unsigned int j = 0; j < 3; ++j)
                s[i][j] = 2.0 * mu * eps[i][j] + (i == j ? lambda * tr : 0.0);
            const double vm2 = 0.5 * ((s[0][0] - s[1][1]) * (s[0][0] - s[1][1]) +
                                      (s[1][1] - s[2][2]) * (s[1][1] - s[2][2]) +
                                      (s[2][2] - s[0][0]) * (s[2][2] - s[0][0])) +
                               3.0 * (s[0][1] * s[0][1] + s[1][2] * s[1][2] + s[2][0] * s[2][0]);
            computed[q](0) = std::sqrt(std::max(vm2, 0.0));
          }
      }

    private:
      double lambda, mu;
    };
  } // namespace

  template <int dim>
  std::string write_body_fields(const ElasticBody<dim> &                      body,
                                const typename ElasticBody<dim>::VectorType &displacement,
                                const std::filesystem::path &directory, const std::string &name,
                                const unsigned int counter)
  {
    const auto & p      = body.get_parameters();
    const double E      = p.youngs_modulus;
    const double nu     = p.poisson_ratio;
    const double lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    const double mu     = E / (2.0 * (1.0 + nu));
    VonMises<dim> von_mises(lambda, mu);

    DataOut<dim> data_out;
    data_out.attach_dof_handler(body.get_dof_handler());
    const std::vector<std::string> names(dim, "displacement");
    const std::vector<DataComponentInterpretation::DataComponentInterpretation> kinds(
      dim, DataComponentInterpretation::component_is_part_of_vector);
    data_out.add_data_vector(displacement, names, DataOut<dim>::type_dof_data, kinds);
    data_out.add_data_vector(displacement, von_mises);
    // One patch per cell (values at the vertices, linear in between): a Q2 field subdivided into
    // 2^dim sub-cells per cell made the files 2.7 times larger and cost a third of a 2D cycle's
    // wall time (docs/accuracy-stiffness.md); the meshes are fine where the stress varies.
    data_out.build_patches(body.get_mapping(), 1);
    DataOutBase::VtkFlags flags;
    flags.compression_level = DataOutBase::VtkFlags::ZlibCompressionLevel::best_speed;
    data_out.set_flags(flags);
    std::string dir = directory.string();
    if (dir.empty() || dir.back() != '/')
      dir += '/';
    return data_out.write_vtu_with_pvtu_record(dir, name, counter, body.get_communicator(), 4);
  }

  void write_point_cloud_vtu(const std::filesystem::path &file,
                             const std::vector<std::array<double, 3>> &points,
                             const std::vector<std::pair<std::string, std::vector<double>>> &data)
  {
    std::ofstream out(file);
    HG_REQUIRE_INPUT(out.good(), "cannot write ", file.string());
    out.precision(10);
    const std::size_t n = points.size();
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
           "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\""
        << n << "\" NumberOfCells=\"" << n << "\">\n<Points>\n"
        << "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const auto &x : points)
      out << x[0] << ' ' << x[1] << ' ' << x[2] << '\n';
    out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" "
           "format=\"ascii\">\n";
    for (std::size_t i = 0; i < n; ++i)
      out << i << '\n';
    out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (std::size_t i = 0; i < n; ++i)
      out << i + 1 << '\n';
    out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (std::size_t i = 0; i < n; ++i)
      out << "1\n"; // VTK_VERTEX
    out << "</DataArray>\n</Cells>\n<PointData>\n";
    for (const auto &[name, values] : data)
      {
        out << "<DataArray type=\"Float64\" Name=\"" << name << "\" format=\"ascii\">\n";
        for (const double v : values)
          out << v << '\n';
        out << "</DataArray>\n";
      }
    out << "</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
    HG_REQUIRE_INPUT(out.good(), "writing ", file.string(), " failed");
  }

  void write_pvd(const std::filesystem::path &file,
                 const std::vector<std::pair<double, std::string>> &entries)
  {
    std::ofstream out(file);
    HG_REQUIRE_INPUT(out.good(), "cannot write ", file.string());
    DataOutBase::write_pvd_record(out, entries);
  }

  template std::string write_body_fields<2>(const ElasticBody<2> &, const ElasticBody<2>::VectorType &,
                                            const std::filesystem::path &, const std::string &,
                                            unsigned int);
  template std::string write_body_fields<3>(const ElasticBody<3> &, const ElasticBody<3>::VectorType &,
                                            const std::filesystem::path &, const std::string &,
                                            unsigned int);
} // namespace hertzgear::fem
