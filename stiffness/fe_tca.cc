#include "stiffness/fe_tca.h"
#include "stiffness/load_map.h"

#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/progress.h"
#include "contact/mesh_cycle.h"
#include "fem/body_fields.h"
#include "fem/core_lending.h"
#include "fem/cyclic_gear_body.h"
#include "fem/flank_compliance.h"
#include "fem/harmonic_sharing.h"
#include "fem/sector_group.h"
#include "common/processes.h"
#include "meshing/pair_kinematics.h"

#include <deal.II/base/mpi.h>
#include <deal.II/distributed/shared_tria.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/tria.h>

#include <array>
#include <chrono>
#include <functional>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>

#include <sys/resource.h>

namespace hertzgear::stiffness
{
  namespace fs = std::filesystem;

  namespace
  {
    // Largest spacing of the 3D compliance table's face nodes, as a multiple of the reference
    // depth d (table_face_nodes = 0). Measured on the paper's crowned pair
    // (docs/accuracy-stiffness.md, "Nodes of the compliance table, and its half-space split").
    constexpr double face_node_spacing_per_depth = 0.5;
    // The same with the half-space split of the table, which interpolates only the remainder: at
    // spacing d the single-pair stiffness is within 0.2 % and the contact within 0.3 % of d/4
    // (the same study).
    constexpr double face_node_spacing_per_depth_split = 1.0;

    double seconds_since(const std::chrono::steady_clock::time_point t0)
    {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }

    // Contact-grid cell k of a position on one body's flank (the gear's pair j is its tooth -j).
    contact::FlankPoint flank_point(const contact::PositionResult &p, const std::size_t k,
                                    const bool is_gear)
    {
      return is_gear ? contact::FlankPoint{-p.cell_pair[k], p.cell_gear_roll_mm[k], p.cell_z_mm[k]} :
                       contact::FlankPoint{p.cell_pair[k], p.cell_pinion_roll_mm[k], p.cell_z_mm[k]};
    }

    // The contact-grid cell centres of a position on a body's flank, in the body's frame.
    template <int dim>
    std::vector<std::array<double, 3>> contact_points_on(const fem::TabulatedFlankCompliance<dim> &table,
                                                         const contact::PositionResult &p, const bool is_gear)
    {
      std::vector<std::array<double, 3>> points;
      for (std::size_t k = 0; k < p.cell_pressure_MPa.size(); ++k)
        {
          const auto            load = table.patch_load(flank_point(p, k, is_gear));
          std::array<double, 3> x{0, 0, 0};
          for (unsigned int c = 0; c < dim; ++c)
            x[c] = load.centre[c];
          points.push_back(x);
        }
      return points;
    }

    struct Body
    {
      virtual ~Body() = default;
      virtual const contact::FlankCompliance &compliance() const = 0;
      virtual std::size_t                     n_dofs() const     = 0;
      // Displacement and stress of the body under the contact pressures of every position
      // (collective; one block substitution for all); returns the .pvtu names, file i for
      // positions[i]. `force_scale` turns p A [N] into the FE body's load (1/b for the
      // unit-thickness plane-strain body).
      virtual std::vector<std::string> write_fields(const std::vector<contact::PositionResult> &positions,
                                                    bool is_gear, double force_scale,
                                                    const fs::path &dir, const std::string &name) const = 0;
      // Wall-time breakdown of the FE body (assembly, factorisation, substitutions, ...).
      virtual const PhaseTimer &timer() const = 0;
      // The contact-grid cell centres on this body's flank, in its frame (z = 0 in 2D).
      virtual std::vector<std::array<double, 3>> contact_points(const contact::PositionResult &p,
                                                                bool is_gear) const = 0;
    };

    template <int dim>
    struct BodyModel : Body
    {
      // parallel::shared: every rank holds the whole (small, 2D or coarse 3D) mesh and owns a
      // partition of it; the linear algebra is distributed over MPI_COMM_WORLD.
      dealii::parallel::shared::Triangulation<dim>         triangulation;
      std::unique_ptr<fem::ElasticBody<dim>>              body;
      std::unique_ptr<fem::TabulatedFlankCompliance<dim>> table;

      BodyModel(const fs::path &msh, const Material &material, const FeSettings &fe,
                const meshing::GearGeometry &gear, const int central, const std::vector<int> &teeth,
                const fem::FlankTableSettings &table_settings)
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
        namespace tag = meshing::physical_tag;
        for (const auto &face : triangulation.active_face_iterators())
          if (face->at_boundary() &&
              (face->boundary_id() == tag::sector_cut_start || face->boundary_id() == tag::sector_cut_end))
            face->set_boundary_id(tag::bore);

        typename fem::ElasticBody<dim>::Parameters p;
        p.youngs_modulus          = material.youngs_modulus_MPa;
        p.poisson_ratio           = material.poisson_ratio;
        p.fe_degree               = fe.degree;
        p.mapping_degree          = 1; // gmsh's straight-sided cells: no curved manifold attached
        p.clamped_boundary_id     = tag::bore;
        p.linear_solver           = fem::ElasticBody<dim>::parse_linear_solver(fe.linear_solver);
        p.linear_solver_tolerance = fe.linear_solver_tolerance;
        body = std::make_unique<fem::ElasticBody<dim>>(triangulation, p);
        std::set<dealii::types::boundary_id> flanks;
        for (const int t : teeth)
          flanks.insert(static_cast<dealii::types::boundary_id>(tag::drive_flank + central + t));
        body->set_load_boundary_ids(flanks);
        body->run();
        fem::FlankTableSettings s = table_settings;
        s.teeth                  = teeth;
        table = std::make_unique<fem::TabulatedFlankCompliance<dim>>(*body, gear, central, s);
      }
      const contact::FlankCompliance &compliance() const override { return *table; }
      std::size_t                     n_dofs() const override { return body->n_dofs(); }

      std::vector<std::string> write_fields(const std::vector<contact::PositionResult> &positions,
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

      std::vector<std::array<double, 3>> contact_points(const contact::PositionResult &p,
                                                        const bool is_gear) const override
      {
        return contact_points_on(*table, p, is_gear);
      }
    };

    // The full gear from one tooth sector (fem::CyclicGearBody). The bodies of a pair are
    // independent: body b is built and tabulated by rank b mod P alone (both at once on two
    // ranks), and its table is then shared with every rank.
    struct SharedBody : Body
    {
      int    owner     = 0;
      double wall_s    = 0; // building and tabulating, on the owner
      std::function<void()> between_work_units; // on the owner, between its units of work
      std::function<double()> work_so_far;      // this rank's FE work so far [s], by which harmonics are shared
      // Helpers of its harmonics while it is built (null: none), and its index among the bodies.
      fem::HarmonicSharing *sharing      = nullptr;
      int                   sharing_body = 0;
      // The ranks that factorise and solve it with the owner (fem/sector_group.h; the owner is
      // rank 0 of it); MPI_COMM_SELF: the owner alone.
      MPI_Comm sector_group = MPI_COMM_SELF;
      // A sector whose factorisation does not fit its group's memory (MUMPS's estimate against
      // the limit per rank) is left, when `may_defer`, for every rank together: `too_large` then
      // holds MUMPS's estimate per process, the limit [MB] and the group's size.
      bool                  may_defer = false;
      std::array<long, 3>   too_large = {0, 0, 0};
      long                  factorisation_MB = 0; // MUMPS's estimate per rank of its group
      virtual std::size_t n_cut_face_dofs() const = 0;
      virtual void build_and_tabulate() = 0; // on the owner
      virtual void share()              = 0; // collective
    };

    template <int dim>
    struct CyclicBodyModel : SharedBody
    {
      const fs::path                                      msh;
      const Material                                      material;
      const FeSettings                                   &fe;
      const meshing::GearGeometry                        &gear;
      fem::FlankTableSettings                             settings;
      dealii::Triangulation<dim>                          sector; // serial, on the owner
      std::unique_ptr<fem::CyclicGearBody<dim>>           body;   // on the owner
      std::unique_ptr<fem::TabulatedFlankCompliance<dim>> table;
      std::size_t                                         dofs = 0, cut_dofs = 0;
      PhaseTimer                                          phases;

      CyclicBodyModel(fs::path msh_file, const Material &m, const FeSettings &fe_settings,
                      const meshing::GearGeometry &g, const std::vector<int> &teeth,
                      const fem::FlankTableSettings &table_settings, const int owner_rank)
        : msh(std::move(msh_file)), material(m), fe(fe_settings), gear(g), settings(table_settings)
      {
        settings.teeth = teeth;
        owner          = owner_rank;
      }

      void build_and_tabulate() override
      {
        // The group's other ranks follow this one until it is dismissed: at the end of the work,
        // or when it fails, after the body that uses its factorisation.
        fem::SectorGroup group(sector_group, work_so_far);
        try
          {
            build_and_tabulate(group);
          }
        catch (const fem::FactorisationTooLarge &e)
          {
            body.reset();
            if (!may_defer)
              throw;
            too_large = {e.estimate_MB_per_process, e.limit_MB_per_process, e.processes};
          }
        catch (...)
          {
            body.reset();
            throw;
          }
      }

