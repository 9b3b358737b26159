// Requirements on the registry of stiffness sources and the one table writer.
#include "common/errors.h"
#include "stiffness/registry.h"
#include "stiffness/table_writer.h"
#include "stiffness_fixtures.h"

#include <gtest/gtest.h>

#include <set>
#include <sstream>

using namespace hertzgear;
using namespace hertzgear::stiffness;

// Every source shall have a distinct name and a summary, and an unknown name shall be refused
// with the list of the known ones.
TEST(StiffnessRegistry, NamesAreDistinctAndUnknownNamesRefused)
{
  std::set<std::string> names;
  for (const auto *s : sources())
    {
      EXPECT_TRUE(names.insert(s->name()).second) << s->name();
      EXPECT_FALSE(s->summary().empty()) << s->name();
    }
  for (const char *expected : {"fem", "table", "fourier", "iso6336", "hertz-analytic", "potential-energy"})
    EXPECT_TRUE(names.count(expected)) << expected;
  try
    {
      find_source("no-such-source");
      FAIL();
    }
  catch (const ParameterError &e)
    {
      EXPECT_EQ(e.parameter(), "source");
      EXPECT_NE(e.text().find("iso6336"), std::string::npos) << e.text();
    }
}

// The writer shall give one CSV row per mesh position under the contract's header, with the
// columns a source does not compute left empty.
TEST(StiffnessWriter, OneRowPerPositionAndEmptyColumnsForWhatIsNotComputed)
{
  PhaseTimer timer;
  const auto r   = find_source("iso6336").compute(test_pairs::paper_pair(), timer);
  const auto csv = stiffness_csv(r);
  std::istringstream in(csv);
  std::string        header, line;
  std::getline(in, header);
  EXPECT_EQ(header, "position,mesh_phase,ste_um,k_total_N_per_m,k_hertz,k_rest_N_per_m,"
                    "pairs_in_contact,load_share_1,load_share_2,hertz_penetration_um,"
                    "contact_a_mm,contact_b_mm,peak_pressure_MPa,k_total_tangent_N_per_m,"
                    "contact_centre_z_mm,face_end_contact,tip_contact");
  int rows = 0;
  while (std::getline(in, line))
    {
      ++rows;
      EXPECT_NE(line.find(",,,,"), std::string::npos) << "pairs and shares left empty: " << line;
      EXPECT_EQ(line.substr(line.size() - 4), ",,,,") << "contact columns left empty: " << line;
    }
  EXPECT_EQ(rows, 16);
  const auto json = stiffness_json(r);
  EXPECT_EQ(json.at("schema").get<std::string>(), "hertzgear-stiffness-table/1");
  EXPECT_DOUBLE_EQ(json.at("mean_k_rest_N_per_m").get<double>(), r.table.k_rest_N_per_m.mean);
  EXPECT_TRUE(json.contains("closed_form_model"));
}
