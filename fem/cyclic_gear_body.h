#pragma once
// The full gear, clamped at its bore, from one tooth sector: substructuring with a block-circulant
// interface (docs/theory-tca.md, "Full gears from one tooth").
//
// A gear of N identical teeth is N copies of a one-tooth sector, each turned by theta = 2 pi / N.
// The sector mesh has matching cut faces: the end cut B is the start cut A turned by theta, node
// for node. Let K be the sector's stiffness matrix clamped at the bore only (cut faces free) and
// S its Schur complement on the cut DoFs [A; B] (MUMPS computes S during the one sparse
// factorisation of K). With every vector in its own sector's frame, the cut between sector s-1
// and s carries the displacement u_s (A-face numbering, frame of sector s), sector s sees
// [u_s; T u_{s+1}] on its cuts (T turns each node's vector by theta), and the gear's cut problem is
// block-circulant:
//   D u_s + E u_{s+1} + E^T u_{s-1} = q_s,   D = S_AA + T^T S_BB T,   E = S_AB T,
// q_s the condensed loads. The discrete Fourier transform over the teeth, u_s = sum_k u^_k w^(ks)
// with w = exp(2 pi i / N), splits it into the N/2 + 1 dense Hermitian systems
//   H_k u^_k = q^_k,   H_k = D + w^k E + w^-k E^T,
// factorised by LAPACK (zpotrf). The same MUMPS factorisation then solves the interior block
// K_II alone (cut faces held at zero, MUMPS ICNTL(26) = 0): the condensed load of a sector is
// q = f_c - K_cI K_II^-1 f_I, and a sector with cut displacement u_c has the interior
// K_II^-1 (f_I - K_Ic u_c). Exact to round-off, at the memory of one tooth and one cut face.
//
// The harmonics are independent: with a communicator of P processes each factorises the
// harmonics k = rank, rank + P, ... and the interface displacements are summed (MPI_Allreduce);
// or helper processes that hold no sector take the harmonics this one has not started
// (fem/harmonic_sharing.h). A group of processes may also share the sector's factorisation, its
// interior solves and its harmonics (fem/sector_group.h).
#include "fem/body_compliance.h"
#include "fem/elastic_body.h"

