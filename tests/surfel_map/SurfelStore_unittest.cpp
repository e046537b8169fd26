// SurfelStore: SoA storage, removal with compaction, and the incremental spatial index.

#include "rasm/surfel_map/SurfelStore.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

using namespace rasm;
using namespace rasm::maps;

namespace {

Surfel randomSurfel(std::mt19937& rng, const SurfelStoreOptions& opt) {
  std::uniform_real_distribution<float> pos(-3.0f, 3.0f), unit(0.0f, 1.0f);
  Surfel s;
  s.position = Vec3f(pos(rng), pos(rng), pos(rng));
  s.normal = Vec3f(unit(rng) - 0.5f, unit(rng) - 0.5f, 1.0f).normalized();
  s.basis = Vec3f(1, 0, 0);
  s.radius = 0.001f + 0.01f * unit(rng);
  s.confidence = 20.0f * unit(rng);
  s.colour = Bgr8{std::uint8_t(rng() & 255), std::uint8_t(rng() & 255), std::uint8_t(rng() & 255)};
  s.stable = s.confidence > 10.0f;
  s.t_init_s = 100.0 + unit(rng);
  s.t_last_s = 101.0 + unit(rng);
  s.segment = rng() % 50;
  s.segment_weight = unit(rng);
  // A few detections of random classes (some negative): up to 6 updates into the 4 slots.
  const int detections = opt.n_classes > 0 ? int(rng() % 7) : 0;
  for (int k = 0; k < detections; ++k)
    classEvidenceUpdate(s.classes, 1 + int(rng() % opt.n_classes), unit(rng));
  for (int v = 0; v < opt.nViewBins(); ++v) s.view_ic.push_back(unit(rng));
  return s;
}

void expectSame(const Surfel& a, const Surfel& b) {
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.normal, b.normal);
  EXPECT_EQ(a.basis, b.basis);
  EXPECT_EQ(a.radius, b.radius);
  EXPECT_EQ(a.confidence, b.confidence);
  EXPECT_EQ(a.colour.b, b.colour.b);
  EXPECT_EQ(a.colour.g, b.colour.g);
  EXPECT_EQ(a.colour.r, b.colour.r);
  EXPECT_EQ(a.stable, b.stable);
  EXPECT_EQ(a.segment, b.segment);
  EXPECT_EQ(a.segment_weight, b.segment_weight);
  EXPECT_NEAR(a.t_init_s, b.t_init_s, 1e-5);
  EXPECT_NEAR(a.t_last_s, b.t_last_s, 1e-5);
  for (int k = 0; k < kClassSlots; ++k) {  // stored as is: exact
    EXPECT_EQ(a.classes.id[k], b.classes.id[k]);
    EXPECT_EQ(a.classes.logit[k], b.classes.logit[k]);
  }
  ASSERT_EQ(a.view_ic.size(), b.view_ic.size());
  for (std::size_t v = 0; v < a.view_ic.size(); ++v)
    EXPECT_NEAR(a.view_ic[v], b.view_ic[v], 0.5 / 255.0 + 1e-6);
}

}  // namespace

TEST(SurfelStore, BytesPerSurfelMatchesTheBudget) {
  // SurfelArrays.h: 56-byte geometric core + segment + segment weight = 64, then 12 bytes of
  // class evidence for any number of classes, then the view bins.
  EXPECT_EQ(SurfelStore::bytesPerSurfel(0, 0), 64u);
  EXPECT_EQ(SurfelStore::bytesPerSurfel(1, 0), 64u + 12u);
  EXPECT_EQ(SurfelStore::bytesPerSurfel(80, 16), 64u + 12u + 16u);
  EXPECT_EQ(SurfelStore::bytesPerSurfel(kMaxClassId, 16), 64u + 12u + 16u);
}

