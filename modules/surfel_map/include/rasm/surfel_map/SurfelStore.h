#pragma once
// Owning structure-of-arrays storage of the surfel map M (II-A) plus its coarse spatial index.
// This is the MRPT-free core that the renderer (II-A), fusion (II-B, II-D), segmentation (III),
// classification (IV) and exploration (V-B) work on; rasm::maps::CSurfelMap wraps one and adds
// the mrpt::maps::CMetricMap interface (serialization, INI creation, visualization).
//
// Layout and byte budget: see SurfelArrays.h (64 bytes + 12 of class evidence when n_classes > 0 +
// n_view_bins per surfel) plus 12 bytes per surfel for the spatial index (VoxelBlockIndex.h).
//
// Index stability: surfel indices are positions in the arrays. append()/allocate() never change
// existing indices. remove() compacts by moving surfels from the tail into the holes, so after it
// every index >= the smallest removed index may name another surfel (the optional `moved` output
// lists each (old index, new index)). sortByBlock() permutes every index (`new_of_old`), and
// SurfelFusion does it now and then before a frame. Anything that keeps surfel indices across a
// removal or a sort (index maps rendered earlier, per-pixel association results) must be remapped
// or recomputed.
//
// Times: surfels store float seconds relative to the map's time origin (the first timestamp the
// map saw), so sub-millisecond resolution holds for runs of hours; the API takes absolute seconds.

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "rasm/surfel_map/PodArray.h"
#include "rasm/surfel_map/SurfelArrays.h"
#include "rasm/surfel_map/VoxelBlockIndex.h"

namespace rasm::maps {

/// Creation-time layout of a surfel store.
struct SurfelStoreOptions {
  /// n_c of II-A: class ids 1..n_classes are valid (0..kMaxClassId = 255). The evidence costs
  /// 12 bytes per surfel whatever the count (ClassEvidence.h); 0 = no class evidence at all.
  int n_classes = kDefaultNumClasses;
  int view_bins_azimuth = 8;    ///< V-B view bins: azimuth sectors around the surfel normal
  int view_bins_elevation = 2;  ///< V-B view bins: elevation rings between the plane and normal
  float block_size_m = 0.5f;    ///< edge of the spatial index blocks

  int nViewBins() const { return view_bins_azimuth * view_bins_elevation; }
  bool operator==(const SurfelStoreOptions& o) const {
    return n_classes == o.n_classes && view_bins_azimuth == o.view_bins_azimuth &&
           view_bins_elevation == o.view_bins_elevation && block_size_m == o.block_size_m;
  }
};

/// One surfel by value (host convenience for appends, tests and I/O; kernels use SurfelArrays).
/// IC values are floats in [0,1] here and quantised to u8 in the store; class evidence is the
/// stored slots (ClassEvidence.h: classProbability, bestClass).
struct Surfel {
  Vec3f position = Vec3f::Zero();  ///< p, world (m)
  Vec3f normal = Vec3f::UnitZ();   ///< n, world, unit
  Vec3f basis = Vec3f::UnitX();    ///< b, world, unit, perpendicular to n (V-B)
  float radius = 0.0f;             ///< r (m)
  float confidence = 0.0f;         ///< w
  Bgr8 colour;                     ///< c
  bool stable = false;             ///< s
  double t_init_s = 0.0;           ///< t, absolute seconds
  double t_last_s = 0.0;           ///< last fusion, absolute seconds
  std::uint32_t segment = 0;       ///< l (0 = none)
  float segment_weight = 0.0f;     ///< w_l
  ClassEvidence classes;           ///< p_c as log-odds slots (default: every class at 0.5)
  std::vector<float> view_ic;      ///< b_v, n_view_bins values (empty = all 0)
};

class SurfelStore {
 public:
  explicit SurfelStore(const SurfelStoreOptions& opt = {});

  /// Drops all surfels and the time origin; `opt` replaces the layout (n_classes, bins, block).
  void reset(const SurfelStoreOptions& opt);
  void clear() { reset(opt_); }
  const SurfelStoreOptions& options() const { return opt_; }

  int size() const { return size_; }
  bool empty() const { return size_ == 0; }
  void reserve(int n);

  /// Mutable spans over the arrays (valid until the next size change). Counts as a modification
  /// (generation()).
  SurfelArrays arrays();
  /// Read-only by contract: the pointers are non-const because SurfelArrays is one plain type
  /// shared by all kernels; code holding a const store must not write through them.
  SurfelArrays arrays() const;

