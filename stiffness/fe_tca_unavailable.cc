// A build without the finite-element stage (cmake -DHERTZGEAR_WITH_FEM=OFF): the FE source is
// registered so that the scene knows its name, and says that this build cannot compute it.
#include "common/errors.h"
#include "stiffness/stiffness_source.h"

namespace hertzgear::stiffness
{
  namespace
  {
    class UnavailableFeSource : public StiffnessSource
    {
    public:
      UnavailableFeSource()
        : StiffnessSource("fem",
                        "meshing (gmsh) and FE contact over the mesh cycle (deal.II); not in this build")
      {}
      bool uses_fe() const override { return true; }
      bool available() const override { return false; }
      void check(const StiffnessInput &) const override { unavailable(); }
      StiffnessResult compute(const StiffnessInput &, PhaseTimer &) const override
      {
        unavailable();
        return {};
      }

    private:
      [[noreturn]] static void unavailable()
      {
        throw ParameterError("source", "fem: this hertzgear was built without the finite-element "
                                       "stage (cmake -DHERTZGEAR_WITH_FEM=OFF)");
      }
    };
  } // namespace

  const StiffnessSource &fe_tca_source() { return the_source<UnavailableFeSource>(); }
} // namespace hertzgear::stiffness