TEST(SurfelStore, AppendGetRoundTripsEveryAttribute) {
  SurfelStoreOptions opt;
  opt.n_classes = 5;
  opt.view_bins_azimuth = 4;
  opt.view_bins_elevation = 2;
  SurfelStore store(opt);
  std::mt19937 rng(1);
  std::vector<Surfel> ref;
  for (int i = 0; i < 100; ++i) {
    ref.push_back(randomSurfel(rng, opt));
    EXPECT_EQ(store.append(ref.back()), i);
  }
  ASSERT_EQ(store.size(), 100);
  for (int i = 0; i < 100; ++i) expectSame(store.get(i), ref[i]);
  std::string why;
  EXPECT_TRUE(store.checkConsistency(&why)) << why;
}

TEST(SurfelStore, DefaultsOfAllocatedSurfels) {
  SurfelStoreOptions opt;
  opt.n_classes = 3;
  SurfelStore store(opt);
  const int first = store.allocate(4);
  EXPECT_EQ(first, 0);
  const SurfelArrays a = store.arrays();
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(classEvidenceEmpty(a.classEvidence(i)));  // II-B: every class at the 0.5 prior
    for (int c = 1; c <= 3; ++c) EXPECT_EQ(classProbability(a.classEvidence(i), c), 0.5f);
    for (int v = 0; v < a.n_view_bins; ++v) EXPECT_EQ(a.viewRow(i)[v], 0);
    EXPECT_EQ(a.segment[i], 0u);
  }
  EXPECT_FALSE(store.checkConsistency());  // not indexed yet
  store.indexAppended();
  EXPECT_TRUE(store.checkConsistency());
}

TEST(SurfelStore, RemoveCompactsAndReportsMovedIndices) {
  SurfelStoreOptions opt;
  opt.n_classes = 2;
  SurfelStore store(opt);
  std::mt19937 rng(7);
  std::vector<Surfel> ref;
  for (int i = 0; i < 2000; ++i) {
    ref.push_back(randomSurfel(rng, opt));
    ref.back().segment = std::uint32_t(i);  // identity tag
    store.append(ref.back());
  }
  for (int round = 0; round < 5; ++round) {
    std::vector<int> rem;
    std::uniform_int_distribution<int> pick(0, store.size() - 1);
    for (int k = 0; k < 150; ++k) rem.push_back(pick(rng));
    rem.push_back(store.size() - 1);  // the tail itself
    rem.push_back(rem.front());       // duplicate
    const std::set<int> rem_set(rem.begin(), rem.end());
    std::vector<std::uint32_t> tags_before(store.size());
    for (int i = 0; i < store.size(); ++i) tags_before[i] = store.arrays().segment[i];
    const int n_before = store.size();

    std::vector<std::pair<int, int>> moved;
    store.remove(rem, &moved);
    ASSERT_EQ(store.size(), n_before - int(rem_set.size()));
    std::string why;
    ASSERT_TRUE(store.checkConsistency(&why)) << why;

    // Surviving tags are exactly the ones not removed; moved pairs say where they went.
    std::multiset<std::uint32_t> expect, got;
    for (int i = 0; i < n_before; ++i)
      if (!rem_set.count(i)) expect.insert(tags_before[i]);
    for (int i = 0; i < store.size(); ++i) got.insert(store.arrays().segment[i]);
    EXPECT_EQ(expect, got);
    for (const auto& [from, to] : moved) {
      EXPECT_GT(from, to);
      EXPECT_FALSE(rem_set.count(from));
      EXPECT_TRUE(rem_set.count(to));
      EXPECT_EQ(store.arrays().segment[to], tags_before[from]);
      expectSame(store.get(to), ref[tags_before[from]]);
    }
    // Indices below the smallest removed index are untouched.
    for (int i = 0; i < *rem_set.begin(); ++i) EXPECT_EQ(store.arrays().segment[i], tags_before[i]);
  }
}