      void build_and_tabulate(fem::SectorGroup &group)
      {
        namespace tag = meshing::physical_tag;
        const auto t0 = std::chrono::steady_clock::now();
        fem::read_gmsh_mesh(msh.string(), sector);
        typename fem::CyclicGearBody<dim>::Parameters p;
        p.body.youngs_modulus      = material.youngs_modulus_MPa;
        p.body.poisson_ratio       = material.poisson_ratio;
        p.body.fe_degree           = fe.degree;
        p.body.mapping_degree      = 1; // gmsh's straight-sided cells
        p.body.clamped_boundary_id = tag::bore;
        p.n_teeth                  = static_cast<unsigned int>(gear.n_teeth());
        p.cut_start_id             = tag::sector_cut_start;
        p.cut_end_id               = tag::sector_cut_end;
        p.twist_rad_per_mm         = gear.flank().section_angle_rad(1.0);
        p.name                     = gear.parameters().name;
        // Through this body's hook, which may be cleared when its caller's state ends.
        p.between_work_units = [this] {
          if (between_work_units)
            between_work_units();
        };
        p.harmonic_sharing = [this] { return sharing; };
        p.sharing_body     = sharing_body;
        p.sector_group     = group.shared() ? &group : nullptr; // the group ends with this call
        body = std::make_unique<fem::CyclicGearBody<dim>>(sector, p);
        // The sector's one tooth (tooth 0 of its mesh) carries every load, turned into it.
        body->set_load_boundary_ids({static_cast<dealii::types::boundary_id>(tag::drive_flank)});
        body->run();
        factorisation_MB = body->factorisation_memory_MB();
        table     = std::make_unique<fem::TabulatedFlankCompliance<dim>>(*body, gear, 0, settings);
        dofs      = body->n_dofs();
        cut_dofs  = body->n_cut_dofs();
        phases    = body->get_timer();
        wall_s    = seconds_since(t0);
        // Only the fields need the factorisation again: without them, free its memory now,
        // before the other body of a serial run is factorised. A group's factorisation ends with
        // the group (the fields are written by bodies of one rank, make_full_gear_bodies).
        HG_REQUIRE_INPUT(fe.fields_dir.empty() || !group.shared(),
                         "the fields of a full gear are written by its owner alone, not by a group of ranks");
        if (fe.fields_dir.empty())
          {
            body.reset();
            sector.clear();
          }
      }

