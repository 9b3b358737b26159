#include "app/stiffness_stage.h"

#include "app/meshing_setup.h"
#include "app/run_directory.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/progress.h"
#include "fem/body_fields.h"
#include "fem/flank_compliance.h"
#include "meshing/gear_body_mesher.h"

#include <deal.II/base/mpi.h>
#include <deal.II/distributed/shared_tria.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/tria.h>

#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <fstream>
#include <iomanip>
#include <memory>
#include <sstream>

namespace hertzgear
{
  namespace fs = std::filesystem;

  namespace
  {
    // Physical-group tags of GearBodyMesher, read by GridIn as boundary ids.
    constexpr dealii::types::boundary_id bore_id             = 10;
    constexpr dealii::types::boundary_id sector_cut_start_id = 11;
    constexpr dealii::types::boundary_id sector_cut_end_id   = 12;
    constexpr unsigned int               drive_flank_id = 100; // + sector tooth index

    // Largest spacing of the 3D compliance table's face nodes, as a multiple of the reference
    // depth d (Stiffness/table_face_nodes = 0). Measured on the paper's crowned pair
    // (docs/accuracy-stiffness.md, "Nodes of the compliance table, and its half-space split").
    constexpr double face_node_spacing_per_depth = 0.5;
    // The same with the half-space split of the table (Stiffness/table_half_space_split), which
    // interpolates only the remainder: at spacing d the single-pair stiffness is within 0.2 % and
    // the contact within 0.3 % of d/4 (the same study).
    constexpr double face_node_spacing_per_depth_split = 1.0;

    // Element size in the contact band [mm] at the scene's level (as the mesher sizes it).
    double band_element_size_mm(const meshing::MeshSettings &m, const double module_mm)
    {
      return m.band_size_modules * module_mm / std::pow(2.0, m.refinement_level);
    }

    struct Body
    {
      virtual ~Body() = default;
      virtual const fem::FlankCompliance &compliance() const = 0;
      virtual std::size_t                 n_dofs() const     = 0;
      // Displacement and stress of the body under the contact pressures of every position
      // (collective; one block substitution for all); returns the .pvtu names, file i for
      // positions[i]. `force_scale` turns p A [N] into the FE body's load (1/b for the
      // unit-thickness plane-strain body).
      virtual std::vector<std::string> write_fields(const std::vector<fem::PositionResult> &positions,
                                                    bool is_gear, double force_scale,
                                                    const fs::path &dir, const std::string &name) const = 0;
      // Wall-time breakdown of the FE body (assembly, factorisation, substitutions, ...).
      virtual const PhaseTimer &timer() const = 0;
      // The contact-grid cell centres on this body's flank, in its frame (z = 0 in 2D).
      virtual std::vector<std::array<double, 3>> contact_points(const fem::PositionResult &p,
                                                                bool is_gear) const = 0;
    };

    unsigned int world_rank()
    {
      return dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);
    }