  /// Appends one surfel and indexes it; returns its index. Sets the time origin if unset.
  int append(const Surfel& s);
  /// Grows the arrays by `count` default surfels (zero geometry, no class evidence, view_ic = 0,
  /// segment 0) and returns the first new index. The new surfels are NOT in the spatial index until
  /// indexAppended() is called once the caller has written their positions (fusion kernels do).
  int allocate(int count);
  /// Adds every surfel allocated since the last call to the spatial index.
  void indexAppended();
  /// Re-bins the given surfels after their positions changed (only those that crossed a block
  /// border cost anything); returns how many changed block.
  int reindex(const std::vector<int>& surfels);
  /// Re-bins every surfel (after bulk edits through arrays()).
  void rebuildIndex();
  /// Becomes a copy of `o`'s surfels (arrays, options, time origin) without its spatial index,
  /// reusing this store's memory where it is large enough: the part of a snapshot taken under
  /// the map lock (memcpy); the taker then calls rebuildIndex() on its own thread.
  void copySurfelsFrom(const SurfelStore& o);
  /// Becomes a thinned copy of `o` for coarse renders (the exploration planner's view
  /// predictions): every `stride`-th alive surfel of `o` in storage order (block-sorted stores
  /// keep this spatially even), every field copied, its radius times `radius_scale` (sqrt(stride)
  /// keeps the splatted area). Without a spatial index: call rebuildIndex(). stride >= 1.
  void copyThinnedFrom(const SurfelStore& o, int stride, float radius_scale);
  /// The spatial index keeps each block's stable surfels first (VoxelBlockIndex.h): code that
  /// sets or clears kSurfelStable through arrays() reports those surfels here (fusion does), or
  /// calls rebuildIndex(). A stable surfel the index does not know as stable is missed by
  /// stable-only renders. O(k).
  void refreshStable(const std::vector<int>& surfels);

  /// Removes the given surfels (any order, duplicates allowed) and compacts by moving tail
  /// surfels into the holes. `moved`, when given, receives (old index, new index) of every surfel
  /// that changed index. See the header comment for the invalidation rule. O(k) for k removals.
  void remove(std::vector<int> surfels, std::vector<std::pair<int, int>>* moved = nullptr);

  /// Reorders the surfels block by block: spatial-index blocks in id order, each block's members
  /// in their list order, the order in which the renderer and fusion visit the surfels of the
  /// blocks in view. Their reads of the arrays then run almost sequentially instead of missing the
  /// cache once per surfel and attribute. Appends and the compaction of remove() scatter that
  /// order again, a few percent of the map per frame; unsortedFraction() says how much.
  /// Every index may change (see the header comment): `new_of_old`, when given, receives the new
  /// index of each old one. Requires every surfel indexed (std::logic_error otherwise). O(N).
  void sortByBlock(std::vector<int>* new_of_old = nullptr);
  /// Every surfel is in the spatial index (no allocate() awaiting indexAppended()).
  bool allIndexed() const { return indexed_ == size_; }
  /// Surfels appended or moved by remove() since the last sortByBlock(), over size() (an upper
  /// bound of the fraction out of block order; 1 for a store never sorted).
  double unsortedFraction() const {
    return size_ > 0 ? std::min(1.0, double(unsorted_) / double(size_)) : 0.0;
  }

  /// Value accessors (slow path: tests, I/O, tools).
  Surfel get(int i) const;
  /// Re-bins i if its position changed. Throws std::invalid_argument (as append) when s.classes
  /// is not classEvidenceValid for the map's n_classes.
  void set(int i, const Surfel& s);

  /// Counts of what a class-evidence update did (ClassEvidenceResult per surfel).
  struct ClassUpdateStats {
    int updated = 0;   ///< added to the class's slot
    int new_slot = 0;  ///< the class took an empty slot
    int replaced = 0;  ///< the class replaced a weaker class (which fell back to the prior)
    int dropped = 0;   ///< all slots held stronger evidence: nothing recorded
    int surfels() const { return updated + new_slot + replaced + dropped; }
  };
  /// The Bayes update of IV, p_c <- p_d p_c / (p_d p_c + (1 - p_d)(1 - p_c)), for class
  /// `class_id` (1..n_classes) with detection probability `p_detection` (0..1) on the given
  /// surfels, as L_c += logit(p_d) (classEvidenceUpdate, slot rule in ClassEvidence.h). Applied in
  /// list order (a duplicate index is updated twice). Throws std::invalid_argument for a bad
  /// class, probability or index (nothing changed then). Does not count as a modification for
  /// generation(): it changes no attribute fusion caches, and a classification stage updating
  /// every frame must not make fusion rebuild its pruning schedule. O(k).
  ClassUpdateStats addClassEvidence(const std::vector<int>& surfels, int class_id,
                                    float p_detection);
  /// The same update on every surfel with segment label `segment` (> 0): one parallel pass over
  /// the whole map, O(N) (a caller with the segment's member list passes it to the overload above).
  ClassUpdateStats addClassEvidenceToSegment(std::uint32_t segment, int class_id,
                                             float p_detection);
  /// The arrays for a caller that writes class evidence (class_ev) and nothing else, e.g. the
  /// classification stage's batch of segment updates in one pass: like addClassEvidence it does
  /// not count as a modification for generation().
  SurfelArrays arraysForClassEvidence() { return static_cast<const SurfelStore&>(*this).arrays(); }

