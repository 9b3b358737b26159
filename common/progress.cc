#include "common/progress.h"

#include <ctime>

#include <iomanip>
#include "common/processes.h"

#include <iostream>

namespace hertzgear
{
  namespace
  {
    std::ostream *current_progress = &std::cerr;
  }

  std::ostream &progress_stream() { return *current_progress; }

  void set_progress_stream(std::ostream *stream)
  {
    current_progress = stream ? stream : &std::cerr;
  }

  QuietOtherRanks::QuietOtherRanks() : quiet(!processes::is_root())
  {
    if (quiet)
      set_progress_stream(&sink);
  }

  QuietOtherRanks::~QuietOtherRanks()
  {
    if (quiet)
      set_progress_stream(nullptr);
  }

  void progress_line(const std::string &stage, const std::string &text)
  {
    progress_stream() << "[" << stage << "] " << text << std::endl;
  }

  PhaseTimer::Scope::Scope(PhaseTimer &timer, std::string phase)
    : timer(timer), phase(std::move(phase)), start(std::chrono::steady_clock::now())
  {}

  PhaseTimer::Scope::~Scope()
  {
    const auto end = std::chrono::steady_clock::now();
    timer.add(phase, std::chrono::duration<double>(end - start).count());
  }

  void PhaseTimer::add(const std::string &phase, double seconds)
  {
    for (auto &entry : entries)
      if (entry.first == phase)
        {
          entry.second += seconds;
          return;
        }
    entries.emplace_back(phase, seconds);
  }

  double PhaseTimer::seconds(const std::string &phase) const
  {
    for (const auto &entry : entries)
      if (entry.first == phase)
        return entry.second;
    return 0.0;
  }

  double PhaseTimer::total_seconds() const
  {
    double total = 0;
    for (const auto &entry : entries)
      total += entry.second;
    return total;
  }

  void PhaseTimer::print_summary(std::ostream &out) const
  {
    const double total = total_seconds();
    out << "+------------------------------------------+------------+--------+\n"
        << "| phase                                    | wall [s]   | share  |\n"
        << "+------------------------------------------+------------+--------+\n";
    for (const auto &[name, t] : entries)
      out << "| " << std::left << std::setw(40) << name << " | " << std::right << std::setw(10)
          << std::fixed << std::setprecision(3) << t << " | " << std::setw(5)
          << std::setprecision(1) << (total > 0 ? 100.0 * t / total : 0.0) << "% |\n";
    out << "+------------------------------------------+------------+--------+\n"
        << "| total                                    | " << std::setw(10) << std::setprecision(3)
        << total << " |        |\n"
        << "+------------------------------------------+------------+--------+" << std::endl;
    out.unsetf(std::ios::floatfield);
  }

  double process_cpu_seconds()
  {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  }
} // namespace hertzgear
