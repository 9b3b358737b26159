#include "stiffness/registry.h"

#include "common/errors.h"

// The registered sources: one line each, naming the function that returns the source (defined in
// the source's own file, stiffness/<name>_source.cc). The order is the order of the help text.
#define HERTZGEAR_STIFFNESS_SOURCES(REGISTER)                                                    \
  REGISTER(fe_tca_source)                                                                        \
  REGISTER(table_source)                                                                         \
  REGISTER(fourier_source)                                                                       \
  REGISTER(iso6336_source)                                                                       \
  REGISTER(hertz_analytic_source)                                                                \
  REGISTER(potential_energy_source)

namespace hertzgear::stiffness
{
#define HERTZGEAR_DECLARE_SOURCE(function) const StiffnessSource &function();
  HERTZGEAR_STIFFNESS_SOURCES(HERTZGEAR_DECLARE_SOURCE)
#undef HERTZGEAR_DECLARE_SOURCE

  const std::vector<const StiffnessSource *> &sources()
  {
#define HERTZGEAR_LIST_SOURCE(function) &function(),
    static const std::vector<const StiffnessSource *> list = {
      HERTZGEAR_STIFFNESS_SOURCES(HERTZGEAR_LIST_SOURCE)};
#undef HERTZGEAR_LIST_SOURCE
    return list;
  }

  std::vector<std::string> source_names()
  {
    std::vector<std::string> names;
    for (const auto *s : sources())
      names.push_back(s->name());
    return names;
  }

  const StiffnessSource &find_source(const std::string &name)
  {
    std::string known;
    for (const auto *s : sources())
      {
        if (s->name() == name)
          {
            if (!s->available())
              throw ParameterError("source", msg(name, ": this hertzgear was built without the "
                                                     "finite-element stage (cmake "
                                                     "-DHERTZGEAR_WITH_FEM=OFF) and cannot "
                                                     "compute it; rebuild with "
                                                     "-DHERTZGEAR_WITH_FEM=ON, or use a table, "
                                                     "Fourier coefficients or a closed-form "
                                                     "source"));
            return *s;
          }
        known += (known.empty() ? "" : ", ") + s->name();
      }
    throw ParameterError("source", msg(name, ": unknown stiffness source (known: ", known, ")"));
  }
} // namespace hertzgear::stiffness
