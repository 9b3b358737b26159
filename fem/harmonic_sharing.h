#pragma once
// Cyclic harmonics shared with processes that have no body of their own to work on.
//
// Under mpirun the FE stage builds each full gear of a pair on one rank (stiffness/fe_tca.cc).
// The dense cut-face systems of a gear's cyclic harmonics (fem/cyclic_gear_body.h:
// H_k u^_k = q^_k, k = 0 .. N/2) are independent of each other, and on a gear with many teeth they
// are a large part of its work. A rank without a body (P > 2), or whose own body is done, helps
// the owner of another: it tells the owner that it is free; the owner, when it reaches its
// harmonics, sends it D and E (once per body), the condensed loads q and a share of the harmonics
// it has not started, and adds the helper's sum of their interface displacements to its own.
// Messages go between two ranks only, never in a collective call: an owner takes help whenever
// it comes and waits for a helper only for the result of harmonics it gave away; a helper waits
// without spinning (a test of its messages every millisecond).
//
// Per body b the messages are (tags of b): helper -> owner FREE (with its work so far, by which
// the owner sizes its share, work_levelling_shares); owner -> helper JOB (a share of
// harmonics), or STOP when the body is done; helper -> owner RESULT (its sum, or the failure of
// a harmonic, which the owner throws as its own NumericalError); helper -> owner BYE after STOP,
// with the number of FREE messages it sent, so that the owner receives every one of them.
//
// The order of the sums over harmonics depends on who solved which, so a shared body equals the
// one process's to round-off, not bit for bit.
#include <Eigen/Dense>

#include <mpi.h>

#include <deque>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace hertzgear::fem
{
  // Adds harmonic k of the block-circulant cut problem of a gear of N teeth to the interface
  // displacements u_s, s = s_min .. s_max (u must hold these sectors): factorises
  // H_k = D + w^k E + w^-k E^T (w = exp(2 pi i / N)) and solves it for the harmonic k of the
  // condensed loads q (sector -> n x m). Throws NumericalError if H_k is not positive definite.
  // `work` holds H_k and the harmonic's loads between calls, so that a run of harmonics reuses
  // their memory instead of taking fresh pages for each.
  // It also counts the harmonics solved with it and the CPU time of their factorisations and
  // solves (the process's, all its threads), which the sharing of harmonics uses as the cost of
  // one.
  struct HarmonicWorkspace
  {
    Eigen::MatrixXcd H, x;
    int              solved = 0;
    double           cpu_s  = 0;
    // CPU seconds per harmonic solved so far; 0 before the first.
    double seconds_per_harmonic() const { return solved > 0 ? cpu_s / solved : 0.0; }
  };
  void add_cyclic_harmonic(int k, int N, const Eigen::MatrixXd &D, const Eigen::MatrixXd &E,
                           const std::map<int, Eigen::MatrixXd> &q, int s_min, int s_max,
                           std::map<int, Eigen::MatrixXd> &u, HarmonicWorkspace &work);

  // The shares of `todo` harmonics that equalise the work of the processes that take them: the
  // owner's group (`group_levels`, the work done so far by each of its processes [s]) and the free
  // helpers (`helper_levels`); one harmonic costs `seconds_per_harmonic` of work. The level L
  // that the remaining work fills up to (every process below L ends at L, none above it takes
  // any) gives each helper round((L - its level) / seconds_per_harmonic) harmonics; the helpers
  // together get at most todo - 1 (the owner's group keeps one), the largest shares cut first.
  std::vector<int> work_levelling_shares(int todo, double seconds_per_harmonic,
                                         const std::vector<double> &group_levels,
                                         const std::vector<double> &helper_levels);

  class HarmonicSharing
  {
  public:
    // `owners[b]`: the rank that builds body b; `helpers[b]`: the ranks without a body that help
    // body b from the start. An owner helps every other body once its own is done. With one
    // process, or no helper at all, every call is a no-op. `on_first_help(b)` is called on the
    // owner of b when it first hands out harmonics (the FE stage gives back cores it borrowed,
    // fem/core_lending.h). `work_so_far()` is this process's work so far [s] (the FE stage's CPU
    // time; by default the process's CPU time): a helper reports it when it is free, and the
    // owner shares its harmonics so that the work comes out even (work_levelling_shares).
    HarmonicSharing(MPI_Comm comm, std::vector<int> owners, std::vector<std::vector<int>> helpers,
                    std::function<void(int)> on_first_help = {}, std::function<double()> work_so_far = {});
    HarmonicSharing(const HarmonicSharing &)            = delete;
    HarmonicSharing &operator=(const HarmonicSharing &) = delete;

    // Owner side, between its own harmonics: gives the helpers of `body` that are free their
    // shares of `todo` (taken from its back; the owner keeps at least one harmonic for itself).
    // The shares level the work (work_levelling_shares) of the free helpers, each at the work it
    // reported when it became free, and of the processes that solve the rest: `group_levels`,
    // the work of each process of the owner's group (fem/sector_group.h), or, if empty, the
    // owner alone at its work so far. `seconds_per_harmonic` is the owner's measured cost of one
    // (HarmonicWorkspace); before the owner has solved one, 0, and nothing is lent: shares need
    // the cost. A helper whose share is 0 stays free for a later call.
    void lend(int body, std::deque<int> &todo, int n_teeth, const Eigen::MatrixXd &D,
              const Eigen::MatrixXd &E, const std::map<int, Eigen::MatrixXd> &q, int s_min, int s_max,
              double seconds_per_harmonic, const std::vector<double> &group_levels = {});
    // Owner side, after its own harmonics: adds the results of every share lent since the last
    // call to u; throws NumericalError with a helper's message if one of its harmonics failed.
    void collect(int body, std::map<int, Eigen::MatrixXd> &u);

    // This rank's work is over (its bodies built, or failed): ends the help for its own bodies,
    // helps the owners of the other bodies until each says its body is done, and receives the
    // last words of every helper. Collective in effect: every rank must call it once, also after
    // a failure of its own body (it does not throw).
    void finish();

    // What this rank did as a helper, for the per-rank report: harmonics solved per body, and
    // the wall time it spent solving them [s].
    const std::map<int, int> &harmonics_helped() const { return helped; }
    double                    helping_busy_s() const { return busy_s; }

  private:
    struct Lent
    {
      int helper = 0, shares = 0;
    };
    MPI_Comm                      comm;
    int                           me = 0, size = 1;
    std::vector<int>              owners;
    std::vector<std::vector<int>> helpers; // per body, the other owners included
    std::function<void(int)>      on_first_help;
    std::function<double()>       work_so_far;
    std::set<int>                 helped_once;                 // bodies that have lent
    std::map<int, std::set<int>>  has_operator;                // body -> helpers holding D, E
    std::map<int, std::map<int, double>> waiting;              // body -> helpers free, not yet given work -> their work [s]
    std::map<int, std::map<int, int>> frees_received, shares_out; // body -> helper -> count
    std::map<int, int>            helped;
    double                        busy_s   = 0;
    bool                          finished = false;

    // D and E of each body this rank helps.
    std::map<int, std::pair<Eigen::MatrixXd, Eigen::MatrixXd>> operators;

    bool active(int body) const;
    void receive_frees(int body);
    // The BYE of each helper of `body` (those that own a body, or those that do not) and the FREE
    // messages it sent that were not received yet.
    void last_words(int body, bool of_owners);
  };
} // namespace hertzgear::fem
