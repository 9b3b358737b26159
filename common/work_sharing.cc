// Units of work shared out over processes by their expected work (common/processes.h).
#include "common/errors.h"
#include "common/processes.h"

#include <algorithm>
#include <numeric>

namespace hertzgear::processes
{
  std::vector<std::size_t> share_by_work(const std::vector<double> &work, const std::size_t count,
                                         const std::vector<double> &earlier_work)
  {
    HG_REQUIRE_INPUT(count > 0, "share_by_work: no process to share the work over");
    HG_REQUIRE_INPUT(earlier_work.empty() || earlier_work.size() == count, "share_by_work: ",
                     earlier_work.size(), " processes' earlier work for ", count, " processes");
    const auto earlier = [&](const std::size_t r) { return earlier_work.empty() ? 0.0 : earlier_work[r]; };
    for (const double w : work)
      HG_REQUIRE_INPUT(w >= 0, "share_by_work: a unit of negative work (", w, ")");
    std::vector<std::size_t> order(work.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](const std::size_t a, const std::size_t b) { return work[a] > work[b]; });
    std::vector<double>      load(count, 0.0);
    std::vector<std::size_t> owner(work.size(), 0);
    for (const std::size_t k : order)
      {
        std::size_t least = 0;
        for (std::size_t r = 1; r < count; ++r)
          if (load[r] < load[least] || (load[r] == load[least] && earlier(r) < earlier(least)))
            least = r;
        owner[k]         = least;
        load[least] += work[k];
      }
    return owner;
  }
} // namespace hertzgear::processes
