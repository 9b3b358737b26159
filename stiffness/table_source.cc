// Stiffness source table: a stiffness table file (stiffness.json of a stiffness run, or the tables
// shipped in data/stiffness/), read by the dynamics directly.
#include "common/errors.h"
#include "stiffness/stiffness_source.h"

#include <cmath>

namespace hertzgear::stiffness
{
  namespace
  {
    class TableSource : public DirectSource
    {
    public:
      TableSource()
        : DirectSource("table", "a stiffness table file, no meshing or FE")
      {}

      StiffnessResult compute(const StiffnessInput &input, PhaseTimer &) const override
      {
        StiffnessResult r;
        r.table = dynamics::read_stiffness_table(input.table_file);
        if (!(std::abs(r.table.hertz_exponent - input.hertz_exponent) < 1e-12))
          throw ParameterError("hertz_exponent",
                               msg(input.hertz_exponent, ", but the stiffness table ",
                                   input.table_file.string(), " has hertz_exponent = ",
                                   r.table.hertz_exponent, "; make them agree"));
        r.table.check();
        return r;
      }
    };
  } // namespace

  const StiffnessSource &table_source() { return the_source<TableSource>(); }
} // namespace hertzgear::stiffness
