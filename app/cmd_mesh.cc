// `hertzgear mesh SCENE --out DIR`: the gmsh bodies of both gears as the FE source meshes them
// (FE build only).
#include "app/command.h"
#include "app/meshing_setup.h"
#include "app/run_directory.h"
#include "app/stiffness_setup.h"
#include "common/errors.h"
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
      // The contact band starts at the start of the active profile: point A on the pinion,
      // point E on the gear.
      const double r_active[2] = {pair.point('A').radius_pinion_mm, pair.point('E').radius_gear_mm};
      RunDirectory dir(ctx.out_dir, scene, ctx.command_line);
      std::filesystem::create_directories(dir.path());
      nlohmann::json quality;
      {
        meshing::GearBodyMesher mesher;
        for (unsigned int body = 0; body < 2; ++body)
          {
            const std::string name = body == 0 ? "pinion" : "gear";
            PhaseTimer::Scope scope(timer, "mesh " + name);
            const auto        q = mesher.mesh(pair.body(body), settings, r_active[body],
                                       dir.path() / (name + ".msh"));
            quality[name] = {{"dimension", q.dimension},
                             {"elements", q.n_elements},
                             {"nodes", q.n_nodes},
                             {"boundary_elements", q.n_boundary_elements},
                             {"non_quad_elements", q.n_other_elements},
                             {"min_scaled_jacobian", q.min_scaled_jacobian},
                             {"contact_band_target_size_mm", q.contact_band_target_size_mm},
                             {"contact_band_max_edge_mm", q.contact_band_max_edge_mm},
                             {"contact_band_mean_edge_mm", q.contact_band_mean_edge_mm},
                             {"teeth_meshed", q.n_teeth_meshed},
                             {"central_tooth", q.central_tooth},
                             {"full_gear", q.full_gear},
                             {"subdivided", q.subdivided},
                             {"max_flank_modification_error_mm", q.max_flank_modification_error_mm},
                             {"physical_groups", q.physical_groups}};
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