TEST(SurfelStore, RemoveWithUnindexedTail) {
  SurfelStore store;
  std::mt19937 rng(3);
  for (int i = 0; i < 50; ++i) store.append(randomSurfel(rng, store.options()));
  const int first = store.allocate(10);  // not indexed yet
  const SurfelArrays a = store.arrays();
  for (int i = first; i < first + 10; ++i) a.pos_conf[i] = Vec4f(0.1f * i, 0.2f, 0.3f, 1.0f);
  store.remove({0, 5, 49, 55});
  store.indexAppended();
  std::string why;
  EXPECT_TRUE(store.checkConsistency(&why)) << why;
  EXPECT_EQ(store.size(), 56);
}

TEST(SurfelStore, ReindexFollowsSurfelsAcrossBlockBorders) {
  SurfelStoreOptions opt;
  opt.block_size_m = 0.25f;
  SurfelStore store(opt);
  std::mt19937 rng(5);
  for (int i = 0; i < 500; ++i) store.append(randomSurfel(rng, opt));
  const int blocks_before = store.spatialIndex().numBlocks();
  // Nudge every surfel by a few cm (as fusion does): some cross block borders.
  std::vector<int> all(store.size());
  const SurfelArrays a = store.arrays();
  for (int i = 0; i < store.size(); ++i) {
    all[i] = i;
    a.pos_conf[i].head<3>() += Vec3f(0.03f, -0.02f, 0.04f);
  }
  EXPECT_FALSE(store.checkConsistency());
  const int moved = store.reindex(all);
  EXPECT_GT(moved, 0);
  EXPECT_LT(moved, store.size());
  std::string why;
  EXPECT_TRUE(store.checkConsistency(&why)) << why;
  EXPECT_GT(blocks_before, 0);
}

TEST(VoxelBlockIndex, FrustumKeepsOnlyBlocksInView) {
  VoxelBlockIndex index(0.5f);
  // One surfel in each block of a 20 x 20 x 4 m volume around the camera.
  int id = 0;
  for (float x = -9.75f; x < 10.0f; x += 0.5f)
    for (float y = -1.75f; y < 2.0f; y += 0.5f)
      for (float z = -9.75f; z < 10.0f; z += 0.5f) index.insert(id++, Vec3f(x, y, z));
  ASSERT_EQ(index.numBlocks(), id);
  const PinholeF K{525.f, 525.f, 319.5f, 239.5f, 640, 480};
  const CameraFrustum f = CameraFrustum::fromCamera(RigidF(), K, 0.1f, 4.0f);
  std::vector<int> blocks;
  index.blocksInFrustum(f, 0.0f, blocks);
  // The frustum (4 m deep, ~63 x 49 deg) covers ~ 1/3 * 4 * (4.9 * 3.6) = 23 m^3; blocks are
  // 0.125 m^3, so ~190 blocks plus a border of partially covered ones: far fewer than 12800.
  EXPECT_GT(int(blocks.size()), 150);
  EXPECT_LT(int(blocks.size()), 900);
  for (int b : blocks) {
    const Vec3f c = index.blockMin(b) + Vec3f::Constant(0.25f);
    EXPECT_GT(c.z(), -0.5f);  // nothing behind the camera
    EXPECT_LT(c.z(), 4.5f);
  }
}

