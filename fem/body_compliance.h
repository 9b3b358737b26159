#pragma once
// What the flank compliance table needs of a gear body: the displacement read at points under
// unit patch loads on its surface. Two bodies answer it: ElasticBody (the meshed body as it is,
// e.g. a sector clamped at its cuts) and CyclicGearBody (the full gear from one tooth sector).
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/lac/full_matrix.h>

#include <vector>

namespace hertzgear::fem
{
  // A unit force along `direction` spread over the boundary within `radius` of `centre` with the
  // smooth weight (1 - (r/radius)^2)^2, so that the load is a traction whose resultant is exactly
  // `direction` (|direction| = 1 for a unit load).
  template <int dim>
  struct PatchLoad
  {
    dealii::Point<dim>     centre;
    dealii::Tensor<1, dim> direction;
    double                 radius = 0.0;
  };

  // Displacement component along `direction` at `point` (anywhere in the body).
  template <int dim>
  struct PointReading
  {
    dealii::Point<dim>     point;
    dealii::Tensor<1, dim> direction;
  };

  template <int dim>
  class BodyCompliance
  {
  public:
    virtual ~BodyCompliance() = default;
    // C(r, l) = displacement of load case l read at reading r: n_readings x n_loads, replicated
    // on every rank of the body's communicator.
    virtual dealii::FullMatrix<double> compliance(const std::vector<PatchLoad<dim>>    &loads,
                                                  const std::vector<PointReading<dim>> &readings) const = 0;
    virtual double youngs_modulus() const = 0;
    virtual double poisson_ratio() const  = 0;
  };
} // namespace hertzgear::fem
