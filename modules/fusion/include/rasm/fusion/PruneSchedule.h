#pragma once
// When to look at an unstable surfel again for the pruning of II-D (SurfelFusion::cleanup): an
// unstable surfel is removed once now - t_init > max_age or now - t_last > max_idle. Scanning the
// whole map for those every frame costs O(N); instead every unstable surfel is filed under the
// earliest time its condition can hold, d = min(t_init + max_age, t_last + max_idle), in a ring of
// time buckets, and a frame looks only at the buckets that have come due. t_last only grows, so the
// filed time is never later than the real one: a surfel looked at too early (it was fused since,
// or the bucket is coarse) is re-filed under its new time; one that became stable is dropped.
// Per frame this costs O(surfels that came due), about (unstable surfels) / (max_idle * rate).
//
// Every unstable surfel stays filed as long as fusion alone changes the map: fusion files the
// surfels it adds and the ones carving demotes, and reports compaction moves (moved()).
// Surfel indices are map indices; a per-surfel key (4 bytes) identifies the live entry so that
// entries left behind by moves are recognised and skipped.

#include <algorithm>
#include <climits>
#include <cstdint>
#include <utility>
#include <vector>

#include "rasm/surfel_map/SurfelArrays.h"

namespace rasm::fusion {

class PruneSchedule {
 public:
  /// Forgets everything; then every unstable surfel of `a` is filed (O(N), only when the map was
  /// changed behind fusion's back or the limits changed).
  void rebuild(const maps::SurfelArrays& a, float now, float max_age_s, float max_idle_s);
  float maxAge() const { return max_age_; }
  float maxIdle() const { return max_idle_; }
  /// Number of surfels the schedule covers (the map size it was last told about).
  int size() const { return int(key_.size()); }
  /// The map grew to n surfels (new ones not filed yet).
  void grow(int n) { key_.resize(std::size_t(n), kNone); }
  /// Files unstable surfel i (map time now): true when it is already due, and then it is NOT
  /// filed (the caller prunes it).
  bool file(const maps::SurfelArrays& a, int i, float now);
  /// Appends to `prune` the unstable surfels whose limit has passed at map time `now`
  /// (exactly the condition of II-D, evaluated on the current arrays); they are unfiled.
  void collectDue(const maps::SurfelArrays& a, float now, std::vector<int>& prune);
  /// After SurfelStore::remove(): the surfels `moved` (old, new) keep their filing, the map has
  /// new_size surfels.
  void moved(const std::vector<std::pair<int, int>>& moved, int new_size);
  /// After SurfelStore::sortByBlock(): surfel i is now new_of_old[i] and keeps its filing.
  void permute(const std::vector<int>& new_of_old);

 private:
  static constexpr std::int32_t kNone = INT32_MIN;
  static constexpr int kRing = 1024;  ///< 32 s ahead; later times are filed at the horizon
  bool due(const maps::SurfelArrays& a, int i, float now) const {
    return now - a.t_init[i] > max_age_ || now - a.t_last[i] > max_idle_;
  }
  std::int32_t keyOf(float t) const;
  void push(int i, std::int32_t key);

  float max_age_ = 0.0f, max_idle_ = 0.0f;
  std::int32_t processed_ = kNone;  ///< all buckets with key <= processed_ were looked at
  std::vector<std::int32_t> key_;   ///< per surfel: key of its live entry, kNone if not filed
  std::vector<std::vector<std::int32_t>> ring_ = std::vector<std::vector<std::int32_t>>(kRing);
};

}  // namespace rasm::fusion
