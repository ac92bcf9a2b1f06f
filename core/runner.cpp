#include "core/runner.hpp"

#include <omp.h>

#include <bit>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"

namespace qmaps {

void advance_parts(std::span<const RunPart> parts, const RunPlan& plan, const Execution& x) {
  if (plan.stride < 1) throw usage_error("stride must be >= 1");
  if (plan.measure_orbits && (plan.tunes.inside(plan.first) || plan.tunes.inside(plan.last)))
    throw Error(ExitCode::failure, "steps " + std::to_string(plan.first) + " to " + std::to_string(plan.last) +
                " split the tunes' windows (steps 1 to " + std::to_string(plan.tunes.end()) + ")");
  if (plan.tunes.window > 0 &&
      (!std::has_single_bit(static_cast<unsigned long long>(plan.tunes.window)) ||
       plan.tunes.order < 1))
    throw usage_error("the tunes' window must be a power of two and their order at least 1");
  struct Blocks {
    std::size_t part, first, count;
  };
  std::vector<Blocks> work;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const std::size_t block = parts[p].model->block_orbits(x);
    if (Ensemble::padding % block != 0)
      throw usage_error("chains must be 1, 2, 4 or 8 (got " + std::to_string(x.chains) + ")");
    // Whole blocks of real orbits; the padding lanes past the last real orbit are never sampled.
    for (std::size_t first = 0; first < parts[p].ensemble->orbits; first += block)
      work.push_back({p, first, block});
  }
  const long long count = static_cast<long long>(work.size());
  const auto advance_blocks = [&](long long w, std::vector<Observers>& mine) {
    const Blocks& b = work[static_cast<std::size_t>(w)];
    const RunPart& part = parts[b.part];
    part.model->advance_range(*part.ensemble, b.first, b.count, plan, x,
                              part.observers ? &mine[b.part] : nullptr);
  };
  std::vector<std::vector<Observers>> partials(static_cast<std::size_t>(x.threads));
#pragma omp parallel num_threads(x.threads)
  {
    auto& mine = partials[static_cast<std::size_t>(omp_get_thread_num())];
    mine.resize(parts.size());
    for (std::size_t p = 0; p < parts.size(); ++p)
      if (parts[p].observers) mine[p] = parts[p].observers->empty_copy();
    if (parts.size() == 1) {
#pragma omp for schedule(static)
      for (long long w = 0; w < count; ++w) advance_blocks(w, mine);
    } else {
#pragma omp for schedule(dynamic)
      for (long long w = 0; w < count; ++w) advance_blocks(w, mine);
    }
  }
  for (std::size_t p = 0; p < parts.size(); ++p) {
    if (Observers* observers = parts[p].observers) {
      for (auto& thread : partials) observers->merge(std::move(thread[p]));
      observers->finish();
    }
    parts[p].ensemble->step = plan.last;
  }
}

}  // namespace qmaps