    // Runs `work` on rank 0 only (gmsh, file system); an exception there is re-thrown on every
    // rank with its type and text, so no rank waits forever in the next collective call.
    void on_root(const std::function<void()> &work)
    {
      int         code = 0;
      std::string text;
      if (world_rank() == 0)
        {
          try
            {
              work();
            }
          catch (const InputError &e)
            {
              code = 2;
              text = e.what();
            }
          catch (const NumericalError &e)
            {
              code = 3;
              text = e.what();
            }
          catch (const std::exception &e)
            {
              code = 1;
              text = e.what();
            }
        }
      if (dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
        {
          code = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, code, 0);
          text = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, text, 0);
        }
      if (code == 2)
        throw InputError(text);
      if (code == 3)
        throw NumericalError(text);
      if (code != 0)
        throw std::runtime_error(text);
    }

    template <int dim>
    struct BodyModel : Body
    {
      // parallel::shared: every rank holds the whole (small, 2D or coarse 3D) mesh and owns a
      // partition of it; the linear algebra is distributed over MPI_COMM_WORLD.
      dealii::parallel::shared::Triangulation<dim>        triangulation;
      std::unique_ptr<fem::ElasticBody<dim>>             body;
      std::unique_ptr<fem::TabulatedFlankCompliance<dim>> table;

      BodyModel(const fs::path &msh, const MaterialScene &material, const Scene &scene,
                const meshing::GearGeometry &gear, const int central,
                const std::vector<int> &teeth, const fem::FlankTableSettings &table_settings)
        : triangulation(MPI_COMM_WORLD)
      {
        dealii::GridIn<dim> grid_in;
        grid_in.attach_triangulation(triangulation);
        std::ifstream in(msh);
        HG_REQUIRE_INPUT(in.good(), "cannot read mesh ", msh.string());
        grid_in.read_msh(in);
        // A sector is held at the bore and at both radial cuts: free cuts would let the sector
        // swing as a cantilevered wedge, far more compliant than the full disc it stands for
        // (docs/theory-tca.md quantifies the difference against a full-gear mesh).
        for (const auto &face : triangulation.active_face_iterators())
          if (face->at_boundary() &&
              (face->boundary_id() == sector_cut_start_id || face->boundary_id() == sector_cut_end_id))
            face->set_boundary_id(bore_id);

        typename fem::ElasticBody<dim>::Parameters p;
        p.youngs_modulus      = material.youngs_modulus_MPa;
        p.poisson_ratio       = material.poisson_ratio;
        p.fe_degree           = scene.stiffness.fe_degree;
        p.mapping_degree      = 1; // gmsh's straight-sided cells: no curved manifold attached
        p.clamped_boundary_id = bore_id;
        p.linear_solver =
          fem::ElasticBody<dim>::parse_linear_solver(scene.stiffness.linear_solver);
        p.linear_solver_tolerance = scene.stiffness.linear_solver_tolerance;
        body = std::make_unique<fem::ElasticBody<dim>>(triangulation, p);
        std::set<dealii::types::boundary_id> flanks;
        for (const int t : teeth)
          flanks.insert(static_cast<dealii::types::boundary_id>(drive_flank_id + central + t));
        body->set_load_boundary_ids(flanks);
        body->run();
        fem::FlankTableSettings s = table_settings;
        s.teeth                  = teeth;
        table = std::make_unique<fem::TabulatedFlankCompliance<dim>>(*body, gear, central, s);
      }
      const fem::FlankCompliance &compliance() const override { return *table; }
      std::size_t                 n_dofs() const override { return body->n_dofs(); }

      fem::FlankPoint flank_point(const fem::PositionResult &p, const std::size_t k,
                                  const bool is_gear) const
      {
        return is_gear ? fem::FlankPoint{-p.cell_pair[k], p.cell_gear_roll_mm[k], p.cell_z_mm[k]} :
                         fem::FlankPoint{p.cell_pair[k], p.cell_pinion_roll_mm[k], p.cell_z_mm[k]};
      }

      std::vector<std::string> write_fields(const std::vector<fem::PositionResult> &positions,
                                            const bool is_gear, const double force_scale,
                                            const fs::path &dir, const std::string &name) const override
      {
        std::vector<std::vector<typename fem::ElasticBody<dim>::PatchLoad>> loads(positions.size());
        std::vector<std::vector<double>>                                    forces(positions.size());
        for (std::size_t i = 0; i < positions.size(); ++i)
          {
            const auto &p = positions[i];
            for (std::size_t k = 0; k < p.cell_pressure_MPa.size(); ++k)
              if (p.cell_pressure_MPa[k] > 0)
                {
                  loads[i].push_back(table->patch_load(flank_point(p, k, is_gear)));
                  forces[i].push_back(p.cell_pressure_MPa[k] * p.cell_area_mm2[k] * force_scale);
                }
          }
        const auto               u = body->solve_patch_load_sets(loads, forces);
        std::vector<std::string> files;
        for (std::size_t i = 0; i < positions.size(); ++i)
          files.push_back(fem::write_body_fields(*body, u[i], dir, name, i));
        return files;
      }

      const PhaseTimer &timer() const override { return body->get_timer(); }

      std::vector<std::array<double, 3>> contact_points(const fem::PositionResult &p,
                                                        const bool is_gear) const override
      {
        std::vector<std::array<double, 3>> points;
        for (std::size_t k = 0; k < p.cell_pressure_MPa.size(); ++k)
          {
            const auto load = table->patch_load(flank_point(p, k, is_gear));
            std::array<double, 3> x{0, 0, 0};
            for (unsigned int c = 0; c < dim; ++c)
              x[c] = load.centre[c];
            points.push_back(x);
          }
        return points;
      }
    };

    std::unique_ptr<Body> make_body(const int dim, const fs::path &msh, const MaterialScene &m,
                                    const Scene &scene, const meshing::GearGeometry &gear,
                                    const int central, const std::vector<int> &teeth,
                                    const fem::FlankTableSettings &settings)
    {
      if (dim == 2)
        return std::make_unique<BodyModel<2>>(msh, m, scene, gear, central, teeth, settings);
      return std::make_unique<BodyModel<3>>(msh, m, scene, gear, central, teeth, settings);
    }

    double roll_at_radius(const meshing::GearGeometry &g, const double r)
    {
      return std::sqrt(std::max(0.0, r * r - g.base_radius_mm() * g.base_radius_mm()));
    }
  } // namespace

  bool is_root_rank() { return world_rank() == 0; }

  double reference_depth_mm(const Scene &scene)
  {
    if (scene.stiffness.reference_depth_mm > 0)
      return scene.stiffness.reference_depth_mm;
    return 3.0 * band_element_size_mm(mesh_settings(scene, scene.stiffness.fe_dimension),
                                      scene.pinion.module_mm);
  }

  StiffnessStageResult run_stiffness_stage(const Scene &scene, const fs::path &mesh_dir,
                                           PhaseTimer &timer)
  {
    return run_stiffness_stage(scene, mesh_dir, timer, StiffnessStageOptions{});
  }

  StiffnessStageResult run_stiffness_stage(const Scene &scene, const fs::path &mesh_dir,
                                           PhaseTimer &timer, const StiffnessStageOptions &options)
  {
    HG_REQUIRE_INPUT(scene.operating.torque_Nm > 0, "Operating/torque_Nm = ",
                     scene.operating.torque_Nm,
                     ": the loaded tooth contact analysis needs a positive torque");
    const int dim = scene.stiffness.fe_dimension;
    HG_REQUIRE_INPUT(dim == 3 || (scene.pinion.crowning_um == 0 && scene.gear.crowning_um == 0),
                     "Stiffness/fe_dimension = 2 cannot represent lead crowning; use 3");

    StiffnessStageResult result;
    std::unique_ptr<meshing::PairKinematics> kin;
    {
      PhaseTimer::Scope scope(timer, "geometry");
      kin = std::make_unique<meshing::PairKinematics>(make_pair(scene));
    }
    const double r_b1 = kin->pinion().base_radius_mm();
    result.load_N     = scene.operating.torque_Nm * 1.0e3 / r_b1;

    // Which teeth can carry load: pair j uses pinion tooth +j and gear tooth -j, and pairs
    // 0 .. ceil(eps) - 1 meet the path of contact during one cycle (unloaded teeth need no
    // column in the compliance table).
    const int n_pairs = static_cast<int>(std::ceil(kin->contact_ratio()));
    // A body meshed as a sector has teeth 0 .. N-1 with the central one N/2; a full gear has all.
    const auto has_tooth = [&](const int z, const int relative) {
      const int n_sector = scene.mesh.teeth_per_sector;
      if (n_sector >= z)
        return true;
      const int k = n_sector / 2 + relative;
      return k >= 0 && k < n_sector;
    };
    std::vector<int> pinion_teeth, gear_teeth;
    for (int j = 0; j < n_pairs; ++j)
      if (has_tooth(scene.pinion.teeth, j) && has_tooth(scene.gear.teeth, -j))
        {
          pinion_teeth.push_back(j);
          gear_teeth.push_back(-j);
        }
    HG_REQUIRE_INPUT(static_cast<int>(pinion_teeth.size()) == n_pairs,
                     "Mesh/teeth_per_sector = ", scene.mesh.teeth_per_sector,
                     " is too few: the contact ratio ", kin->contact_ratio(), " needs ", n_pairs,
                     " loaded teeth on each side of the sector's centre; use at least ",
                     2 * n_pairs + 1);

    const meshing::MeshSettings mesh = mesh_settings(scene, dim);
    const double h = band_element_size_mm(mesh, kin->pinion().module_mm());
    fem::FlankTableSettings table;
    table.reference_depth_mm = reference_depth_mm(scene);
    table.patch_radius_mm    = 0.5 * table.reference_depth_mm;
    HG_REQUIRE_INPUT(table.reference_depth_mm <= 0.5 * kin->pinion().module_mm(),
                     "Stiffness/reference_depth_mm = ", table.reference_depth_mm,
                     " mm is deeper than half a module (", 0.5 * kin->pinion().module_mm(),
                     " mm): the half-space cannot stand for the local deformation of a tooth "
                     "that deep");
    HG_REQUIRE_INPUT(scene.stiffness.table_roll_nodes != 1,
                     "Stiffness/table_roll_nodes = 1: the compliance table needs at least 2 nodes "
                     "across the active profile (0 = automatic)");
    HG_REQUIRE_INPUT(dim == 2 || scene.stiffness.table_face_nodes != 1,
                     "Stiffness/table_face_nodes = 1: a 3D compliance table needs at least 2 nodes "
                     "along the face (0 = automatic)");
    table.n_face             = 1; // 3D: per body, from its face width (below)
    table.split_half_space   = dim == 3 && scene.stiffness.table_half_space_split;

    on_root([&] { fs::create_directories(mesh_dir); });
    std::unique_ptr<Body> bodies[2];
    std::size_t           n_dofs_total = 0;
    const auto            A = kin->point('A'), E = kin->point('E');
    for (unsigned int b = 0; b < 2; ++b)
      {
        const auto       &gear  = kin->body(b);
        const std::string name  = b == 0 ? "pinion" : "gear";
        const double      start = b == 0 ? A.radius_pinion_mm : E.radius_gear_mm;
        const fs::path    msh   = mesh_dir / (name + ".msh");
        int               central = 0;
        double            band_max_edge_mm = 0;
        {
          PhaseTimer::Scope scope(timer, "mesh " + name);
          // gmsh runs on rank 0 only; the others read its file.
          on_root([&] {
            meshing::GearBodyMesher mesher;
            const auto quality = mesher.mesh(gear, mesh, start, msh);
            central            = quality.central_tooth;
            band_max_edge_mm   = quality.contact_band_max_edge_mm;
            progress_line("stiffness", name + " mesh: " + std::to_string(quality.n_elements) +
                                         " elements, " + std::to_string(quality.n_nodes) + " nodes" +
                                         (quality.full_gear ? " (full gear)" : ""));
          });
          if (dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
            {
              central = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, central, 0);
              band_max_edge_mm = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, band_max_edge_mm, 0);
            }
        }
        PhaseTimer::Scope scope(timer, "FE compliance " + name);
        // Tabulate the active profile, where the mesher refines the band; grid cells just
        // outside it (within the band half-width) take the value of the nearest node.
        fem::FlankTableSettings s = table;
        s.roll_min_mm = roll_at_radius(gear, start) + table.patch_radius_mm;
        s.roll_max_mm = roll_at_radius(gear, gear.tip_radius_mm()) - table.patch_radius_mm;
        s.n_roll      = std::max(8u, static_cast<unsigned int>(
                                      std::ceil((s.roll_max_mm - s.roll_min_mm) /
                                                table.reference_depth_mm)) + 1);
        if (scene.stiffness.table_roll_nodes > 0)
          s.n_roll = static_cast<unsigned int>(scene.stiffness.table_roll_nodes);
        if (dim == 3)
          {
            // Along the face the structural compliance read at depth d peaks over a width of
            // about d; bilinear interpolation between nodes much farther apart flattens the peak
            // and so lengthens the structural influence, which concentrates a crowned contact
            // (6 nodes on the paper's 20 mm face: b 10 % short, p0 8 % high, single-pair
            // stiffness 3 % low, all growing as d shrinks; docs/accuracy-stiffness.md). The
            // split table takes that peak from the half-space exactly, and its remainder needs
            // nodes about d apart; the unsplit one needs them d/2 apart.
            const double span    = gear.face_width_mm() - 2 * table.patch_radius_mm;
            const double spacing = (table.split_half_space ? face_node_spacing_per_depth_split :
                                                             face_node_spacing_per_depth) *
                                   table.reference_depth_mm;
            s.n_face = scene.stiffness.table_face_nodes > 0 ?
                         static_cast<unsigned int>(scene.stiffness.table_face_nodes) :
                         std::max(2u, static_cast<unsigned int>(std::ceil(span / spacing - 1e-9)) + 1);
          }
        const auto t0 = std::chrono::steady_clock::now();
        try
          {
            bodies[b] = make_body(dim, msh, b == 0 ? scene.pinion_material : scene.gear_material,
                                  scene, gear, central, b == 0 ? pinion_teeth : gear_teeth, s);
          }
        catch (const fem::PatchOffMeshError &e)
          {
            // The user did not ask for patches; say which scene values make the mesh too coarse.
            std::ostringstream why;
            why << "the FE mesh of the " << name << " is too coarse for the contact band: the "
                << "load patches of the compliance table have a radius of " << s.patch_radius_mm
                << " mm (half of Stiffness/reference_depth_mm; the band element size is " << h
                << " mm at Stiffness/fe_level = " << scene.stiffness.fe_level << "), but the flank elements are up to "
                << band_max_edge_mm << " mm long across the profile";
            if (dim == 3)
              why << " and " << gear.face_width_mm() / (mesh.face_width_layers *
                                                         std::pow(2.0, mesh.refinement_level))
                  << " mm along the face (face width / (Mesh/face_width_layers = "
                  << scene.mesh.face_width_layers << " x 2^level))";
            why << ", so a patch can fall between the quadrature points of a face. Raise "
                << (dim == 3 ? "Mesh/face_width_layers or " : "")
                << "Stiffness/fe_level, or Stiffness/reference_depth_mm. ("
                << e.what() << ")";
            throw InputError(why.str());
          }
        n_dofs_total += bodies[b]->n_dofs();
        const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::ostringstream line;
        line << name << " FE: " << bodies[b]->n_dofs() << " DOFs, "
             << (b == 0 ? pinion_teeth : gear_teeth).size() * s.n_roll * s.n_face
             << " load cases, " << std::fixed << std::setprecision(2) << dt << " s";
        nlohmann::json breakdown = nlohmann::json::object();
        line << " (";
        for (const auto &[phase, seconds] : bodies[b]->timer().phases())
          {
            line << (breakdown.empty() ? "" : ", ") << phase << " " << seconds;
            breakdown[phase] = seconds;
          }
        line << " s)";
        progress_line("stiffness", line.str());
        result.metadata["bodies"][name] = {{"dofs", bodies[b]->n_dofs()},
                                           {"load_cases", (b == 0 ? pinion_teeth : gear_teeth).size() *
                                                            s.n_roll * s.n_face},
                                           {"table_roll_nodes", s.n_roll},
                                           {"table_face_nodes", s.n_face},
                                           {"wall_time_s", dt},
                                           {"wall_time_breakdown_s", breakdown}};
      }

    fem::MeshCycleSettings cs;
    cs.n_positions    = scene.stiffness.positions_per_cycle;
    cs.n_harmonics    = scene.stiffness.harmonics;
    cs.profile_cells  = scene.stiffness.contact_grid_profile_points;
    cs.face_cells     = scene.stiffness.contact_grid_face_points;
    cs.hertz_exponent = scene.stiffness.hertz_exponent;
    cs.plane_strain   = dim == 2;
    cs.max_contact_iterations = static_cast<unsigned int>(scene.stiffness.contact_max_iterations);
    const fem::BodyMaterial m1{scene.pinion_material.youngs_modulus_MPa,
                               scene.pinion_material.poisson_ratio};
    const fem::BodyMaterial m2{scene.gear_material.youngs_modulus_MPa,
                               scene.gear_material.poisson_ratio};
    // tooth_coupling = decoupled: the study of what the coupling of loaded teeth does.
    const bool                          decoupled = scene.stiffness.tooth_coupling == "decoupled";
    const fem::DecoupledFlankCompliance decoupled_pinion(bodies[0]->compliance());
    const fem::DecoupledFlankCompliance decoupled_gear(bodies[1]->compliance());
    const fem::FlankCompliance &pinion_compliance =
      decoupled ? static_cast<const fem::FlankCompliance &>(decoupled_pinion) : bodies[0]->compliance();
    const fem::FlankCompliance &gear_compliance =
      decoupled ? static_cast<const fem::FlankCompliance &>(decoupled_gear) : bodies[1]->compliance();
    const fem::MeshCycle cycle(*kin, m1, m2, pinion_compliance, gear_compliance, cs);
    {
      PhaseTimer::Scope scope(timer, "contact over the mesh cycle");
      auto              t0 = std::chrono::steady_clock::now();
      result.cycle = cycle.run(result.load_N, [&](unsigned int i, const fem::PositionResult &p) {
        const auto         now = std::chrono::steady_clock::now();
        std::ostringstream line;
        line << "position " << i + 1 << "/" << cs.n_positions << "  phase " << std::fixed
             << std::setprecision(3) << p.mesh_phase << "  STE " << std::setprecision(3)
             << p.ste_mm * 1e3 << " um  k_total " << std::setprecision(1)
             << p.k_total_secant_N_per_mm * 1e-3 << " N/um  pairs " << p.pairs.size()
             << "  active cells " << p.n_active << "/" << p.n_cells << "  ("
             << std::setprecision(2) << std::chrono::duration<double>(now - t0).count() << " s)";
        progress_line("stiffness", line.str());
        t0 = now;
      });
    }

    for (const auto &[profile, face] : options.extra_contact_grids)
      {
        PhaseTimer::Scope      scope(timer, "contact over the mesh cycle (grid ladder)");
        fem::MeshCycleSettings c2 = cs;
        c2.profile_cells          = static_cast<unsigned int>(profile);
        c2.face_cells             = static_cast<unsigned int>(face);
        const fem::MeshCycle other(*kin, m1, m2, pinion_compliance, gear_compliance, c2);
        const auto           t0 = std::chrono::steady_clock::now();
        result.extra_cycles.push_back(other.run(result.load_N));
        std::ostringstream line;
        line << "contact grid " << profile << " x " << (dim == 2 ? 1 : face) << ": mean k_total "
             << std::setprecision(6) << result.extra_cycles.back().k_total.mean * 1e-3
             << " N/um  (" << std::setprecision(3)
             << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s)";
        progress_line("stiffness", line.str());
      }

    if (!options.fields_dir.empty())
      {
        PhaseTimer::Scope scope(timer, "fields");
        // A hidden partial folder next to the destination; commit_stiffness_fields renames it.
        std::string partial = temporary_path_for(options.fields_dir).string();
        if (dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
          partial = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, partial, 0);
        on_root([&] {
          fs::remove_all(partial);
          fs::create_directories(partial);
        });
        const double force_scale = dim == 2 ? 1.0 / std::min(kin->pinion().face_width_mm(),
                                                             kin->gear().face_width_mm()) :
                                              1.0;
        for (unsigned int b = 0; b < 2; ++b)
          {
            const std::string name = b == 0 ? "pinion" : "gear";
            std::vector<std::pair<double, std::string>> fields, contact;
            const auto files =
              bodies[b]->write_fields(result.cycle.positions, b == 1, force_scale, partial, name);
            for (unsigned int i = 0; i < result.cycle.positions.size(); ++i)
              {
                const auto &p = result.cycle.positions[i];
                fields.emplace_back(p.mesh_phase, files[i]);
                const auto points = bodies[b]->contact_points(p, b == 1);
                const std::string file = msg(name, "_contact_", std::setw(4), std::setfill('0'), i, ".vtu");
                contact.emplace_back(p.mesh_phase, file);
                on_root([&] {
                  std::vector<double> pair(p.cell_pair.begin(), p.cell_pair.end()), force;
                  for (std::size_t k = 0; k < p.cell_pressure_MPa.size(); ++k)
                    force.push_back(p.cell_pressure_MPa[k] * p.cell_area_mm2[k]);
                  fem::write_point_cloud_vtu(fs::path(partial) / file, points,
                                             {{"contact_pressure_MPa", p.cell_pressure_MPa},
                                              {"cell_force_N", force},
                                              {"pair", pair}});
                });
              }
            on_root([&] {
              fem::write_pvd(fs::path(partial) / (name + ".pvd"), fields);
              fem::write_pvd(fs::path(partial) / (name + "_contact.pvd"), contact);
            });
            progress_line("stiffness", msg(name, " fields: ", fields.size(), " positions"));
          }
        result.fields_partial_dir = partial;
      }

    // The dynamics' table, in SI: N/m, N/m^n, m.
    const double n      = cs.hertz_exponent;
    const auto   to_si  = [](const FourierSeries &s, const double factor) {
      dynamics::FourierSeries d;
      d.mean = s.mean * factor;
      for (unsigned int j = 0; j < s.n_harmonics(); ++j)
        {
          d.amplitudes.push_back(s.amplitudes[j] * factor);
          d.phases_rad.push_back(s.phases_rad[j]);
        }
      return d;
    };
    auto &t          = result.table;
    t.hertz_exponent = n;
    t.source         = "hertzgear stiffness (FE/half-space TCA)";
    t.k_hertz_N_per_m_pow_n = to_si(result.cycle.k_hertz, std::pow(1.0e3, n));
    std::vector<double> k_rest, unloaded;
    for (const auto &p : result.cycle.positions)
      {
        t.samples.mesh_phase.push_back(p.mesh_phase);
        t.samples.k_total_N_per_m.push_back(p.k_total_secant_N_per_mm * 1e3);
        t.samples.k_hertz_N_per_m_pow_n.push_back(p.k_hertz * std::pow(1e3, n));
        t.samples.k_rest_N_per_m.push_back(p.k_rest_N_per_mm * 1e3);
        t.samples.ste_m.push_back(p.ste_mm * 1e-3);
        t.samples.unloaded_ste_m.push_back(p.unloaded_ste_mm * 1e-3);
        k_rest.push_back(p.k_rest_N_per_mm);
        unloaded.push_back(p.unloaded_ste_mm);
      }
    const auto &phases = t.samples.mesh_phase;
    t.k_rest_N_per_m   = to_si(fit_fourier_series(phases, k_rest, cs.n_harmonics), 1e3);
    t.unloaded_ste_m   = to_si(fit_fourier_series(phases, unloaded, cs.n_harmonics), 1e-3);
    t.has_unloaded_ste = true;
    t.check();

    result.metadata["dimension"]              = dim;
    result.metadata["fe_level"]               = scene.stiffness.fe_level;
    result.metadata["fe_degree"]              = scene.stiffness.fe_degree;
    result.metadata["linear_solver"]          = scene.stiffness.linear_solver;
    if (scene.stiffness.linear_solver != "direct")
      result.metadata["linear_solver_tolerance"] = scene.stiffness.linear_solver_tolerance;
    if (scene.stiffness.tooth_coupling != "coupled")
      result.metadata["tooth_coupling"] = scene.stiffness.tooth_coupling;
    result.metadata["dofs"]                   = n_dofs_total;
    result.metadata["reference_depth_mm"]     = table.reference_depth_mm;
    result.metadata["table_half_space_split"] = table.split_half_space;
    result.metadata["load_patch_radius_mm"]   = table.patch_radius_mm;
    result.metadata["band_element_size_mm"]   = h;
    result.metadata["contact_band_half_width_mm"] = result.cycle.band_half_width_mm;
    result.metadata["contact_grid"] = {{"profile_cells", cs.profile_cells},
                                       {"face_cells", dim == 2 ? 1u : cs.face_cells}};
    return result;
  }

  void commit_stiffness_fields(const StiffnessStageResult &result, const fs::path &fields_dir)
  {
    if (result.fields_partial_dir.empty())
      return;
    on_root([&] {
      // Replace an older folder: move it aside first, so that fields_dir is never half there.
      const fs::path old = temporary_path_for(fields_dir);
      if (fs::exists(fields_dir))
        fs::rename(fields_dir, old);
      fs::rename(result.fields_partial_dir, fields_dir);
      fs::remove_all(old);
    });
  }

  std::string stiffness_csv(const StiffnessStageResult &r, const double n)
  {
    std::ostringstream os;
    os << std::setprecision(10);
    os << "position,mesh_phase,ste_um,k_total_N_per_m,k_hertz,k_rest_N_per_m,pairs_in_contact,"
          "load_share_1,load_share_2,hertz_penetration_um,contact_a_mm,contact_b_mm,"
          "peak_pressure_MPa\n";
    unsigned int i = 0;
    for (const auto &p : r.cycle.positions)
      {
        // Pair 1 is the pair that entered at phase 0, pair 2 the one ahead of it.
        double share[2] = {0, 0};
        const fem::PairState *main_pair = nullptr;
        unsigned int          n_loaded  = 0;
        for (const auto &pair : p.pairs)
          {
            if (pair.pair == 0 || pair.pair == 1)
              share[pair.pair] = pair.load_share;
            n_loaded += pair.load_share > 0;
            if (!main_pair || pair.force_N > main_pair->force_N)
              main_pair = &pair;
          }
        os << i++ << ',' << p.mesh_phase << ',' << p.ste_mm * 1e3 << ','
           << p.k_total_secant_N_per_mm * 1e3 << ',' << p.k_hertz * std::pow(1e3, n) << ','
           << p.k_rest_N_per_mm * 1e3 << ',' << n_loaded << ',' << share[0] << ',' << share[1]
           << ',' << p.hertz_penetration_mm * 1e3 << ',' << main_pair->contact_a_mm << ','
           << main_pair->contact_b_mm << ',' << main_pair->peak_pressure_MPa << '\n';
      }
    return os.str();
  }

  nlohmann::json stiffness_json(const StiffnessStageResult &r, const Scene &scene)
  {
    nlohmann::json j = nlohmann::json::parse(dynamics::stiffness_table_to_json_text(r.table));
    const auto     series = [](const FourierSeries &s, const double factor) {
      nlohmann::json o;
      o["mean"] = s.mean * factor;
      std::vector<double> a;
      for (const double v : s.amplitudes)
        a.push_back(v * factor);
      o["amplitudes"]   = a;
      o["phases_rad"]   = s.phases_rad;
      o["residual_rms"] = s.residual_rms * factor;
      return o;
    };
    j["k_total_N_per_m"]        = series(r.cycle.k_total, 1e3);
    j["ste_m"]                  = series(r.cycle.ste_mm, 1e-3);
    j["k_hertz_unit"]           = "N/m^n";
    j["mean_k_total_N_per_m"]   = r.cycle.k_total.mean * 1e3;
    j["mean_k_hertz_N_per_m_pow_n"] = r.table.k_hertz_N_per_m_pow_n.mean;
    j["mean_k_rest_N_per_m"]    = r.cycle.mean_k_rest_N_per_mm * 1e3;
    double ste_min = 1e300, ste_max = -1e300;
    for (const auto &p : r.cycle.positions)
      {
        ste_min = std::min(ste_min, p.ste_mm);
        ste_max = std::max(ste_max, p.ste_mm);
      }
    j["ste_peak_to_peak_um"] = (ste_max - ste_min) * 1e3;
    j["load_N"]              = r.load_N;
    j["harmonics"]           = scene.stiffness.harmonics;
    j["fe"]                  = r.metadata;
    j.update(provenance(scene));
    return j;
  }
} // namespace hertzgear