  /// Segment relabelling of III (merges, filling unused ids): every surfel with segment l <
  /// table.size() gets table[l] (0 = none); labels >= table.size() are left alone. Like
  /// addClassEvidence it does not count as a modification for generation() (no attribute fusion
  /// caches changes). One parallel pass, O(N). Returns the surfels whose label changed.
  int relabelSegments(const std::vector<std::uint32_t>& table);

  const VoxelBlockIndex& spatialIndex() const { return index_; }
  /// Upper bound of the radius of every indexed surfel (grows with indexAppended / reindex / set;
  /// exact after rebuildIndex). The renderer grows its frustum culling by it.
  float radiusBound() const { return radius_bound_; }

  /// Time origin (absolute seconds) of the stored float times; NaN until set.
  double timeOrigin() const { return t0_s_; }
  bool hasTimeOrigin() const { return t0_s_ == t0_s_; }
  void setTimeOrigin(double t0_s) { t0_s_ = t0_s; }
  /// Absolute seconds <-> stored float (0 before the origin is set).
  float toMapTime(double t_s) const { return hasTimeOrigin() ? float(t_s - t0_s_) : 0.0f; }
  double fromMapTime(float t) const { return (hasTimeOrigin() ? t0_s_ : 0.0) + double(t); }

  /// Bytes per surfel of the arrays (SurfelArrays.h budget; n_classes only matters as 0 / > 0)
  /// and of the spatial index.
  static std::size_t bytesPerSurfel(int n_classes, int n_view_bins);
  static constexpr std::size_t kIndexBytesPerSurfel = 12;
  /// Bytes held by arrays and index (capacity based).
  std::size_t memoryBytes() const;

  /// Bumped by every call that may modify surfels (append, allocate, set, remove, reset, and the
  /// mutable arrays()) except addClassEvidence*: a consumer that caches per-surfel state (fusion's
  /// pruning schedule) tells from it whether someone else changed the map since it last did.
  std::uint64_t generation() const { return generation_.value; }

  /// Spatial index consistent with the positions and stable flags (tests).
  bool checkConsistency(std::string* why = nullptr) const;

 private:
  void resizeArrays(int n);
  void checkClassUpdate(int class_id, float p_detection, const char* who) const;
  void moveSurfel(int from, int to);

  SurfelStoreOptions opt_;
  int size_ = 0;
  int indexed_ = 0;  ///< surfels [0, indexed_) are in index_
  double t0_s_ = std::numeric_limits<double>::quiet_NaN();
  float radius_bound_ = 0.0f;
  long long unsorted_ = 0;  ///< appended or moved since the last sortByBlock() (unsortedFraction)

  /// Unique across stores: a copy, or a new store that happens to live at a freed store's
  /// address, never continues another store's sequence.
  struct Generation {
    std::uint64_t value = next();
    Generation() = default;
    Generation(const Generation&) : value(next()) {}
    Generation& operator=(const Generation&) {
      value = next();
      return *this;
    }
    static std::uint64_t next() {
      static std::atomic<std::uint64_t> stores{0};
      return (stores.fetch_add(1) + 1) << 32;
    }
  };
  Generation generation_;

  // Growth never copies (PodArray.h): no reallocation spike when a large map grows.
  PodArray<Vec4f> pos_conf_;
  PodArray<Vec4f> normal_radius_;
  PodArray<std::uint32_t> colour_flags_;
  PodArray<float> t_init_;
  PodArray<float> t_last_;
  PodArray<Vec3f> basis_;
  PodArray<std::uint32_t> segment_;
  PodArray<float> segment_w_;
  PodArray<ClassEvidence> class_ev_;  ///< empty when n_classes = 0
  PodArray<std::uint8_t> view_ic_;

  VoxelBlockIndex index_;
};

}  // namespace rasm::maps