TEST(SurfelStore, GrowingKeepsTheSurfelsAndCountsModifications) {
  // PodArray growth (mremap) must keep the contents; generation() tells modifications apart and
  // is unique per store (a copy does not continue the original's sequence).
  SurfelStoreOptions opt;
  opt.n_classes = 3;
  SurfelStore store(opt);
  store.setTimeOrigin(100.0);
  std::mt19937 rng(11);
  std::vector<Surfel> ref;
  std::uint64_t g = store.generation();
  for (int round = 0; round < 6; ++round) {
    const int n = 1 << (8 + 2 * round);  // 256 ... 262144 surfels per round
    const int first = store.allocate(n);
    EXPECT_NE(store.generation(), g);
    g = store.generation();
    const SurfelArrays a = store.arrays();
    for (int i = first; i < first + n; ++i) a.pos_conf[i] = Vec4f(float(i), 0.5f, -float(i), 1.0f);
    ref.push_back(randomSurfel(rng, opt));
    store.set(first, ref.back());
  }
  store.indexAppended();
  const SurfelArrays a = store.arrays();
  int k = 0, first = 0;
  for (int round = 0; round < 6; ++round) {
    const int n = 1 << (8 + 2 * round);
    expectSame(store.get(first), ref[k++]);
    for (int i = first + 1; i < first + n; i += 97) EXPECT_EQ(a.pos_conf[i].x(), float(i));
    first += n;
  }
  const std::uint64_t before = store.generation();
  const SurfelStore& cstore = store;
  (void)cstore.arrays();  // read access
  EXPECT_EQ(store.generation(), before);
  const SurfelStore copy = store;
  EXPECT_NE(copy.generation(), store.generation());
  EXPECT_EQ(copy.size(), store.size());
  std::string why;
  EXPECT_TRUE(copy.checkConsistency(&why)) << why;
}

// sortByBlock: a permutation that keeps every attribute of every surfel and leaves each block's
// members at consecutive indices in list order (what makes the renderer's reads sequential).
TEST(SurfelStore, SortByBlockKeepsEverySurfelAndMakesBlocksContiguous) {
  SurfelStoreOptions opt;
  opt.n_classes = 3;
  opt.block_size_m = 0.5f;
  SurfelStore store(opt);
  std::mt19937 rng(21);
  for (int i = 0; i < 3000; ++i) store.append(randomSurfel(rng, opt));
  // Scatter the order as fusion does: removals (tail moved into holes), appends, re-binning.
  std::vector<int> rem;
  for (int k = 0; k < 300; ++k) rem.push_back(int(rng() % store.size()));
  store.remove(rem);
  for (int i = 0; i < 200; ++i) store.append(randomSurfel(rng, opt));
  std::vector<int> nudged;
  for (int i = 0; i < store.size(); i += 7) {
    store.arrays().pos_conf[i].head<3>() += Vec3f(0.2f, 0.0f, -0.1f);
    nudged.push_back(i);
  }
  store.reindex(nudged);
  EXPECT_GT(store.unsortedFraction(), 0.0);

  const int n = store.size();
  std::vector<Surfel> before(n);
  for (int i = 0; i < n; ++i) before[i] = store.get(i);
  std::vector<int> new_of_old;
  store.sortByBlock(&new_of_old);
  ASSERT_EQ(store.size(), n);
  ASSERT_EQ(int(new_of_old.size()), n);
  std::string why;
  ASSERT_TRUE(store.checkConsistency(&why)) << why;
  EXPECT_EQ(store.unsortedFraction(), 0.0);
  std::vector<int> seen(n, 0);
  for (int i = 0; i < n; ++i) {
    ASSERT_GE(new_of_old[i], 0);
    ASSERT_LT(new_of_old[i], n);
    ++seen[new_of_old[i]];
    expectSame(store.get(new_of_old[i]), before[i]);
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), n);  // a permutation
  // Blocks in id order, each block's members consecutive in list order.
  const VoxelBlockIndex& index = store.spatialIndex();
  int next = 0;
  for (int b = 0; b < index.blockCapacity(); ++b)
    for (const int i : index.members(b)) EXPECT_EQ(i, next++) << "block " << b;
  EXPECT_EQ(next, n);

  store.append(randomSurfel(rng, opt));
  EXPECT_NEAR(store.unsortedFraction(), 1.0 / store.size(), 1e-12);
}

