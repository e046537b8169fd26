#include "rasm/fusion/PruneSchedule.h"

#include <cmath>

namespace rasm::fusion {

namespace {
constexpr int kBucketsPerSecond = 32;
std::int32_t floorKey(float t) {
  const double k = std::floor(double(t) * kBucketsPerSecond);
  return std::int32_t(std::max(-1.0e9, std::min(1.0e9, k)));
}
}  // namespace

std::int32_t PruneSchedule::keyOf(float t) const {
  return floorKey(t) - 1;  // one bucket early: the float test decides, never a late look
}

void PruneSchedule::push(int i, std::int32_t key) {
  if (key <= processed_) key = processed_ + 1;
  if (key > processed_ + kRing) key = processed_ + kRing;  // looked at again at the horizon
  ring_[std::size_t(((key % kRing) + kRing) % kRing)].push_back(i);
  key_[std::size_t(i)] = key;
}

void PruneSchedule::rebuild(const maps::SurfelArrays& a, float now, float max_age_s,
                            float max_idle_s) {
  max_age_ = max_age_s;
  max_idle_ = max_idle_s;
  for (auto& b : ring_) b.clear();
  key_.assign(std::size_t(a.size), kNone);
  processed_ = floorKey(now) - 1;
  for (int i = 0; i < a.size; ++i)
    if (!(a.colour_flags[i] & maps::kSurfelStable))
      push(i, keyOf(std::min(a.t_init[i] + max_age_, a.t_last[i] + max_idle_)));
}

bool PruneSchedule::file(const maps::SurfelArrays& a, int i, float now) {
  if (due(a, i, now)) return true;
  push(i, keyOf(std::min(a.t_init[i] + max_age_, a.t_last[i] + max_idle_)));
  return false;
}

void PruneSchedule::collectDue(const maps::SurfelArrays& a, float now, std::vector<int>& prune) {
  const std::int32_t current = floorKey(now);
  if (current <= processed_) return;
  const std::int32_t from = std::max(processed_ + 1, current - kRing + 1);
  const std::int32_t n = std::int32_t(key_.size());
  std::vector<std::int32_t> looked;
  for (std::int32_t k = from; k <= current; ++k) {
    const std::size_t b = std::size_t(((k % kRing) + kRing) % kRing);
    std::vector<std::int32_t>& bucket = ring_[b];
    std::size_t keep = 0;
    for (const std::int32_t i : bucket) {
      if (i >= n) continue;  // left behind by a removal
      const std::int32_t key = key_[std::size_t(i)];
      if (key == kNone || std::size_t(((key % kRing) + kRing) % kRing) != b) continue;  // moved on
      if (key > current) {
        bucket[keep++] = i;  // filed for a later round of the ring
        continue;
      }
      key_[std::size_t(i)] = kNone;
      looked.push_back(i);
    }
    bucket.resize(keep);
  }
  processed_ = current;
  for (const std::int32_t i : looked) {
    if (a.colour_flags[i] & maps::kSurfelStable) continue;
    if (due(a, i, now))
      prune.push_back(i);
    else
      push(i, keyOf(std::min(a.t_init[i] + max_age_, a.t_last[i] + max_idle_)));
  }
}

void PruneSchedule::moved(const std::vector<std::pair<int, int>>& moved, int new_size) {
  for (const auto& [from, to] : moved) {
    const std::int32_t key = key_[std::size_t(from)];
    key_[std::size_t(from)] = kNone;
    key_[std::size_t(to)] = key;
    if (key != kNone) ring_[std::size_t(((key % kRing) + kRing) % kRing)].push_back(to);
  }
  key_.resize(std::size_t(new_size), kNone);
}

void PruneSchedule::permute(const std::vector<int>& new_of_old) {
  const std::int32_t n = std::int32_t(key_.size());
  std::vector<std::int32_t> key(key_.size(), kNone);
  for (std::int32_t i = 0; i < n; ++i)
    key[std::size_t(new_of_old[std::size_t(i)])] = key_[std::size_t(i)];
  key_.swap(key);
  // Entries keep their bucket; an entry is live when its surfel's key maps to that bucket, and
  // key and surfel move together, so the rule still holds. Entries past the end are dropped.
  for (std::vector<std::int32_t>& bucket : ring_) {
    std::size_t keep = 0;
    for (const std::int32_t i : bucket)
      if (i < n) bucket[keep++] = new_of_old[std::size_t(i)];
    bucket.resize(keep);
  }
}

}  // namespace rasm::fusion
