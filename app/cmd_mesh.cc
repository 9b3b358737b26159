// `hertzgear mesh SCENE --out DIR`: the gmsh bodies of both gears as the FE source meshes them
// (FE build only).
#include "app/command.h"
#include "app/meshing_setup.h"
#include "app/run_directory.h"
#include "app/stiffness_setup.h"
#include "common/errors.h"
#include "common/processes.h"
#include "meshing/gear_body_mesher.h"
#include "stiffness/fe_tca.h"

#include <filesystem>

namespace hertzgear
{
  namespace
  {
    int run_mesh(const CommandContext &ctx)
    {
      HG_REQUIRE_INPUT(!ctx.out_dir.empty(), "hertzgear mesh needs --out DIR");
      PhaseTimer  timer;
      const Scene scene = load_scene(ctx.scene_file, ctx.overrides);
      const auto  pair  = make_pair(scene);
      const auto  settings = stiffness::fe_mesh_settings(stiffness_input(scene).fe);
      meshing::require_layers_for_twist(pair, settings); // both bodies, before any folder
      begin_on_out(ctx);
      if (!processes::is_root())
        return 0; // gmsh meshes on one process
      RunDirectory dir(ctx.out_dir, scene, ctx.command_line);
      std::filesystem::create_directories(dir.path());
      nlohmann::json quality;
      {
        meshing::GearBodyMesher mesher;
        for (unsigned int body = 0; body < 2; ++body)
          {
            const std::string name = body == 0 ? "pinion" : "gear";
            PhaseTimer::Scope scope(timer, "mesh " + name);
            // The contact band runs from the start of the active profile to the tip.
            const auto        q = mesher.mesh(pair.body(body), settings,
                                              pair.active_profile_start_radius_mm(body),
                                              dir.path() / (name + ".msh"));
            quality[name] = meshing::mesh_quality_json(q);
            progress_line("mesh", msg(name, ": ", q.n_elements,
                                      q.dimension == 2 ? " quadrilaterals, " : " hexahedra, ",
                                      q.n_nodes, " nodes, min scaled Jacobian ",
                                      q.min_scaled_jacobian));
          }
      }
      quality["refinement_level"] = settings.refinement_level;
      quality["scene_hash"]       = scene.hash;
      dir.write_json("mesh_quality.json", quality);
      dir.finish(timer);
      return 0;
    }
  } // namespace

  void add_mesh_command(CommandRegistry &registry)
  {
    registry.add_command({"mesh", "gmsh meshes of both bodies (DIR/pinion.msh, DIR/gear.msh, "
                                  "DIR/mesh_quality.json)", true, true},
                         run_mesh);
  }
} // namespace hertzgear