// The index keeps each block's stable surfels first (renders of stable surfels visit only those);
// insert, removal, re-binning, set() and refreshStable() keep it so.
TEST(VoxelBlockIndex, StableSurfelsComeFirstInTheirBlock) {
  SurfelStoreOptions opt;
  opt.block_size_m = 2.0f;  // few blocks, many members each
  SurfelStore store(opt);
  std::mt19937 rng(8);
  for (int i = 0; i < 1500; ++i) store.append(randomSurfel(rng, opt));
  const auto expectPartitioned = [&](const char* when) {
    std::string why;
    EXPECT_TRUE(store.checkConsistency(&why)) << when << ": " << why;
    const VoxelBlockIndex& index = store.spatialIndex();
    const SurfelArrays a = store.arrays();
    int stable = 0;
    for (int b = 0; b < index.blockCapacity(); ++b) {
      const std::vector<int>& m = index.members(b);
      for (int k = 0; k < int(m.size()); ++k)
        ASSERT_EQ(a.stable(m[k]), k < index.stableCount(b))
            << when << ": block " << b << " slot " << k;
      stable += index.stableCount(b);
    }
    int expect = 0;
    for (int i = 0; i < a.size; ++i) expect += a.stable(i) ? 1 : 0;
    EXPECT_EQ(stable, expect) << when;
    EXPECT_GT(stable, 0) << when;
    EXPECT_LT(stable, a.size) << when;
  };
  expectPartitioned("after appends");

  // Flags flipped behind the index's back are caught by the check, then reported.
  std::vector<int> flipped;
  for (int i = 0; i < store.size(); i += 5) {
    store.arrays().colour_flags[i] ^= kSurfelStable;
    flipped.push_back(i);
  }
  EXPECT_FALSE(store.checkConsistency());
  store.refreshStable(flipped);
  expectPartitioned("after refreshStable");

  std::vector<int> rem;
  for (int k = 0; k < 200; ++k) rem.push_back(int(rng() % store.size()));
  store.remove(rem);
  expectPartitioned("after remove");

  std::vector<int> moved;
  for (int i = 0; i < store.size(); i += 3) {
    store.arrays().pos_conf[i].head<3>() += Vec3f(1.1f, 0.0f, 0.0f);  // into the next block
    moved.push_back(i);
  }
  EXPECT_GT(store.reindex(moved), 0);
  expectPartitioned("after reindex");

  Surfel s = store.get(10);
  s.stable = !s.stable;
  s.position += Vec3f(0.0f, 2.5f, 0.0f);
  store.set(10, s);
  expectPartitioned("after set");

  std::vector<int> new_of_old;
  store.sortByBlock(&new_of_old);
  expectPartitioned("after sortByBlock");
}

TEST(SurfelStore, ThinnedCopyKeepsEveryKthAliveSurfelWithEveryAttribute) {
  SurfelStoreOptions opt;
  opt.n_classes = 5;
  opt.view_bins_azimuth = 4;
  opt.view_bins_elevation = 2;
  SurfelStore store(opt);
  std::mt19937 rng(7);
  for (int i = 0; i < 1000; ++i) store.append(randomSurfel(rng, opt));
  // Free slots (a removed surfel the allocator will reuse) are not surfels: skipped.
  std::vector<int> alive;
  SurfelArrays a = store.arrays();
  for (int i = 0; i < store.size(); ++i)
    if (i % 10 == 3)
      a.colour_flags[i] |= kSurfelFree;
    else
      alive.push_back(i);

  SurfelStore thinned;
  thinned.copyThinnedFrom(store, 3, 1.5f);
  thinned.rebuildIndex();
  ASSERT_EQ(thinned.size(), int((alive.size() + 2) / 3));  // alive surfels 0, 3, 6, ...
  EXPECT_EQ(thinned.options(), store.options());
  for (int j = 0; j < thinned.size(); ++j) {
    Surfel expected = store.get(alive[std::size_t(3 * j)]);
    expected.radius *= 1.5f;
    expectSame(thinned.get(j), expected);
  }
  std::string why;
  EXPECT_TRUE(thinned.checkConsistency(&why)) << why;
  // Stride 1 is a copy of the alive surfels.
  thinned.copyThinnedFrom(store, 1, 1.0f);
  EXPECT_EQ(thinned.size(), int(alive.size()));
  EXPECT_THROW(thinned.copyThinnedFrom(store, 0, 1.0f), std::invalid_argument);
}
