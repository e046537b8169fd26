// The pruning schedule of II-D (PruneSchedule): over a long random history of fusion-like changes
// (fused surfels, new surfels, surfels becoming stable, demotions, compacting removals, re-sorts
// of the store by block) it must report exactly the unstable surfels a full scan of the map finds
// past their age / idle limits.

#include "rasm/fusion/PruneSchedule.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

#include "rasm/surfel_map/SurfelStore.h"

using namespace rasm;
using namespace rasm::maps;

namespace {

std::vector<int> fullScan(const SurfelArrays& a, float now, float max_age, float max_idle) {
  std::vector<int> due;
  for (int i = 0; i < a.size; ++i)
    if (!(a.colour_flags[i] & kSurfelStable) &&
        (now - a.t_init[i] > max_age || now - a.t_last[i] > max_idle))
      due.push_back(i);
  return due;
}

}  // namespace

TEST(PruneSchedule, FindsExactlyWhatAFullScanFinds) {
  const float max_age = 2.0f, max_idle = 0.5f;
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  SurfelStore store;
  store.setTimeOrigin(0.0);
  // Initial map: mixed ages, a third stable.
  const int n0 = 4000;
  store.allocate(n0);
  {
    const SurfelArrays a = store.arrays();
    for (int i = 0; i < n0; ++i) {
      a.pos_conf[i] = Vec4f(u01(rng), u01(rng), u01(rng), 1.0f);
      a.t_init[i] = 1.5f * u01(rng);
      a.t_last[i] = a.t_init[i] + 0.4f * u01(rng);
      a.colour_flags[i] = u01(rng) < 0.33f ? kSurfelStable : 0u;
    }
  }
  store.indexAppended();
  fusion::PruneSchedule schedule;
  float now = 1.9f;
  schedule.rebuild(static_cast<const SurfelStore&>(store).arrays(), now, max_age, max_idle);
  int pruned_total = 0;
  for (int frame = 0; frame < 240; ++frame) {
    now += frame % 7 == 3 ? 0.2f : 1.0f / 30.0f;  // with an occasional dropped-frame gap
    std::vector<int> due_now;
    {
      const SurfelArrays a = store.arrays();
      // Fusion: a random tenth is fused now, some of those become stable; a few demotions.
      for (int i = 0; i < a.size; ++i) {
        const float r = u01(rng);
        if (r < 0.1f) {
          a.t_last[i] = now;
          if (r < 0.01f) a.colour_flags[i] |= kSurfelStable;
        } else if (r > 0.999f && (a.colour_flags[i] & kSurfelStable)) {
          a.colour_flags[i] &= ~std::uint32_t(kSurfelStable);
          if (schedule.file(a, i, now)) due_now.push_back(i);
        }
      }
    }
    // New surfels (unstable, born now).
    const int added = 60 + int(rng() % 60);
    const int first = store.allocate(added);
    {
      const SurfelArrays a = store.arrays();
      schedule.grow(store.size());
      for (int i = first; i < first + added; ++i) {
        a.pos_conf[i] = Vec4f(u01(rng), u01(rng), u01(rng), 1.0f);
        a.t_init[i] = a.t_last[i] = now;
        if (schedule.file(a, i, now)) due_now.push_back(i);
      }
    }
    store.indexAppended();
    // Due surfels: schedule vs full scan.
    const SurfelArrays a = static_cast<const SurfelStore&>(store).arrays();
    std::vector<int> due = due_now;
    schedule.collectDue(a, now, due);
    std::sort(due.begin(), due.end());
    due.erase(std::unique(due.begin(), due.end()), due.end());
    ASSERT_EQ(due, fullScan(a, now, max_age, max_idle)) << "frame " << frame;
    pruned_total += int(due.size());
    // Remove them, plus a few random others (carving), and follow the compaction.
    std::vector<int> removed = due;
    for (int k = 0; k < 5; ++k) removed.push_back(int(rng() % std::uint32_t(store.size())));
    std::vector<std::pair<int, int>> moved;
    store.remove(removed, &moved);
    schedule.moved(moved, store.size());
    ASSERT_EQ(schedule.size(), store.size());
    if (frame % 40 == 20) {  // fusion re-sorts the store now and then: every index changes
      std::vector<int> new_of_old;
      store.sortByBlock(&new_of_old);
      schedule.permute(new_of_old);
      ASSERT_EQ(schedule.size(), store.size());
    }
  }
  EXPECT_GT(pruned_total, 10000);
}