      void share() override
      {
        if (processes::count() == 1)
          return;
        const auto root = static_cast<unsigned int>(owner);
        const bool mine = processes::rank() == owner;
        Eigen::MatrixXd raw;
        if (mine)
          raw = table->matrix();
        Eigen::Index n = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, raw.rows(), root);
        if (!mine)
          raw.resize(n, n);
        MPI_Bcast(raw.data(), static_cast<int>(n * n), MPI_DOUBLE, owner, MPI_COMM_WORLD);
        if (!mine)
          table = std::make_unique<fem::TabulatedFlankCompliance<dim>>(raw, material.youngs_modulus_MPa,
                                                                       material.poisson_ratio, gear, settings);
        dofs     = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, dofs, root);
        cut_dofs = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, cut_dofs, root);
        factorisation_MB = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, factorisation_MB, root);
        wall_s   = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, wall_s, root);
        const auto entries = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, phases.phases(), root);
        if (!mine)
          for (const auto &[phase, seconds] : entries)
            phases.add(phase, seconds);
      }

      const contact::FlankCompliance &compliance() const override { return *table; }
      std::size_t                     n_dofs() const override { return dofs; }
      const PhaseTimer &timer() const override { return phases; }
      std::size_t       n_cut_face_dofs() const override { return cut_dofs; }

      // The field of the gear's tooth-0 sector (the tooth of pair 0) under the contact of every
      // position, written by the owner.
      std::vector<std::string> write_fields(const std::vector<contact::PositionResult> &positions,
                                            const bool is_gear, const double force_scale,
                                            const fs::path &dir, const std::string &name) const override
      {
        std::vector<std::string> files;
        if (body)
          {
            std::vector<typename fem::CyclicGearBody<dim>::SectorLoads> cases(positions.size());
            for (std::size_t i = 0; i < positions.size(); ++i)
              {
                const auto &p = positions[i];
                for (std::size_t k = 0; k < p.cell_pressure_MPa.size(); ++k)
                  if (p.cell_pressure_MPa[k] > 0)
                    {
                      auto       load = table->patch_load(flank_point(p, k, is_gear));
                      const int  t    = body->tooth_of(load.centre);
                      load.centre     = body->to_sector(load.centre, t);
                      load.direction  = body->to_sector(load.direction, t);
                      cases[i].loads[t].push_back(load);
                      cases[i].forces[t].push_back(p.cell_pressure_MPa[k] * p.cell_area_mm2[k] * force_scale);
                    }
              }
            const auto fields = body->sector_fields(body->condense(cases), {0});
            for (std::size_t i = 0; i < positions.size(); ++i)
              files.push_back(fem::write_body_fields(body->sector_body(), fields[i].at(0), dir, name, i));
          }
        if (processes::count() > 1)
          {
            files.resize(positions.size());
            for (auto &f : files)
              f = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, f, static_cast<unsigned int>(owner));
          }
        return files;
      }

      std::vector<std::array<double, 3>> contact_points(const contact::PositionResult &p,
                                                        const bool is_gear) const override
      {
        return contact_points_on(*table, p, is_gear);
      }
    };

    double roll_at_radius(const meshing::GearGeometry &g, const double r)
    {
      return std::sqrt(std::max(0.0, r * r - g.base_radius_mm() * g.base_radius_mm()));
    }

    // The rows, fits and table of a mesh cycle (N, mm inside; SI and the units of the row names
    // outside).
    // One row of stiffness.csv from a solved position (SI in the columns' units).
    PositionRow row_of_position(const contact::PositionResult &p, const double n)
    {
      PositionRow               row;
      const contact::PairState *main_pair = nullptr;
      int                       n_loaded  = 0;
      row.load_share_1 = 0.0;
      row.load_share_2 = 0.0;
      for (const auto &pair : p.pairs)
        {
          // Pair 1 is the pair that entered at phase 0, pair 2 the one ahead of it.
          if (pair.pair == 0)
            row.load_share_1 = pair.load_share;
          if (pair.pair == 1)
            row.load_share_2 = pair.load_share;
          n_loaded += pair.load_share > 0;
          if (!main_pair || pair.force_N > main_pair->force_N)
            main_pair = &pair;
        }
      row.mesh_phase              = p.mesh_phase;
      row.ste_um                  = p.ste_mm * 1e3;
      row.k_total_N_per_m         = p.k_total_secant_N_per_mm * 1e3;
      row.k_total_tangent_N_per_m = p.k_total_tangent_N_per_mm * 1e3;
      row.k_hertz_N_per_m_pow_n   = p.k_hertz * std::pow(1e3, n);
      row.k_rest_N_per_m          = p.k_rest_N_per_mm * 1e3;
      row.pairs_in_contact        = n_loaded;
      row.hertz_penetration_um    = p.hertz_penetration_mm * 1e3;
      row.contact_a_mm            = main_pair->contact_a_mm;
      row.contact_b_mm            = main_pair->contact_b_mm;
      // The highest pressure of the position, whichever pair carries it (at a tip the entering
      // pair can carry little force at a high pressure).
      for (const auto &pair : p.pairs)
        row.peak_pressure_MPa = std::max(row.peak_pressure_MPa, pair.peak_pressure_MPa);
      row.contact_centre_z_mm     = p.contact_centre_z_mm;
      row.face_end_contact        = p.face_end_contact;
      row.tip_contact             = p.tip_contact;
      return row;
    }

    // The loaded cells of a cycle on the pinion flank.
    std::vector<ContactPatternCell> pattern_of_cycle(const contact::MeshCycleResult &cycle)
    {
      std::vector<ContactPatternCell> cells;
      for (std::size_t i = 0; i < cycle.positions.size(); ++i)
        {
          const auto &p = cycle.positions[i];
          for (std::size_t k = 0; k < p.cell_pressure_MPa.size(); ++k)
            if (p.cell_pressure_MPa[k] > 0)
              cells.push_back({static_cast<int>(i), p.cell_pair[k], p.cell_pinion_roll_mm[k],
                               p.cell_z_mm[k], p.cell_pressure_MPa[k]});
        }
      return cells;
    }

    StiffnessResult result_of_cycle(const contact::MeshCycleResult &cycle, const double n,
                                    const int harmonics)
    {
      StiffnessResult r;
      r.load_N              = cycle.load_N;
      r.harmonics           = harmonics;
      r.k_total_N_per_m     = cycle.k_total.scaled(1e3);
      r.ste_m               = cycle.ste_mm.scaled(1e-3);
      r.mean_k_rest_N_per_m = cycle.mean_k_rest_N_per_mm * 1e3;
      auto &t               = r.table;
      t.hertz_exponent      = n;
      t.source              = "hertzgear stiffness (FE/half-space TCA)";
      t.k_hertz_N_per_m_pow_n = cycle.k_hertz.scaled(std::pow(1.0e3, n));
      std::vector<double> k_rest, unloaded;
      for (const auto &p : cycle.positions)
        {
          t.samples.mesh_phase.push_back(p.mesh_phase);
          t.samples.k_total_N_per_m.push_back(p.k_total_secant_N_per_mm * 1e3);
          t.samples.k_hertz_N_per_m_pow_n.push_back(p.k_hertz * std::pow(1e3, n));
          t.samples.k_rest_N_per_m.push_back(p.k_rest_N_per_mm * 1e3);
          t.samples.ste_m.push_back(p.ste_mm * 1e-3);
          t.samples.unloaded_ste_m.push_back(p.unloaded_ste_mm * 1e-3);
          k_rest.push_back(p.k_rest_N_per_mm);
          unloaded.push_back(p.unloaded_ste_mm);
          r.rows.push_back(row_of_position(p, n));
        }
      const auto &phases = t.samples.mesh_phase;
      const auto  H      = static_cast<unsigned int>(harmonics);
      t.k_rest_N_per_m   = fit_fourier_series(phases, k_rest, H).scaled(1e3);
      t.unloaded_ste_m   = fit_fourier_series(phases, unloaded, H).scaled(1e-3);
      t.has_unloaded_ste = true;
      t.check();
      return r;
    }

    // Which teeth can carry load: pair j uses pinion tooth +j and gear tooth -j, and pairs
    // 0 .. ceil(eps_alpha) - 1 of a spur pair meet the path of contact during one cycle (unloaded
    // teeth need no column in the compliance table). A helical pair's line j lies at
    // s_A + (tau + j) p_b + k z, k b = eps_beta p_b: it meets the path [s_A, s_E] at some face
    // position for some phase tau in [0, 1) when -1 - eps_beta / 2 < j <= eps_alpha + eps_beta / 2
    // (the contact stage's pairs, contact::MeshCycle). A body meshed as a sector has teeth
    // 0 .. N-1 with the central one N/2; a full gear has all. Throws ParameterError when the
    // sector is too small.
    std::array<std::vector<int>, 2> loaded_teeth(const StiffnessInput &in,
                                                 const meshing::PairKinematics &kin)
    {
      const auto  &fe       = in.fe;
      const double eps_beta = kin.face_contact_ratio();
      const int    first    = eps_beta > 0 ? static_cast<int>(std::floor(-1 - 0.5 * eps_beta)) + 1 : 0;
      const int    last     = eps_beta > 0 ?
                                static_cast<int>(std::floor(kin.contact_ratio() + 0.5 * eps_beta + 1e-12)) :
                                static_cast<int>(std::ceil(kin.contact_ratio())) - 1;
      const int    n_pairs  = last - first + 1;
      const auto  has_tooth = [&](const int z, const int relative) {
        const int n_sector = fe.teeth_per_sector;
        if (fe.body_model == "full-gear" || n_sector >= z)
          return true;
        const int k = n_sector / 2 + relative;
        return k >= 0 && k < n_sector;
      };
      std::array<std::vector<int>, 2> teeth;
      for (int j = first; j <= last; ++j)
        if (has_tooth(in.pair.pinion.teeth, j) && has_tooth(in.pair.gear.teeth, -j))
          {
            teeth[0].push_back(j);
            teeth[1].push_back(-j);
          }
      if (static_cast<int>(teeth[0].size()) != n_pairs)
        throw ParameterError("teeth_per_sector",
                             msg(fe.teeth_per_sector, " is too few: the contact ratio ",
                                 kin.contact_ratio(), " needs ", n_pairs,
                                 " loaded teeth on each side of the sector's centre; use at least ",
                                 2 * std::max(last, -first) + 3));
      return teeth;
    }

    // One FE/half-space TCA, phase by phase; run() reads as the algorithm.
    class FeTcaRun
    {
    public:
      FeTcaRun(const StiffnessInput &input, PhaseTimer &timer)
        : input(input), fe(input.fe), timer(timer), dim(input.fe.dimension),
          mesh(fe_mesh_settings(input.fe))
      {}

      StiffnessResult run()
      {
        make_kinematics();
        choose_loaded_teeth();
        set_table_settings();
        processes::agree([&] { fs::create_directories(fe.mesh_dir); }, true);
        for (unsigned int b = 0; b < 2; ++b)
          make_mesh(b);
        fe_start     = std::chrono::steady_clock::now();
        fe_cpu_start = process_cpu_seconds();
        if (full_gear_model())
          make_full_gear_bodies();
        else
          for (unsigned int b = 0; b < 2; ++b)
            make_body_and_compliance_table(b);
        solve_contact_cycle();
        solve_extra_contact_grids();
        solve_map();
        solve_load_ladder();
        report_ranks();
        if (!fe.fields_dir.empty())
          write_fields();
        return fit();
      }

    private:
      const StiffnessInput &input;
      const FeSettings     &fe;
      PhaseTimer           &timer;
      const int             dim;
      const meshing::MeshSettings mesh;

      std::unique_ptr<meshing::PairKinematics> kin;
      double                                   load_N = 0;
      std::vector<int>                         teeth[2]; // loaded teeth of pinion and gear
      fem::FlankTableSettings                  table;
      int                                      central[2] = {0, 0};
      double                                   band_max_edge_mm[2] = {0, 0};
      std::unique_ptr<Body>                    bodies[2];
      std::size_t                              n_dofs_total = 0;
      nlohmann::json                           body_notes   = nlohmann::json::object();
      nlohmann::json                           rank_notes   = nlohmann::json::array();
      // This rank's share of the FE stage (after the meshes), for the per-rank report.
      std::chrono::steady_clock::time_point    fe_start;
      double                                   fe_cpu_start   = 0;
      nlohmann::json                           my_bodies      = nlohmann::json::array();
      nlohmann::json                           harmonics_helped = nlohmann::json::object(); // body -> count
      double                                   body_busy_s    = 0;
      double                                   contact_busy_s = 0;
      std::size_t                              contact_positions = 0;
      contact::MeshCycleSettings               cycle_settings;
      contact::MeshCycleResult                 cycle;
      std::vector<contact::MeshCycleResult>    extra_cycles;
      double                                   cycle_time_s = 0;
      std::vector<double>                      extra_cycle_time_s;
      std::vector<MapCase>                     map;
      // The load ladder's cycles (the scene's own cycle at 100 %) and their contact time.
      std::vector<contact::MeshCycleResult>    ladder;
      double                                   ladder_time_s = 0;
      fs::path                                 fields_partial_dir;

      static std::string body_name(const unsigned int b) { return b == 0 ? "pinion" : "gear"; }
      bool full_gear_model() const { return fe.body_model == "full-gear"; }

      void make_kinematics()
      {
        PhaseTimer::Scope scope(timer, "geometry");
        kin    = std::make_unique<meshing::PairKinematics>(input.pair);
        load_N = input.torque_Nm * 1.0e3 / kin->pinion().base_radius_mm();
      }

      // Which teeth can carry load: pair j uses pinion tooth +j and gear tooth -j, and pairs
      // 0 .. ceil(eps) - 1 meet the path of contact during one cycle (unloaded teeth need no
      // column in the compliance table).
      void choose_loaded_teeth()
      {
        const auto loaded = loaded_teeth(input, *kin);
        teeth[0]          = loaded[0];
        teeth[1]          = loaded[1];
      }

      void set_table_settings()
      {
        table.reference_depth_mm = fe_reference_depth_mm(fe, kin->pinion().module_mm());
        table.patch_radius_mm    = 0.5 * table.reference_depth_mm;
        table.n_face             = 1; // 3D: per body, from its face width
        table.split_half_space   = dim == 3 && fe.table_half_space_split;
      }

      void make_mesh(const unsigned int b)
      {
        const auto       &gear = kin->body(b);
        const std::string name = body_name(b);
        PhaseTimer::Scope scope(timer, "mesh " + name);
        // gmsh runs on rank 0 only; the others read its file.
        processes::agree([&] {
          meshing::GearBodyMesher mesher;
          const auto quality  = mesher.mesh(gear, mesh, active_start_radius_mm(b), msh_file(b));
          central[b]          = quality.central_tooth;
          band_max_edge_mm[b] = quality.contact_band_max_edge_mm;
          progress_line("stiffness", name + " mesh: " + std::to_string(quality.n_elements) +
                                       " elements, " + std::to_string(quality.n_nodes) + " nodes" +
                                       (quality.full_gear ? " (full gear)" : ""));
        }, true);
        if (processes::count() > 1)
          {
            central[b] = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, central[b], 0);
            band_max_edge_mm[b] =
              dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, band_max_edge_mm[b], 0);
          }
      }

      double active_start_radius_mm(const unsigned int b) const
      {
        return b == 0 ? kin->point('A').radius_pinion_mm : kin->point('E').radius_gear_mm;
      }
      fs::path msh_file(const unsigned int b) const { return fe.mesh_dir / (body_name(b) + ".msh"); }

      // The compliance table of one body: its roll nodes over the active profile (where the
      // mesher refines the band; grid cells just outside it take the value of the nearest node)
      // and its face nodes.
      fem::FlankTableSettings body_table_settings(const unsigned int b) const
      {
        const auto             &gear = kin->body(b);
        fem::FlankTableSettings s    = table;
        s.roll_min_mm = roll_at_radius(gear, active_start_radius_mm(b)) + table.patch_radius_mm;
        s.roll_max_mm = roll_at_radius(gear, gear.tip_radius_mm()) - table.patch_radius_mm;
        s.n_roll      = std::max(8u, static_cast<unsigned int>(
                                      std::ceil((s.roll_max_mm - s.roll_min_mm) /
                                                table.reference_depth_mm)) + 1);
        if (fe.table_roll_nodes > 0)
          s.n_roll = static_cast<unsigned int>(fe.table_roll_nodes);
        if (dim == 3)
          {
            // Along the face the structural compliance read at depth d peaks over a width of
            // about d; bilinear interpolation between nodes much farther apart flattens the peak
            // and so lengthens the structural influence, which concentrates a crowned contact
            // (docs/accuracy-stiffness.md). The split table takes that peak from the half-space
            // exactly, and its remainder needs nodes about d apart; the unsplit one needs them
            // d/2 apart.
            const double span    = gear.face_width_mm() - 2 * table.patch_radius_mm;
            const double spacing = (table.split_half_space ? face_node_spacing_per_depth_split :
                                                             face_node_spacing_per_depth) *
                                   table.reference_depth_mm;
            s.n_face = fe.table_face_nodes > 0 ?
                         static_cast<unsigned int>(fe.table_face_nodes) :
                         std::max(2u, static_cast<unsigned int>(std::ceil(span / spacing - 1e-9)) + 1);
          }
        return s;
      }

      void make_body_and_compliance_table(const unsigned int b)
      {
        const std::string name = body_name(b);
        PhaseTimer::Scope scope(timer, "FE compliance " + name);
        const auto        s  = body_table_settings(b);
        const auto        t0 = std::chrono::steady_clock::now();
        try
          {
            const Material &m = b == 0 ? input.pinion_material : input.gear_material;
            if (dim == 2)
              bodies[b] = std::make_unique<BodyModel<2>>(msh_file(b), m, fe, kin->body(b), central[b],
                                                         teeth[b], s);
            else
              bodies[b] = std::make_unique<BodyModel<3>>(msh_file(b), m, fe, kin->body(b), central[b],
                                                         teeth[b], s);
          }
        catch (const fem::PatchOffMeshError &e)
          {
            throw ParameterError("level", too_coarse_message(b, s, e.what()));
          }
        n_dofs_total += bodies[b]->n_dofs();
        body_busy_s += seconds_since(t0);
        my_bodies.push_back(processes::count() > 1 ? name + " (every rank)" : name);
        report_body(b, s, seconds_since(t0));
      }

      // A body built by a group, as a work unit of each of its ranks: "gear (ranks 1, 2)"; a
      // group of one is the body's name alone.
      std::string group_unit(const unsigned int b, const std::vector<int> &ranks) const
      {
        if (ranks.size() == 1)
          return body_name(b);
        std::ostringstream os;
        os << body_name(b) << " (ranks ";
        for (std::size_t i = 0; i < ranks.size(); ++i)
          os << (i ? ", " : "") << ranks[i];
        os << ")";
        return os.str();
      }

      // Both full gears at once: body b on rank b mod P. With more ranks, and without fields
      // (whose solves come after the stage's collective calls), each body is built by a group:
      // ranks 2, 3, ... join the bodies in turn, the gear with more teeth first.
      void make_full_gear_bodies()
      {
        PhaseTimer::Scope  scope(timer, "FE compliance (full gears)");
        const int          P          = processes::count();
        const bool         groups     = P > 2 && fe.fields_dir.empty();
        const unsigned int more_teeth = kin->body(1).n_teeth() >= kin->body(0).n_teeth() ? 1 : 0;
        std::vector<std::vector<int>> group_ranks(2);
        for (int r = 0; r < P; ++r)
          {
            const unsigned int b = r < 2 ? static_cast<unsigned int>(r) : ((r % 2 == 0) ? more_teeth : 1 - more_teeth);
            group_ranks[b].push_back(r);
          }
        if (P > 2)
          {
            std::ostringstream line;
            if (groups)
              {
                line << "note: " << P << " ranks for a pair on full gears: each body is factorised, solved and "
                     << "its harmonics summed by a group of ranks (";
                for (unsigned int b = 0; b < 2; ++b)
                  {
                    line << (b ? "; " : "") << body_name(b) << ": rank" << (group_ranks[b].size() > 1 ? "s " : " ");
                    for (std::size_t i = 0; i < group_ranks[b].size(); ++i)
                      line << (i ? ", " : "") << group_ranks[b][i];
                  }
                line << "), then every rank shares the contact positions (docs/accuracy-stiffness.md, \"MPI: what "
                        "runs where\")";
              }
            else
              line << "warning: " << P << " ranks, but a pair on full gears whose fields are written has two bodies, "
                   << "each built by one rank: ranks 2 to " << P - 1 << " only help with their harmonics, then share "
                   << "the contact positions (docs/accuracy-stiffness.md, \"MPI: what runs where\")";
            progress_line("stiffness", line.str());
          }
        // Every rank takes part in the split (collective); the owner of body b is rank b, rank 0
        // of its group.
        MPI_Comm group_comm = MPI_COMM_SELF;
        if (groups)
          {
            const int color = std::find(group_ranks[0].begin(), group_ranks[0].end(), processes::rank()) !=
                                  group_ranks[0].end() ? 0 : 1;
            MPI_Comm_split(MPI_COMM_WORLD, color, processes::rank(), &group_comm);
          }
        const struct FreeGroup
        {
          MPI_Comm &comm;
          ~FreeGroup()
          {
            if (comm != MPI_COMM_SELF)
              MPI_Comm_free(&comm);
          }
        } free_group{group_comm};
        fem::FlankTableSettings     s[2];
        std::unique_ptr<SharedBody> shared[2];
        bool                        deferred[2] = {false, false};
        long                        bodies_factorisation_MB[2] = {0, 0};
        int                         member_of   = -1; // the body whose group this rank joined, not owning it
        for (unsigned int b = 0; b < 2; ++b)
          {
            s[b]              = body_table_settings(b);
            const Material &m = b == 0 ? input.pinion_material : input.gear_material;
            const int owner   = static_cast<int>(b % static_cast<unsigned int>(P));
            if (dim == 2)
              shared[b] = std::make_unique<CyclicBodyModel<2>>(msh_file(b), m, fe, kin->body(b), teeth[b], s[b], owner);
            else
              shared[b] = std::make_unique<CyclicBodyModel<3>>(msh_file(b), m, fe, kin->body(b), teeth[b], s[b], owner);
            if (groups && owner == processes::rank())
              shared[b]->sector_group = group_comm;
            // Without fields (written by a body of one rank) a body too large for its group waits
            // for every rank.
            const std::size_t group_size = groups ? group_ranks[b].size() : 1;
            shared[b]->may_defer         = fe.fields_dir.empty() && static_cast<int>(group_size) < P;
          }
        // On two ranks the one that finishes first lends its cores to the other until that one
        // hands out harmonics to it. Without groups, ranks without a body help with the
        // harmonics from the start (the gear with more teeth, more harmonics, first); with groups,
        // the ranks of the group that is done first help the other's. A rank whose body is done
        // helps the other's (fem/harmonic_sharing.h).
        fem::CoreLending              lending(MPI_COMM_WORLD);
        std::vector<int>              owners = {shared[0]->owner, shared[1]->owner};
        std::vector<std::vector<int>> helpers(2);
        for (int r = 2; r < P; ++r)
          if (!groups)
            {
              helpers[more_teeth].push_back(r);
              helpers[1 - more_teeth].push_back(r);
            }
          else // a member of one body's group helps the other body once its group is done
            for (unsigned int b = 0; b < 2; ++b)
              if (std::find(group_ranks[b].begin(), group_ranks[b].end(), r) == group_ranks[b].end())
                helpers[b].push_back(r);
        const auto           fe_work = [this] { return process_cpu_seconds() - fe_cpu_start; }; // as reported
        fem::HarmonicSharing sharing(MPI_COMM_WORLD, owners, helpers, [&lending](int) { lending.give_back(); }, fe_work);
        processes::agree([&] {
          const auto end_of_own_work = [&] {
            lending.announce(); // the partner may take this rank's cores ...
            sharing.finish();   // ... until it hands out harmonics to it
            lending.finish();   // the partner waits for this rank's word before any collective
          };
          try
            {
              for (unsigned int b = 0; b < 2; ++b)
                if (shared[b]->owner == processes::rank())
                  try
                    {
                      const auto t0 = std::chrono::steady_clock::now();
                      shared[b]->between_work_units = [&lending] { lending.poll(); };
                      shared[b]->sharing            = &sharing;
                      shared[b]->sharing_body       = static_cast<int>(b);
                      shared[b]->work_so_far        = fe_work;
                      shared[b]->build_and_tabulate();
                      body_busy_s += seconds_since(t0);
                      if (shared[b]->too_large[0] == 0)
                        my_bodies.push_back(groups ? group_unit(b, group_ranks[b]) : body_name(b));
                    }
                  catch (const fem::PatchOffMeshError &e)
                    {
                      throw ParameterError("level", too_coarse_message(b, s[b], e.what()));
                    }
              if (groups && processes::rank() >= 2)
                {
                  const unsigned int b = std::find(group_ranks[0].begin(), group_ranks[0].end(),
                                                   processes::rank()) != group_ranks[0].end() ? 0 : 1;
                  body_busy_s += fem::serve_sector_group(group_comm, fe_work);
                  member_of = static_cast<int>(b);
                }
            }
          catch (...)
            {
              end_of_own_work();
              throw;
            }
          end_of_own_work();
        });
        for (const auto &[b, count] : sharing.harmonics_helped())
          harmonics_helped[body_name(static_cast<unsigned int>(b))] = count;
        body_busy_s += sharing.helping_busy_s();
        // A body too large for its group's memory: built now by every rank together, its owner
        // first (fem/sector_group.h), the factors spread over all of them.
        for (unsigned int b = 0; b < 2; ++b)
          {
            std::array<long, 3> too_large = shared[b]->too_large;
            MPI_Bcast(too_large.data(), 3, MPI_LONG, shared[b]->owner, MPI_COMM_WORLD);
            if (too_large[0] == 0)
              continue;
            progress_line("stiffness", msg(body_name(b), ": MUMPS estimates ", too_large[0], " MB per process for its "
                                           "sector's factorisation on ", too_large[2], too_large[2] == 1 ? " rank" : " ranks",
                                           ", more than the ", too_large[1], " MB per rank it may use: it is "
                                           "factorised over all ", P, " ranks, after the other body"));
            const bool owner = shared[b]->owner == processes::rank();
            MPI_Comm   all   = MPI_COMM_NULL;
            MPI_Comm_split(MPI_COMM_WORLD, 0, owner ? -1 : processes::rank(), &all);
            const struct FreeAll
            {
              MPI_Comm &comm;
              ~FreeAll() { MPI_Comm_free(&comm); }
            } free_all{all};
            group_ranks[b].clear();
            group_ranks[b].push_back(shared[b]->owner);
            for (int r = 0; r < P; ++r)
              if (r != shared[b]->owner)
                group_ranks[b].push_back(r);
            processes::agree([&] {
              const auto t0 = std::chrono::steady_clock::now();
              if (owner)
                {
                  shared[b]->sector_group = all;
                  shared[b]->may_defer    = false;
                  shared[b]->too_large    = {0, 0, 0};
                  try
                    {
                      shared[b]->build_and_tabulate();
                    }
                  catch (const fem::PatchOffMeshError &e)
                    {
                      throw ParameterError("level", too_coarse_message(b, s[b], e.what()));
                    }
                  body_busy_s += seconds_since(t0);
                }
              else
                body_busy_s += fem::serve_sector_group(all, fe_work);
              my_bodies.push_back(group_unit(b, group_ranks[b]));
            });
            deferred[b] = true;
            long per_rank = shared[b]->factorisation_MB;
            MPI_Bcast(&per_rank, 1, MPI_LONG, shared[b]->owner, MPI_COMM_WORLD);
            progress_line("stiffness", msg(body_name(b), ": factorised over ", P, " ranks (MUMPS's analysis, INFOG(16): up to ",
                                           per_rank, " MB per rank)"));
          }
        if (member_of >= 0 && !deferred[member_of])
          my_bodies.push_back(group_unit(static_cast<unsigned int>(member_of), group_ranks[static_cast<std::size_t>(member_of)]));
        for (unsigned int b = 0; b < 2; ++b)
          {
            shared[b]->between_work_units = nullptr; // `lending` ends here; later solves poll no one
            shared[b]->sharing            = nullptr; // and `sharing`: the fields' harmonics stay here
            shared[b]->share();
            bodies_factorisation_MB[b] = shared[b]->factorisation_MB;
            const double      wall = shared[b]->wall_s;
            const std::size_t cut = shared[b]->n_cut_face_dofs();
            bodies[b]             = std::move(shared[b]);
            n_dofs_total += bodies[b]->n_dofs();
            report_body(b, s[b], wall);
            body_notes[body_name(b)]["cut_face_dofs"] = cut;
            body_notes[body_name(b)]["factorisation_memory_MB_per_rank"] = bodies_factorisation_MB[b];
            body_notes[body_name(b)]["rank"]          = b % static_cast<unsigned int>(P);
            body_notes[body_name(b)]["ranks"]         = groups || deferred[b] ? group_ranks[b] : std::vector<int>{static_cast<int>(b % static_cast<unsigned int>(P))};
          }
      }

      // Per rank, gathered on every rank and printed: its work units (the bodies it built, the
      // harmonics of other ranks' bodies and the contact positions it solved), the wall time it
      // worked on them, the CPU time of its process over the FE stage (its BLAS threads
      // included), the rest of the stage, in which it waited (for another rank's body, for the
      // tables' broadcast, for the exchange of positions), and its peak memory. A body of the
      // sector model is built by every rank together.
      void report_ranks()
      {
        const double   stage_s = seconds_since(fe_start);
        const double   busy_s  = body_busy_s + contact_busy_s;
        nlohmann::json mine    = {{"rank", processes::rank()},
                                  {"work_units", my_bodies},
                                  {"harmonics_helped", harmonics_helped},
                                  {"contact_positions", contact_positions},
                                  {"busy_s", busy_s},
                                  {"cpu_s", process_cpu_seconds() - fe_cpu_start},
                                  {"idle_s", std::max(0.0, stage_s - busy_s)},
                                  {"peak_memory_GiB", process_peak_memory_GiB()}};
        rank_notes = nlohmann::json::array();
        for (const auto &text : processes::all_gather(mine.dump()))
          rank_notes.push_back(nlohmann::json::parse(text));
        for (const auto &r : rank_notes)
          {
            std::ostringstream line;
            line << "rank " << r["rank"].get<int>() << ": ";
            if (r["work_units"].empty())
              line << "no body";
            for (std::size_t u = 0; u < r["work_units"].size(); ++u)
              line << (u ? ", " : "") << r["work_units"][u].get<std::string>();
            for (const auto &[body, count] : r["harmonics_helped"].items())
              line << ", " << count.get<int>() << (count.get<int>() == 1 ? " harmonic" : " harmonics") << " of the "
                   << body;
            line << ", " << r["contact_positions"].get<std::size_t>() << " contact position" << (r["contact_positions"].get<std::size_t>() == 1 ? "" : "s") << std::fixed
                 << std::setprecision(2) << "; busy " << r["busy_s"].get<double>() << " s, CPU "
                 << r["cpu_s"].get<double>() << " s, idle " << r["idle_s"].get<double>() << " s, peak memory "
                 << r["peak_memory_GiB"].get<double>() << " GiB";
            progress_line("stiffness", line.str());
          }
      }

      // Peak resident memory of this process so far [GiB] (ru_maxrss, kB on Linux).
      static double process_peak_memory_GiB()
      {
        rusage u{};
        getrusage(RUSAGE_SELF, &u);
        return double(u.ru_maxrss) / (1024.0 * 1024.0);
      }


      // The user did not ask for patches; say which settings make the mesh too coarse.
      std::string too_coarse_message(const unsigned int b, const fem::FlankTableSettings &s,
                                     const std::string &why) const
      {
        const auto        &gear = kin->body(b);
        std::ostringstream os;
        os << fe.level << ": the FE mesh of the " << body_name(b)
           << " is too coarse for the contact band: the load patches of the compliance table have "
           << "a radius of " << s.patch_radius_mm << " mm (half of {reference_depth_mm}; the band "
           << "element size is " << mesh.band_element_size_mm(kin->pinion().module_mm())
           << " mm at this level), but the flank elements are up to " << band_max_edge_mm[b]
           << " mm long across the profile";
        if (dim == 3)
          os << " and "
             << gear.face_width_mm() / (mesh.face_width_layers * std::ldexp(1.0, mesh.refinement_level))
             << " mm along the face (face width / ({face_width_layers} = " << fe.face_width_layers
             << " x 2^level))";
        os << ", so a patch can fall between the quadrature points of a face. Raise "
           << (dim == 3 ? "{face_width_layers} or " : "") << "{level}, or {reference_depth_mm}. ("
           << why << ")";
        return os.str();
      }

      void report_body(const unsigned int b, const fem::FlankTableSettings &s, const double dt)
      {
        const std::size_t  load_cases = teeth[b].size() * s.n_roll * s.n_face;
        std::ostringstream line;
        line << body_name(b) << " FE: " << bodies[b]->n_dofs() << " DOFs, " << load_cases
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
        body_notes[body_name(b)] = {{"dofs", bodies[b]->n_dofs()},
                                    {"load_cases", load_cases},
                                    {"table_roll_nodes", s.n_roll},
                                    {"table_face_nodes", s.n_face},
                                    {"wall_time_s", dt},
                                    {"wall_time_breakdown_s", breakdown}};
      }

      const contact::FlankCompliance &compliance(const unsigned int b) const
      {
        return bodies[b]->compliance();
      }

      // A contact cycle of a stage: its kinematics, grid settings and load [N].
      struct CycleJob
      {
        const meshing::PairKinematics *kinematics = nullptr;
        contact::MeshCycleSettings     settings;
        double                         load_N = 0;
      };

      // Solved positions of one rank, for the exchange between ranks.
      struct SolvedPositions
      {
        std::vector<contact::PositionResult> positions;
        std::vector<double>                  seconds; // wall time of each solve

        template <class Archive>
        void serialize(Archive &ar, const unsigned int /*version*/)
        {
          ar &positions &seconds;
        }
      };

      // The contact cycles of a stage on the shared FE bodies, their positions shared out over the
      // ranks by their expected work (processes::share_by_work), and every rank then receives
      // every position (docs/accuracy-stiffness.md, "MPI: what runs where"). A position's solve is
      // the same code on the same compliances whichever rank runs it, and every rank assembles
      // each cycle from the same positions: the cycles do not depend on P. `done(c, cycle,
      // work_s)` is called on every rank for every cycle in order, work_s the sum of its
      // positions' solve times: with one rank as soon as the cycle is solved, on several after the
      // exchange. `position_line(c, i, p, s, rank)` is called on rank 0 for each
      // position it solves, and after the exchange for the other ranks' positions; without it, a
      // stage of several cycles on several ranks shows its progress by a line of rank 0 per cycle
      // (`label(c)`) when rank 0 has solved its part of it.
      void solve_cycles(const std::function<std::string(std::size_t)> &label, const std::vector<CycleJob> &jobs,
                        const std::function<void(std::size_t, const contact::MeshCycleResult &, double)> &done,
                        const std::function<void(std::size_t, unsigned int, const contact::PositionResult &,
                                                 double, int)> &position_line = {})
      {
        if (jobs.empty())
          return;
        // Decoupled teeth: the study of what the coupling of loaded teeth does.
        const contact::DecoupledFlankCompliance decoupled_pinion(compliance(0)), decoupled_gear(compliance(1));
        const contact::FlankCompliance &c0 =
          fe.decoupled_teeth ? static_cast<const contact::FlankCompliance &>(decoupled_pinion) : compliance(0);
        const contact::FlankCompliance &c1 =
          fe.decoupled_teeth ? static_cast<const contact::FlankCompliance &>(decoupled_gear) : compliance(1);
        std::vector<std::unique_ptr<contact::MeshCycle>> cycles;
        std::vector<std::size_t>                         first; // flat index of each cycle's position 0
        std::size_t                                      n_total = 0;
        for (const auto &job : jobs)
          {
            cycles.push_back(std::make_unique<contact::MeshCycle>(*job.kinematics, input.pinion_material,
                                                                  input.gear_material, c0, c1, job.settings));
            first.push_back(n_total);
            n_total += job.settings.n_positions;
          }
        const auto P    = static_cast<std::size_t>(processes::count());
        const auto me   = static_cast<std::size_t>(processes::rank());
        // Who solves each position (flat index k = first[c] + i), and its place in that rank's list.
        std::vector<std::size_t> owner(n_total, 0), slot(n_total, 0);
        if (P > 1)
          processes::agree([&] {
            // On a tie the rank that has worked least so far (its bodies, its help with other
            // bodies' harmonics and its earlier contact stages) takes the position. Gathered
            // first: nothing before this collective call can fail on one rank alone.
            const auto earlier = dealii::Utilities::MPI::all_gather(MPI_COMM_WORLD, body_busy_s + contact_busy_s);
            // A position's solve costs about the square of its grid's cells (the cells' dense
            // compliance matrix; two pairs' 768 cells take 3.3 times one pair's 384).
            std::vector<double> work(n_total);
            for (std::size_t c = 0; c < jobs.size(); ++c)
              for (unsigned int i = 0; i < jobs[c].settings.n_positions; ++i)
                {
                  const double cells = cycles[c]->grid_cells(cycles[c]->phase_of_position(i), jobs[c].load_N);
                  work[first[c] + i] = cells * cells;
                }
            owner = processes::share_by_work(work, P, earlier);
            std::vector<std::size_t> taken(P, 0);
            for (std::size_t k = 0; k < n_total; ++k)
              slot[k] = taken[owner[k]]++;
            if (P > n_total)
              {
                std::vector<std::size_t> none;
                for (std::size_t r = 0; r < P; ++r)
                  if (taken[r] == 0)
                    none.push_back(r);
                std::ostringstream list;
                for (std::size_t i = 0; i < none.size(); ++i)
                  list << (i == 0 ? "" : ", ") << none[i];
                progress_line("stiffness", msg("warning: ", P, " ranks for the ", n_total, " contact positions of ",
                                               jobs.size() == 1 ? label(0) : msg(label(0), " .. ", label(jobs.size() - 1)),
                                               ": rank", none.size() == 1 ? " " : "s ", list.str(),
                                               none.size() == 1 ? " has" : " have", " none"));
              }
          });
        const auto t0   = std::chrono::steady_clock::now();
        const auto finish = [&](const std::size_t c, std::vector<contact::PositionResult> positions,
                                const double work_s) {
          auto result = cycles[c]->assemble(jobs[c].load_N, std::move(positions));
          // The load face band is sized from Hertz; say where the contact outgrew it.
          const auto enlarged = std::count_if(result.positions.begin(), result.positions.end(),
                                              [](const auto &p) { return p.face_band_enlargements > 0; });
          if (enlarged > 0)
            progress_line("stiffness", msg("note: at ", jobs[c].load_N, " N the contact grid's face band was "
                                           "enlarged at ", enlarged, " of ", result.positions.size(),
                                           " positions (the contact outgrew ", jobs[c].settings.face_band_semi_axes,
                                           " Hertz semi-axes along the face)"));
          done(c, result, work_s);
        };

        // This rank's positions, in order; a failure on any rank ends every rank with it.
        SolvedPositions mine;
        std::size_t     solved_by_me = 0;
        processes::agree([&] {
          for (std::size_t c = 0; c < jobs.size(); ++c)
            {
              std::size_t solved_here = 0;
              double      here_s      = 0;
              for (unsigned int i = 0; i < jobs[c].settings.n_positions; ++i)
                {
                  if (owner[first[c] + i] != me)
                    continue;
                  const auto start = std::chrono::steady_clock::now();
                  auto       p     = cycles[c]->solve_position(cycles[c]->phase_of_position(i), jobs[c].load_N);
                  const double s   = seconds_since(start);
                  ++solved_here;
                  ++solved_by_me;
                  here_s += s;
                  if (position_line && me == 0)
                    position_line(c, i, p, s, 0);
                  mine.positions.push_back(std::move(p));
                  mine.seconds.push_back(s);
                }
              if (P == 1)
                {
                  // One rank: the cycle is complete.
                  auto positions = std::move(mine.positions);
                  mine           = {};
                  finish(c, std::move(positions), here_s);
                }
              else if (me == 0 && !position_line && jobs.size() > 1)
                progress_line("stiffness", msg(label(c), ": ", solved_here, " of its ",
                                               jobs[c].settings.n_positions, " positions solved on rank 0 (",
                                               std::fixed, std::setprecision(2), here_s, " s)"));
            }
        });
        contact_busy_s += seconds_since(t0);
        contact_positions += solved_by_me;
        if (P == 1)
          return;

        // Every rank's positions on every rank; position k is the slot[k]-th of rank owner[k].
        const auto all = dealii::Utilities::MPI::all_gather(MPI_COMM_WORLD, mine);
        for (std::size_t c = 0; c < jobs.size(); ++c)
          {
            std::vector<contact::PositionResult> positions;
            double                               work_s = 0;
            for (unsigned int i = 0; i < jobs[c].settings.n_positions; ++i)
              {
                const std::size_t k = first[c] + i, r = owner[k], j = slot[k];
                positions.push_back(all[r].positions.at(j));
                work_s += all[r].seconds.at(j);
                if (position_line && r != 0)
                  position_line(c, i, positions.back(), all[r].seconds.at(j), static_cast<int>(r));
              }
            finish(c, std::move(positions), work_s);
          }
      }

      void solve_contact_cycle()
      {
        auto &cs       = cycle_settings;
        cs             = fe_contact_grid_settings(input);
        cs.n_positions = static_cast<unsigned int>(input.positions_per_cycle);
        cs.n_harmonics = static_cast<unsigned int>(input.harmonics);
        cs.plane_strain = dim == 2;
        PhaseTimer::Scope scope(timer, "contact over the mesh cycle");
        const auto        t0 = std::chrono::steady_clock::now();
        solve_cycles(
          [](std::size_t) { return std::string("the mesh cycle"); }, {{kin.get(), cs, load_N}},
          [&](std::size_t, const contact::MeshCycleResult &c, double) { cycle = c; },
          [&](std::size_t, const unsigned int i, const contact::PositionResult &p, const double s, const int r) {
            std::ostringstream line;
            line << "position " << i + 1 << "/" << cs.n_positions << "  phase " << std::fixed
                 << std::setprecision(3) << p.mesh_phase << "  STE " << std::setprecision(3)
                 << p.ste_mm * 1e3 << " um  k_total " << std::setprecision(1)
                 << p.k_total_secant_N_per_mm * 1e-3 << " N/um  pairs " << p.pairs.size()
                 << "  active cells " << p.n_active << "/" << p.n_cells << "  (" << std::setprecision(2)
                 << s << " s" << (processes::count() > 1 ? msg(", rank ", r) : std::string()) << ")";
            progress_line("stiffness", line.str());
          });
        cycle_time_s         = seconds_since(t0);
        const auto face_end  = std::count_if(cycle.positions.begin(), cycle.positions.end(),
                                            [](const auto &p) { return p.face_end_contact; });
        if (face_end > 0)
          progress_line("stiffness", msg("warning: the contact reaches a face end at ", face_end, " of ",
                                         cycle.positions.size(),
                                         " positions (edge contact; column face_end_contact)"));
      }

      // The contact-grid ladder of `hertzgear accuracy stiffness`: the same FE bodies. Each
      // grid's time is its contact work (the sum of its positions' solves).
      void solve_extra_contact_grids()
      {
        if (fe.extra_contact_grids.empty())
          return;
        PhaseTimer::Scope     scope(timer, "contact over the mesh cycle (grid ladder)");
        std::vector<CycleJob> jobs;
        for (const auto &[profile, face] : fe.extra_contact_grids)
          {
            contact::MeshCycleSettings cs = cycle_settings;
            cs.profile_cells              = static_cast<unsigned int>(profile);
            cs.face_cells                 = static_cast<unsigned int>(face);
            jobs.push_back({kin.get(), cs, load_N});
          }
        const auto label = [&](const std::size_t c) {
          return msg("contact grid ", jobs[c].settings.profile_cells, " x ", dim == 2 ? 1u : jobs[c].settings.face_cells);
        };
        solve_cycles(label, jobs, [&](std::size_t c, const contact::MeshCycleResult &cyc, double work_s) {
          extra_cycles.push_back(cyc);
          extra_cycle_time_s.push_back(work_s);
          std::ostringstream line;
          line << "contact grid " << jobs[c].settings.profile_cells << " x "
               << (dim == 2 ? 1u : jobs[c].settings.face_cells) << ": mean k_total " << std::setprecision(6)
               << cyc.k_total.mean * 1e-3 << " N/um  (" << std::setprecision(3) << work_s << " s)";
          progress_line("stiffness", line.str());
        });
      }

      // The load and design map: every case a further contact cycle on the same FE bodies, its
      // time the contact work of its positions.
      void solve_map()
      {
        const auto cases = map_cases(input);
        if (cases.empty())
          return;
        PhaseTimer::Scope scope(timer, "load and design map");
        const auto        n = input.hertz_exponent;
        std::vector<std::unique_ptr<meshing::PairKinematics>> kinematics;
        std::vector<CycleJob>                                 jobs;
        std::vector<MapCase>                                  solved = cases;
        for (auto &mc : solved)
          {
            kinematics.push_back(std::make_unique<meshing::PairKinematics>(map_case_pair(input, mc)));
            mc.load_N = mc.torque_Nm * 1.0e3 / kinematics.back()->pinion().base_radius_mm();
            jobs.push_back({kinematics.back().get(), cycle_settings, mc.load_N});
          }
        const auto label = [&](const std::size_t c) { return msg("map ", c + 1, "/", jobs.size()); };
        solve_cycles(label, jobs, [&](std::size_t c, const contact::MeshCycleResult &cyc, double work_s) {
          MapCase &mc       = solved[c];
          mc.contact_time_s = work_s;
          for (const auto &p : cyc.positions)
            mc.rows.push_back(row_of_position(p, n));
          mc.pattern = pattern_of_cycle(cyc);
          report_map_case(c, cases.size(), mc);
          map.push_back(std::move(mc));
        });
      }

      // The load ladder of the FE force law: the mesh cycle at every load of the ladder on the
      // same FE bodies (the scene's own cycle serves 100 %).
      void solve_load_ladder()
      {
        const auto &percents = input.load_ladder_percent;
        if (percents.empty())
          return;
        PhaseTimer::Scope scope(timer, "load ladder");
        const auto        start = std::chrono::steady_clock::now();
        // A rung is its approach and Hertzian part per position: no tangent stiffness.
        auto rung_settings    = cycle_settings;
        rung_settings.tangent = false;
        // Every rung but 100 % is a cycle to solve: rung j is job job_of_rung[j], job c rung rung_of_job[c].
        std::vector<CycleJob>    jobs;
        std::vector<std::size_t> job_of_rung(percents.size(), 0), rung_of_job;
        for (std::size_t j = 0; j < percents.size(); ++j)
          if (percents[j] != 100.0)
            {
              job_of_rung[j] = jobs.size();
              rung_of_job.push_back(j);
              jobs.push_back({kin.get(), rung_settings, load_N * percents[j] / 100.0});
            }
        std::vector<contact::MeshCycleResult> rungs(jobs.size());
        std::vector<double>                   work(jobs.size(), 0.0);
        std::size_t                           next = 0; // the next rung to report
        // Rungs are reported in ladder order, each as soon as it and the rungs below it are known.
        const auto report = [&](const std::size_t known_jobs) {
          for (; next < percents.size(); ++next)
            {
              const bool nominal = percents[next] == 100.0;
              if (!nominal && job_of_rung[next] >= known_jobs)
                return;
              ladder.push_back(nominal ? cycle : std::move(rungs[job_of_rung[next]]));
              double a_min = 1e300, a_max = 0, ah_mean = 0, a_mean = 0;
              for (const auto &p : ladder.back().positions)
                {
                  a_min = std::min(a_min, p.approach_mm);
                  a_max = std::max(a_max, p.approach_mm);
                  a_mean += p.approach_mm / ladder.back().positions.size();
                  ah_mean += p.hertz_penetration_mm / ladder.back().positions.size();
                }
              std::ostringstream line;
              line << "ladder " << next + 1 << "/" << percents.size() << "  load " << std::setprecision(5)
                   << ladder.back().load_N << " N (" << percents[next] << " %):  approach "
                   << std::fixed << std::setprecision(3) << a_min * 1e3 << " .. " << a_max * 1e3
                   << " um, Hertzian part " << std::setprecision(1) << 100.0 * ah_mean / a_mean
                   << " %  (";
              if (nominal)
                line << "the scene's cycle)";
              else
                line << std::setprecision(2) << work[job_of_rung[next]] << " s)";
              progress_line("stiffness", line.str());
            }
        };
        const auto label = [&](const std::size_t c) { return msg("ladder ", rung_of_job[c] + 1, "/", percents.size()); };
        solve_cycles(label, jobs, [&](std::size_t c, const contact::MeshCycleResult &cyc, double work_s) {
          rungs[c] = cyc;
          work[c]  = work_s;
          report(c + 1);
        });
        report(jobs.size());
        ladder_time_s = seconds_since(start);
      }

      // The ladder's table entry (SI). The contact analysis must give approaches that grow with
      // the load: where it does not, its contact grid is too coarse for rungs that close.
      table::LoadLadder load_ladder() const
      {
        table::LoadLadder l;
        l.nominal_load_N = load_N;
        for (const auto &c : ladder)
          {
            l.load_N.push_back(c.load_N);
            l.approach_m.emplace_back();
            l.hertz_approach_m.emplace_back();
            for (const auto &p : c.positions)
              {
                l.approach_m.back().push_back(p.approach_mm * 1e-3);
                l.hertz_approach_m.back().push_back(p.hertz_penetration_mm * 1e-3);
              }
          }
        try
          {
            l.check("the FE load ladder");
          }
        catch (const InputError &e)
          {
            // A step of the discretisation between two rungs is what finer grids or rungs
            // further apart cure.
            throw NumericalError(msg(e.what(), ". A finer contact grid ({contact_grid_profile_cells}, "
                                               "{contact_grid_face_cells}) or loads further apart "
                                               "({load_ladder_percent}) resolve a step of the grid"));
          }
        return l;
      }

      void report_map_case(const std::size_t c, const std::size_t n_cases, const MapCase &mc) const
      {
        double ste_min = 1e300, ste_max = -1e300, p_max = 0;
        int    face_end = 0;
        for (const auto &row : mc.rows)
          {
            ste_min = std::min(ste_min, row.ste_um);
            ste_max = std::max(ste_max, row.ste_um);
            p_max   = std::max(p_max, row.peak_pressure_MPa);
            face_end += row.face_end_contact.value_or(false);
          }
        std::ostringstream line;
        line << "map " << c + 1 << "/" << n_cases << "  torque " << std::setprecision(5) << mc.torque_Nm
             << " N m (" << mc.torque_percent << " %)  crowning " << mc.pinion_crowning_mm * 1e3
             << (mc.gear_crowning_mm != mc.pinion_crowning_mm ? msg("/", mc.gear_crowning_mm * 1e3) : "")
             << " um  misalignment " << mc.mesh_misalignment_mm * 1e3 << " um  f_Hb "
             << mc.pinion_helix_slope_deviation_mm * 1e3
             << (mc.gear_helix_slope_deviation_mm != 0 ? msg("/", mc.gear_helix_slope_deviation_mm * 1e3) : "")
             << " um:  STE p-p "
             << std::fixed << std::setprecision(3) << ste_max - ste_min << " um  peak pressure "
             << std::setprecision(0) << p_max << " MPa  (" << std::setprecision(2) << mc.contact_time_s
             << " s)";
        progress_line("stiffness", line.str());
        if (face_end > 0)
          progress_line("stiffness",
                        msg("warning: map ", c + 1, ": the contact reaches a face end at ", face_end,
                            " of ", mc.rows.size(), " positions (edge contact; column face_end_contact)"));
      }

      void write_fields()
      {
        PhaseTimer::Scope scope(timer, "fields");
        // A hidden partial folder next to the destination; the caller renames it when the
        // other artifacts are written.
        std::string partial = temporary_path_for(fe.fields_dir).string();
        if (processes::count() > 1)
          partial = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, partial, 0);
        processes::agree([&] {
          fs::remove_all(partial);
          fs::create_directories(partial);
        }, true);
        const double force_scale =
          dim == 2 ? 1.0 / std::min(kin->pinion().face_width_mm(), kin->gear().face_width_mm()) : 1.0;
        for (unsigned int b = 0; b < 2; ++b)
          write_body_fields(b, partial, force_scale);
        fields_partial_dir = partial;
      }

      void write_body_fields(const unsigned int b, const fs::path &partial, const double force_scale) const
      {
        const std::string name = body_name(b);
        std::vector<std::pair<double, std::string>> fields, contact_files;
        const auto files = bodies[b]->write_fields(cycle.positions, b == 1, force_scale, partial, name);
        for (unsigned int i = 0; i < cycle.positions.size(); ++i)
          {
            const auto &p = cycle.positions[i];
            fields.emplace_back(p.mesh_phase, files[i]);
            const auto        points = bodies[b]->contact_points(p, b == 1);
            const std::string file = msg(name, "_contact_", std::setw(4), std::setfill('0'), i, ".vtu");
            contact_files.emplace_back(p.mesh_phase, file);
            processes::agree([&] {
              std::vector<double> pair(p.cell_pair.begin(), p.cell_pair.end()), force;
              for (std::size_t k = 0; k < p.cell_pressure_MPa.size(); ++k)
                force.push_back(p.cell_pressure_MPa[k] * p.cell_area_mm2[k]);
              fem::write_point_cloud_vtu(partial / file, points,
                                         {{"contact_pressure_MPa", p.cell_pressure_MPa},
                                          {"cell_force_N", force},
                                          {"pair", pair}});
            }, true);
          }
        processes::agree([&] {
          fem::write_pvd(partial / (name + ".pvd"), fields);
          fem::write_pvd(partial / (name + "_contact.pvd"), contact_files);
        }, true);
        progress_line("stiffness", msg(name, " fields: ", fields.size(), " positions"));
      }

      // The dynamics' table in SI (N/m, N/m^n, m) and the record of the FE settings.
      StiffnessResult fit() const
      {
        StiffnessResult r = result_of_cycle(cycle, input.hertz_exponent, input.harmonics);
        r.contact_time_s  = cycle_time_s;
        for (std::size_t k = 0; k < extra_cycles.size(); ++k)
          {
            r.extra_grids.push_back(result_of_cycle(extra_cycles[k], input.hertz_exponent, input.harmonics));
            r.extra_grids.back().contact_time_s = extra_cycle_time_s[k];
          }
        r.fields_partial_dir = fields_partial_dir;
        r.pattern            = pattern_of_cycle(cycle);
        r.map                = map;
        if (!ladder.empty())
          {
            r.table.ladder = load_ladder();
            r.notes["load_ladder"] = {{"rungs", ladder.size()},
                                      {"load_percent", input.load_ladder_percent},
                                      {"contact_time_s", ladder_time_s}};
          }
        r.face_width_mm      = kin->face_width_mm();
        r.pinion_active_roll_min_mm = kin->point('A').roll_distance_mm;
        r.pinion_active_roll_max_mm = kin->point('E').roll_distance_mm;
        r.notes_key          = "fe";
        auto &m              = r.notes;
        m["bodies"]          = body_notes;
        if (!rank_notes.empty())
          m["ranks"] = rank_notes;
        m["dimension"]       = dim;
        m["fe_level"]        = fe.level;
        m["fe_degree"]       = fe.degree;
        m["body_model"]      = fe.body_model == "full-gear" ? "full gear (cyclic, one tooth sector)" :
                               fe.teeth_per_sector >= std::min(input.pair.pinion.teeth, input.pair.gear.teeth) ?
                                                        "full gear (meshed whole)" :
                                                        msg(fe.teeth_per_sector, "-tooth sector, cuts clamped");
        m["linear_solver"]   = fe.linear_solver;
        if (fe.linear_solver != "direct")
          m["linear_solver_tolerance"] = fe.linear_solver_tolerance;
        if (fe.decoupled_teeth)
          m["tooth_coupling"] = "decoupled";
        m["dofs"]                       = n_dofs_total;
        m["reference_depth_mm"]         = table.reference_depth_mm;
        m["table_half_space_split"]     = table.split_half_space;
        m["load_patch_radius_mm"]       = table.patch_radius_mm;
        m["band_element_size_mm"]       = mesh.band_element_size_mm(kin->pinion().module_mm());
        m["contact_band_half_width_mm"] = cycle.band_half_width_mm;
        m["contact_grid"] = {{"profile_cells", cycle_settings.profile_cells},
                             {"face_cells", dim == 2 ? 1u : cycle_settings.face_cells}};
        // Recorded where the band follows the load (a crowned spur pair in 3D with the load face
        // extent); elsewhere the grid covers the whole face whatever the key says.
        if (cycle.face_band_follows_load)
          {
            unsigned int enlarged = 0;
            for (const auto &p : cycle.positions)
              enlarged += p.face_band_enlargements > 0;
            m["contact_grid"]["face_extent"]     = "load";
            m["contact_grid"]["face_band_mm"]    = {cycle.face_band_min_mm, cycle.face_band_max_mm};
            m["contact_grid"]["face_band_enlarged_positions"] = enlarged;
          }
        return r;
      }
    };

    class FeTcaSource : public StiffnessSource
    {
    public:
      FeTcaSource()
        : StiffnessSource("fem", "meshing (gmsh) and FE contact over the mesh cycle (deal.II)")
      {}
      bool uses_fe() const override { return true; }
      bool tabulates_unloaded_ste() const override { return true; }

      void check(const StiffnessInput &input) const override
      {
        const auto &fe = input.fe;
        // A helical pair's contact lines cross the face: its bodies are 3D (the sections turned
        // along the face, docs/geometry.md "Meshes").
        if (fe.dimension != 3 && input.pair.pinion.helix_angle_rad != 0)
          throw ParameterError("dimension",
                               msg(fe.dimension, " cannot represent a helical pair (helix angle ",
                                   input.pair.pinion.helix_angle_rad * 180 / M_PI,
                                   " deg, {pinion.helix_angle_rad}): its contact lines cross the "
                                   "face; use 3"));
        // Its layers along the face must carry the twist: refused here, before any work, by the
        // mesher's own rule (each body from the start of its active profile, as it is meshed).
        if (fe.dimension == 3 && input.pair.pinion.helix_angle_rad != 0)
          {
            const meshing::PairKinematics kin(input.pair);
            const auto                    mesh = fe_mesh_settings(fe);
            meshing::require_layers_for_twist(kin, mesh);
          }
        if (!(input.torque_Nm > 0))
          throw ParameterError("torque_Nm", msg(input.torque_Nm, ": the loaded tooth contact "
                                                                 "analysis needs a positive torque"));
        if (fe.dimension != 3 && (input.pair.pinion.crowning_mm != 0 || input.pair.gear.crowning_mm != 0))
          throw ParameterError("dimension", msg(fe.dimension, " cannot represent lead crowning; use 3"));
        // The plane-strain model has one face column at mid-face, where a misalignment or a lead
        // modification (each varying along the face width) removes nothing: it would be ignored.
        if (fe.dimension != 3)
          {
            const std::pair<const char *, double> along_face[] = {
              {"mesh_misalignment_mm", input.pair.mesh_misalignment_mm},
              {"axis_inclination_mm", input.pair.axis_inclination_mm},
              {"axis_deviation_mm", input.pair.axis_deviation_mm},
              {"pinion.helix_slope_deviation_mm", input.pair.pinion.helix_slope_deviation_mm},
              {"gear.helix_slope_deviation_mm", input.pair.gear.helix_slope_deviation_mm},
              {"pinion.lead_end_relief_mm", input.pair.pinion.lead_end_relief_mm},
              {"gear.lead_end_relief_mm", input.pair.gear.lead_end_relief_mm}};
            for (const auto &[field, value_mm] : along_face)
              if (value_mm != 0)
                throw ParameterError("dimension",
                                     msg(fe.dimension, " cannot represent {", field, "} = ",
                                         value_mm * 1e3, " um, which varies along the face width: "
                                         "misalignment and lead modifications need the 3D model; "
                                         "use 3"));
          }
        if (fe.body_model == "full-gear" && fe.linear_solver != "direct")
          throw ParameterError("linear_solver",
                               msg(fe.linear_solver, ": the full-gear body model ({body_model}) takes "
                                                     "its cut-face Schur complement from the direct "
                                                     "solver's factorisation; use direct, or "
                                                     "{body_model} = sector"));
        if (fe.body_model != "full-gear" && fe.body_model != "sector")
          throw ParameterError("body_model", msg(fe.body_model, ": full-gear or sector"));
        const double module_mm = input.pair.pinion.module_mm;
        const double depth     = fe_reference_depth_mm(fe, module_mm);
        if (!(depth <= 0.5 * module_mm))
          throw ParameterError("reference_depth_mm",
                               msg(depth, " mm is deeper than half a module (", 0.5 * module_mm,
                                   " mm): the half-space cannot stand for the local deformation "
                                   "of a tooth that deep"));
        check_map(input);
        check_load_ladder(input);
        loaded_teeth(input, meshing::PairKinematics(input.pair));
        if (fe.table_roll_nodes == 1)
          throw ParameterError("table_roll_nodes", "1: the compliance table needs at least 2 nodes "
                                                   "across the active profile (0 = automatic)");
        if (fe.dimension == 3 && fe.table_face_nodes == 1)
          throw ParameterError("table_face_nodes", "1: a 3D compliance table needs at least 2 "
                                                   "nodes along the face (0 = automatic)");
      }

      StiffnessResult compute(const StiffnessInput &input, PhaseTimer &timer) const override
      {
        check(input);
        return FeTcaRun(input, timer).run();
      }
    };
  } // namespace

  meshing::MeshSettings fe_mesh_settings(const FeSettings &fe)
  {
    meshing::MeshSettings s;
    s.dimension         = fe.dimension;
    s.teeth_per_sector  = fe.body_model == "full-gear" ? 1 : fe.teeth_per_sector;
    s.face_width_layers = fe.face_width_layers;
    s.refinement_level  = fe.level;
    return s;
  }

  double fe_reference_depth_mm(const FeSettings &fe, const double module_mm)
  {
    if (fe.reference_depth_mm > 0)
      return fe.reference_depth_mm;
    return 3.0 * fe_mesh_settings(fe).band_element_size_mm(module_mm);
  }

  contact::MeshCycleSettings fe_contact_grid_settings(const StiffnessInput &input)
  {
    const FeSettings          &fe = input.fe;
    contact::MeshCycleSettings cs;
    cs.profile_cells          = static_cast<unsigned int>(fe.contact_grid_profile_cells);
    cs.face_cells             = static_cast<unsigned int>(fe.contact_grid_face_cells);
    cs.face_extent            = fe.contact_grid_face_extent == "load" ?
                                  contact::MeshCycleSettings::FaceExtent::load :
                                  contact::MeshCycleSettings::FaceExtent::face_width;
    cs.hertz_exponent         = input.hertz_exponent;
    cs.max_contact_iterations = static_cast<unsigned int>(fe.contact_max_iterations);
    return cs;
  }

  const StiffnessSource &fe_tca_source() { return the_source<FeTcaSource>(); }
} // namespace hertzgear::stiffness
