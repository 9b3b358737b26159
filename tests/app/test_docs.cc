// Requirement: docs/scenes.md documents every scene key exactly as declared (it is generated from
// the declarations, so it cannot drift).
#include "app/scene.h"

#include "tests/support/run_command.h"

#include <gtest/gtest.h>

TEST(Docs, ScenesReferenceIsUpToDate)
{
  const std::string on_disk =
    hertzgear::testing::slurp(std::string(HERTZGEAR_SOURCE_DIR) + "/docs/scenes.md");
  EXPECT_EQ(on_disk, hertzgear::scene_reference_markdown())
    << "docs/scenes.md is stale: regenerate it with "
       "`build/app/hertzgear defaults --markdown > docs/scenes.md`";
}