#include <deal.II/grid/tria.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace hertzgear::fem
{
  class HarmonicSharing;
  class SectorGroup;
  class SectorFactorisation;
  struct SparseColumns;

  template <int dim>
  class CyclicGearBody : public BodyCompliance<dim>
  {
  public:
    struct Parameters
    {
      typename ElasticBody<dim>::Parameters body;     // clamped_boundary_id: the bore
      unsigned int                         n_teeth = 0;
      dealii::types::boundary_id           cut_start_id = 11; // the sector's clockwise cut (A)
      dealii::types::boundary_id           cut_end_id   = 12; // A turned by 2 pi / n_teeth (B)
      // A helical gear's section turn psi(z) = twist_rad_per_mm z (meshing::FlankSurface::
      // section_angle_rad; 0 for a spur gear): tooth t's centre at face position z lies at polar
      // angle t theta + psi(z). The sector and its cut faces twist with it; the cyclic model is
      // unchanged, a turn about the axis by theta still maps the start cut onto the end cut.
      double twist_rad_per_mm = 0;
      std::string name = "gear"; // the body's name in messages ("pinion", "gear")
      // Who shares the harmonics (each process holds the whole sector).
      MPI_Comm harmonic_communicator = MPI_COMM_SELF;
      // Called between units of work (a block of interior solves, a cyclic harmonic): the FE
      // stage lends the cores of a rank that has finished its own body here (CoreLending).
      std::function<void()> between_work_units;
      // Helper processes that take harmonics this process has not started (under mpirun, a rank
      // without a body of its own; fem/harmonic_sharing.h), and this body's index among the
      // bodies they help; no sharing when it is empty or returns null.
      std::function<HarmonicSharing *()> harmonic_sharing;
      int                                sharing_body = 0;
      // The processes that factorise and solve the sector with this one, which is its rank 0
      // (fem/sector_group.h); null or a group of one: this process alone. It must outlive the
      // body's work; the caller dismisses it.
      SectorGroup *sector_group = nullptr;
    };

    // `sector`: a serial triangulation of one tooth centred on +x (the tooth at polar angle 0),
    // whose cut faces lie at -pi/N and +pi/N; it must outlive the body.
    CyclicGearBody(const dealii::Triangulation<dim> &sector, const Parameters &parameters);
    ~CyclicGearBody() override;

    // Patch loads may only touch these boundary ids (the flank of the sector's tooth).
    void set_load_boundary_ids(const std::set<dealii::types::boundary_id> &ids);
    // Assembly, the pairing of the cut faces (InputError if they do not match), the sparse
    // factorisation with the Schur complement, and the interface blocks D and E.
    void run();

    // Loads and readings anywhere on the full gear, in the gear's frame (tooth t at polar angle
    // t theta): C(r, l) of the full gear. A load or reading on tooth t is turned into the sector
    // (by -t theta); equal local loads and readings are solved once.
    dealii::FullMatrix<double> compliance(const std::vector<PatchLoad<dim>>    &loads,
                                          const std::vector<PointReading<dim>> &readings) const override;
    double youngs_modulus() const override { return parameters.body.youngs_modulus; }
    double poisson_ratio() const override { return parameters.body.poisson_ratio; }

    // The cut-face displacements u_s (A numbering, frame of sector s) for s = s_min .. s_max of the
    // full gear under the condensed loads q (sector -> n_cut x m matrix), all harmonics.
    // `only_harmonic` >= 0 keeps that harmonic alone (tests of the transform).
    std::map<int, Eigen::MatrixXd> solve_interface(const std::map<int, Eigen::MatrixXd> &q, int s_min,
                                                   int s_max, int only_harmonic = -1) const;
    // The harmonic content of condensed loads: ||q^_k||_F for k = 0 .. N/2 (tests: a load
    // pattern that is one pure harmonic has only that one).
    std::vector<double> harmonic_norms(const std::map<int, Eigen::MatrixXd> &q) const;

    // One load case of the gear: patch loads per sector in the sector's own frame, loads[s]
    // carrying forces[s].
    struct SectorLoads
    {
      std::map<int, std::vector<PatchLoad<dim>>> loads;
      std::map<int, std::vector<double>>         forces;
    };
    // Per case, the free sector's field under each loaded sector's own load, and the condensed
    // cut loads q (sector -> n_cut x n_cases).
    struct CondensedLoads
    {
      std::vector<std::map<int, typename ElasticBody<dim>::VectorType>> free_fields; // ghosted
      std::map<int, Eigen::MatrixXd>                                    q;
    };
    CondensedLoads condense(const std::vector<SectorLoads> &cases) const;
    // Displacement fields of the sectors `sectors` of the full gear, per case; ghosted, on the
    // sector mesh, each in its sector's frame.
    std::vector<std::map<int, typename ElasticBody<dim>::VectorType>>
    sector_fields(const CondensedLoads &loads, const std::vector<int> &sectors,
                  int only_harmonic = -1) const;

    const ElasticBody<dim> &sector_body() const { return body; }
    unsigned int            n_teeth() const { return parameters.n_teeth; }
    unsigned int            n_cut_dofs() const { return static_cast<unsigned int>(cut_a.size()); }
    dealii::types::global_dof_index n_dofs() const { return body.n_dofs(); }
    // The tooth a point of the gear belongs to (its section turned back by psi(z) in 3D), and the
    // point turned into the sector.
    int                tooth_of(const dealii::Point<dim> &x) const;
    dealii::Point<dim> to_sector(const dealii::Point<dim> &x, int tooth) const;
    dealii::Tensor<1, dim> to_sector(const dealii::Tensor<1, dim> &v, int tooth) const;
    const PhaseTimer &get_timer() const { return timer; }
    // MUMPS's estimate of the largest memory per process of the sector's factorisation [MB], on
    // the group that made it (fem/sector_group.h).
    long factorisation_memory_MB() const;

  private:
    using VectorType = typename ElasticBody<dim>::VectorType;

    void pair_cut_faces();
    void factorise();
    // Interior solves K_II^-1 b_I (cut faces held at zero; the cut entries of b are ignored and
    // those of the solution are 0) for every right-hand side, in blocks. On raw columns of the
    // factorisation's block (K's size): `fill(j, b)` writes right-hand side j into its zeroed
    // column, `use(j, x)` reads its solution (constrained entries as MUMPS returns them: 0, the
    // clamped DoFs' rows of K holding their diagonal alone and their right-hand sides 0).
    void solve_interior_columns(std::size_t n_rhs, const std::function<void(std::size_t, double *)> &fill,
                                const std::function<void(std::size_t, const double *)> &use) const;
    // Interior solves read only through the functionals F (rows x K's size, no entries on cut
    // DoFs): F K_II^-1 b_j for every right-hand side j, in blocks; `fill(j, columns)` appends the
    // entries of b_j off the cut faces (rows ascending, each once) to `columns`. On a group the
    // solutions stay where MUMPS computes them (SectorFactorisation::solve_functionals).
    Eigen::MatrixXd solve_interior_functionals(const Eigen::SparseMatrix<double> &F, std::size_t n_rhs,
                                               const std::function<void(std::size_t, SparseColumns &)> &fill) const;
    // The same on vectors; `use` gets each solution with its constraints applied, ghosted.
    void solve_interior(std::vector<VectorType> &rhs,
                        const std::function<void(std::size_t, const VectorType &)> &use) const;
    Eigen::VectorXd cut_values(const double *u) const;      // [A; B]
    Eigen::VectorXd cut_values(const VectorType &u) const;
    Eigen::VectorXd cut_reaction(const double *x) const;     // (K x) on [A; B]
    Eigen::VectorXd cut_reaction(const VectorType &x) const;
    void            zero_cut_entries(double *values) const;
    // T x and T^T x on A-numbered node vectors.
    Eigen::MatrixXd turn(const Eigen::MatrixXd &x, bool transpose) const;

    const Parameters parameters;
    ElasticBody<dim> body;
    double           theta = 0;
    std::vector<dealii::types::global_dof_index> cut_a, cut_b; // node-blocked, paired
    std::vector<char> on_cut;                                  // per DoF: 1 on the cut faces A and B
    Eigen::MatrixXd D, E;
    Eigen::SparseMatrix<double, Eigen::RowMajor> K_cut; // the rows of K at [A; B]
    std::unique_ptr<SectorFactorisation> own_factors; // alone
    const SectorFactorisation           *factors = nullptr; // own_factors or the group's
    bool in_group() const;
    mutable PhaseTimer timer;
  };
} // namespace hertzgear::fem
