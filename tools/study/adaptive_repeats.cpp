#include "tools/study/adaptive_repeats.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "tools/study/baselines.h"
#include "tools/study/statistics.h"

namespace nuld::study {

const char *stopName(RepeatStop stop) {
  constexpr const char *names[] = {"fixed", "precision", "budget"};
  return names[int(stop)];
}

RepeatPlan planRepeats(const std::vector<TimedRow> &rows, const std::vector<std::size_t> &repeats,
                       const RepeatBudget &budget) {
  RepeatPlan plan;
  plan.want = repeats;
  plan.decided.assign(rows.size(), true);
  plan.worstStderr.assign(rows.size(), 0.0);
  if (!(budget.targetStderr > 0)) return plan;

  // Each scene and spp's best classic row and sobol's row.
  const std::vector<ClassicBaseline> classic = classicBaselines(rows);
  std::map<std::pair<std::string, std::size_t>, std::size_t> sobol, best;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto key = std::pair(rows[i].scene, rows[i].spp);
    if (rows[i].backend == "sobol") sobol[key] = i;
    if (!classic[i].backend.empty() && rows[i].backend == classic[i].backend) best[key] = i;
  }
  const auto grow = [&](std::size_t i, double factor) {
    const std::size_t n = std::max<std::size_t>(repeats[i], 2);
    const double wanted = std::clamp(double(n) * factor, 2.0 * double(n), 4.0 * double(n));
    plan.want[i] = std::max(plan.want[i], std::min(budget.maxRepeats, std::size_t(wanted)));
  };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto key = std::pair(rows[i].scene, rows[i].spp);
    for (const auto *baselines : {&best, &sobol}) {
      const auto it = baselines->find(key);
      if (it == baselines->end() || it->second == i) continue;
      const TimedRow &b = rows[it->second];
      const Ratio q = ratioOfMeans(rows[i].mse, rows[i].mseStderr, b.mse, b.mseStderr);
      // One repeat says nothing of the noise: undecided, as its verdict is.
      const bool known =
          std::isfinite(q.stderr_) && q.value > 0 && repeats[i] > 1 && repeats[it->second] > 1;
      const double se = known ? q.stderr_ / q.value : INFINITY;
      plan.worstStderr[i] = std::max(plan.worstStderr[i], se);
      if (se <= budget.targetStderr) continue;
      plan.decided[i] = false;
      const double factor =
          known ? 1.1 * (se / budget.targetStderr) * (se / budget.targetStderr) : 4.0;
      grow(i, factor);
      grow(it->second, factor);
    }
  }
  return plan;
}

}  // namespace nuld::study
