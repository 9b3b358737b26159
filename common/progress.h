#pragma once
// Progress lines and phase timings on stderr, so that stdout stays clean for results
// (`hertzgear geometry --json` pipes into jq).
#include <chrono>
#include <map>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

namespace hertzgear
{
  // Where progress goes; defaults to std::cerr. Tests may silence it.
  std::ostream &progress_stream();
  void          set_progress_stream(std::ostream *stream);

  // Under mpirun, for the life of this object, the progress of every rank but 0 goes nowhere
  // (rank 0 tells it; common/processes.h).
  class QuietOtherRanks
  {
  public:
    QuietOtherRanks();
    ~QuietOtherRanks();
    QuietOtherRanks(const QuietOtherRanks &)            = delete;
    QuietOtherRanks &operator=(const QuietOtherRanks &) = delete;

  private:
    std::ostringstream sink;
    bool               quiet = false;
  };

  // "[stiffness] position 3/16  phase 0.125  ste 12.3 um  (0.42 s)"
  void progress_line(const std::string &stage, const std::string &text);

  // CPU time of this process so far, every thread, user and system [s].
  double process_cpu_seconds();

  // Accumulates wall time per named phase; prints a table like deal.II's TimerOutput summary.
  class PhaseTimer
  {
  public:
    class Scope
    {
    public:
      Scope(PhaseTimer &timer, std::string phase);
      ~Scope();
      Scope(const Scope &) = delete;
      Scope &operator=(const Scope &) = delete;

    private:
      PhaseTimer                                    &timer;
      std::string                                    phase;
      std::chrono::steady_clock::time_point          start;
    };

    void   add(const std::string &phase, double seconds);
    double seconds(const std::string &phase) const;
    double total_seconds() const;
    // Phases in the order they were first entered, with their wall time.
    const std::vector<std::pair<std::string, double>> &phases() const { return entries; }
    void print_summary(std::ostream &out) const;

  private:
    std::vector<std::pair<std::string, double>> entries;
  };
} // namespace hertzgear
