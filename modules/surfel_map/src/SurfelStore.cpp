#include "rasm/surfel_map/SurfelStore.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "rasm/compute/Parallel.h"

namespace rasm::maps {

namespace {
void checkOptions(const SurfelStoreOptions& o) {
  if (o.n_classes < 0 || o.n_classes > kMaxClassId || o.view_bins_azimuth < 0 ||
      o.view_bins_elevation < 0 || o.nViewBins() > 4096 || !(o.block_size_m > 0.0f)) {
    std::ostringstream s;
    s << "SurfelStoreOptions: invalid layout n_classes=" << o.n_classes
      << " view_bins_azimuth=" << o.view_bins_azimuth
      << " view_bins_elevation=" << o.view_bins_elevation << " block_size_m=" << o.block_size_m;
    throw std::invalid_argument(s.str());
  }
}
}  // namespace

SurfelStore::SurfelStore(const SurfelStoreOptions& opt) : opt_(opt), index_(opt.block_size_m) {
  checkOptions(opt);
}

void SurfelStore::reset(const SurfelStoreOptions& opt) {
  checkOptions(opt);
  opt_ = opt;
  size_ = 0;
  indexed_ = 0;
  unsorted_ = 0;
  t0_s_ = std::numeric_limits<double>::quiet_NaN();
  radius_bound_ = 0.0f;
  ++generation_.value;
  pos_conf_.clear();
  normal_radius_.clear();
  colour_flags_.clear();
  t_init_.clear();
  t_last_.clear();
  basis_.clear();
  segment_.clear();
  segment_w_.clear();
  class_ev_.clear();
  view_ic_.clear();
  index_ = VoxelBlockIndex(opt.block_size_m);
}

void SurfelStore::reserve(int n) {
  pos_conf_.reserve(n);
  normal_radius_.reserve(n);
  colour_flags_.reserve(n);
  t_init_.reserve(n);
  t_last_.reserve(n);
  basis_.reserve(n);
  segment_.reserve(n);
  segment_w_.reserve(n);
  if (opt_.n_classes > 0) class_ev_.reserve(std::size_t(n));
  view_ic_.reserve(std::size_t(n) * opt_.nViewBins());
}

void SurfelStore::resizeArrays(int n) {
  pos_conf_.resize(n, Vec4f::Zero());
  normal_radius_.resize(n, Vec4f(0, 0, 1, 0));
  colour_flags_.resize(n, 0u);
  t_init_.resize(n, 0.0f);
  t_last_.resize(n, 0.0f);
  basis_.resize(n, Vec3f::UnitX());
  segment_.resize(n, 0u);
  segment_w_.resize(n, 0.0f);
  if (opt_.n_classes > 0) class_ev_.resize(std::size_t(n), ClassEvidence{});  // every class at 0.5
  view_ic_.resize(std::size_t(n) * opt_.nViewBins(), 0);
}

SurfelArrays SurfelStore::arrays() {
  ++generation_.value;
  return const_cast<const SurfelStore*>(this)->arrays();
}

SurfelArrays SurfelStore::arrays() const {
  SurfelStore& m = const_cast<SurfelStore&>(*this);  // SurfelArrays is one plain mutable type
  SurfelArrays a;
  a.pos_conf = m.pos_conf_.data();
  a.normal_radius = m.normal_radius_.data();
  a.colour_flags = m.colour_flags_.data();
  a.t_init = m.t_init_.data();
  a.t_last = m.t_last_.data();
  a.basis = m.basis_.data();
  a.segment = m.segment_.data();
  a.segment_w = m.segment_w_.data();
  a.class_ev = opt_.n_classes > 0 ? m.class_ev_.data() : nullptr;
  a.view_ic = m.view_ic_.data();
  a.size = size_;
  a.n_classes = opt_.n_classes;
  a.n_view_bins = opt_.nViewBins();
  return a;
}

int SurfelStore::allocate(int count) {
  if (count < 0) throw std::invalid_argument("SurfelStore::allocate: negative count");
  const int first = size_;
  if (std::int64_t(size_) + count > std::int64_t(std::numeric_limits<int>::max() / 2))
    throw std::length_error("SurfelStore::allocate: too many surfels");
  size_ += count;
  unsorted_ += count;
  ++generation_.value;
  resizeArrays(size_);
  return first;
}

void SurfelStore::indexAppended() {
  if (indexed_ >= size_) return;
  index_.insertRange(indexed_, size_ - indexed_, pos_conf_.data(), colour_flags_.data(),
                     kSurfelStable);
  for (int i = indexed_; i < size_; ++i)
    radius_bound_ = std::max(radius_bound_, normal_radius_[i].w());
  indexed_ = size_;
}

int SurfelStore::reindex(const std::vector<int>& surfels) {
  // Parallel read-only pass (radius bound, which surfels crossed a block border), then the few
  // re-binnings serially in input order.
  const int n = int(surfels.size());
  const int nt = compute::maxThreads();
  std::vector<std::vector<int>> movers(nt);
  std::vector<float> rmax(nt, 0.0f);
#pragma omp parallel num_threads(nt)
  {
#ifdef _OPENMP
    const int t = omp_get_thread_num(), tn = omp_get_num_threads();
#else
    const int t = 0, tn = 1;
#endif
    const int begin = int(std::int64_t(n) * t / tn), end = int(std::int64_t(n) * (t + 1) / tn);
    for (int k = begin; k < end; ++k) {
      const int i = surfels[k];
      if (i < 0 || i >= indexed_) continue;
      rmax[t] = std::max(rmax[t], normal_radius_[i].w());
      if (index_.needsMove(i, pos_conf_[i].head<3>())) movers[t].push_back(i);
    }
  }
  int moved = 0;
  for (int t = 0; t < nt; ++t) {
    radius_bound_ = std::max(radius_bound_, rmax[t]);
    for (int i : movers[t]) moved += index_.move(i, pos_conf_[i].head<3>()) ? 1 : 0;
  }
  unsorted_ += moved;
  return moved;
}

void SurfelStore::rebuildIndex() {
  index_.clear();
  indexed_ = 0;
  radius_bound_ = 0.0f;
  indexAppended();
}

void SurfelStore::copySurfelsFrom(const SurfelStore& o) {
  opt_ = o.opt_;
  size_ = o.size_;
  t0_s_ = o.t0_s_;
  unsorted_ = o.unsorted_;
  pos_conf_ = o.pos_conf_;
  normal_radius_ = o.normal_radius_;
  colour_flags_ = o.colour_flags_;
  t_init_ = o.t_init_;
  t_last_ = o.t_last_;
  basis_ = o.basis_;
  segment_ = o.segment_;
  segment_w_ = o.segment_w_;
  class_ev_ = o.class_ev_;
  view_ic_ = o.view_ic_;
  index_.clear();
  indexed_ = 0;
  radius_bound_ = 0.0f;
  generation_.value = Generation::next();
}

void SurfelStore::copyThinnedFrom(const SurfelStore& o, int stride, float radius_scale) {
  if (stride < 1 || !(radius_scale > 0.0f))
    throw std::invalid_argument("SurfelStore::copyThinnedFrom: stride >= 1 and radius_scale > 0");
  opt_ = o.opt_;
  t0_s_ = o.t0_s_;
  int kept = 0, alive = 0;
  for (int i = 0; i < o.size_; ++i)
    if ((o.colour_flags_[i] & kSurfelFree) == 0) kept += alive++ % stride == 0;
  size_ = kept;
  resizeArrays(kept);
  const std::size_t nv = std::size_t(opt_.nViewBins());
  alive = 0;
  for (int i = 0, j = 0; i < o.size_; ++i) {
    if ((o.colour_flags_[i] & kSurfelFree) != 0 || alive++ % stride != 0) continue;
    pos_conf_[j] = o.pos_conf_[i];
    normal_radius_[j] = o.normal_radius_[i];
    normal_radius_[j].w() *= radius_scale;
    colour_flags_[j] = o.colour_flags_[i];
    t_init_[j] = o.t_init_[i];
    t_last_[j] = o.t_last_[i];
    basis_[j] = o.basis_[i];
    segment_[j] = o.segment_[i];
    segment_w_[j] = o.segment_w_[i];
    if (opt_.n_classes > 0) class_ev_[j] = o.class_ev_[i];
    if (nv > 0)
      std::copy_n(o.view_ic_.data() + std::size_t(i) * nv, nv,
                  view_ic_.data() + std::size_t(j) * nv);
    ++j;
  }
  unsorted_ = 0;
  index_.clear();
  indexed_ = 0;
  radius_bound_ = 0.0f;
  generation_.value = Generation::next();
}

int SurfelStore::append(const Surfel& s) {
  if (!classEvidenceValid(s.classes, opt_.n_classes))  // (set() would leave the slot allocated)
    throw std::invalid_argument("SurfelStore::append: class evidence invalid for n_classes = " +
                                std::to_string(opt_.n_classes));
  if (!hasTimeOrigin()) setTimeOrigin(s.t_init_s);
  const int i = allocate(1);
  set(i, s);
  indexAppended();
  return i;
}

void SurfelStore::set(int i, const Surfel& s) {
  if (i < 0 || i >= size_) throw std::out_of_range("SurfelStore::set: index " + std::to_string(i));
  if (!classEvidenceValid(s.classes, opt_.n_classes))
    throw std::invalid_argument(
        "SurfelStore::set: class evidence invalid for n_classes = " +
        std::to_string(opt_.n_classes) +
        " (ids 1..n_classes, unique, nonzero log-odds within the clamp, empty slots zero)");
  ++generation_.value;
  if (!s.view_ic.empty() && int(s.view_ic.size()) != opt_.nViewBins())
    throw std::invalid_argument("SurfelStore::set: view_ic has " +
                                std::to_string(s.view_ic.size()) + " values, the map has " +
                                std::to_string(opt_.nViewBins()) + " view bins");
  pos_conf_[i] = Vec4f(s.position.x(), s.position.y(), s.position.z(), s.confidence);
  normal_radius_[i] = Vec4f(s.normal.x(), s.normal.y(), s.normal.z(), s.radius);
  colour_flags_[i] = packColour(s.colour, s.stable ? kSurfelStable : 0u);
  t_init_[i] = toMapTime(s.t_init_s);
  t_last_[i] = toMapTime(s.t_last_s);
  basis_[i] = s.basis;
  segment_[i] = s.segment;
  segment_w_[i] = s.segment_weight;
  if (opt_.n_classes > 0) class_ev_[i] = s.classes;
  std::uint8_t* vb = view_ic_.data() + std::size_t(i) * opt_.nViewBins();
  for (int v = 0; v < opt_.nViewBins(); ++v)
    vb[v] = s.view_ic.empty() ? 0 : quantizeUnit(s.view_ic[v]);
  if (i < indexed_) {
    radius_bound_ = std::max(radius_bound_, s.radius);
    index_.move(i, s.position);
    index_.setStable(i, s.stable);
  }
}

void SurfelStore::refreshStable(const std::vector<int>& surfels) {
  for (const int i : surfels)
    if (i >= 0 && i < indexed_) index_.setStable(i, (colour_flags_[i] & kSurfelStable) != 0);
}

Surfel SurfelStore::get(int i) const {
  if (i < 0 || i >= size_) throw std::out_of_range("SurfelStore::get: index " + std::to_string(i));
  Surfel s;
  s.position = pos_conf_[i].head<3>();
  s.confidence = pos_conf_[i].w();
  s.normal = normal_radius_[i].head<3>();
  s.radius = normal_radius_[i].w();
  s.colour = unpackColour(colour_flags_[i]);
  s.stable = (colour_flags_[i] & kSurfelStable) != 0;
  s.t_init_s = fromMapTime(t_init_[i]);
  s.t_last_s = fromMapTime(t_last_[i]);
  s.basis = basis_[i];
  s.segment = segment_[i];
  s.segment_weight = segment_w_[i];
  if (opt_.n_classes > 0) s.classes = class_ev_[i];
  s.view_ic.resize(opt_.nViewBins());
  for (int v = 0; v < opt_.nViewBins(); ++v)
    s.view_ic[v] = dequantizeUnit(view_ic_[std::size_t(i) * opt_.nViewBins() + v]);
  return s;
}

void SurfelStore::moveSurfel(int from, int to) {
  pos_conf_[to] = pos_conf_[from];
  normal_radius_[to] = normal_radius_[from];
  colour_flags_[to] = colour_flags_[from];
  t_init_[to] = t_init_[from];
  t_last_[to] = t_last_[from];
  basis_[to] = basis_[from];
  segment_[to] = segment_[from];
  segment_w_[to] = segment_w_[from];
  const std::size_t nv = opt_.nViewBins();
  if (opt_.n_classes > 0) class_ev_[to] = class_ev_[from];
  std::copy_n(view_ic_.data() + from * nv, nv, view_ic_.data() + to * nv);
  if (from < indexed_) index_.renumber(from, to);
}

void SurfelStore::remove(std::vector<int> surfels, std::vector<std::pair<int, int>>* moved) {
  if (moved) moved->clear();
  if (surfels.empty()) return;
  std::sort(surfels.begin(), surfels.end());
  surfels.erase(std::unique(surfels.begin(), surfels.end()), surfels.end());
  if (surfels.front() < 0 || surfels.back() >= size_)
    throw std::out_of_range("SurfelStore::remove: index out of range");
  ++generation_.value;
  // Mark, and drop from the spatial index, every removed surfel.
  for (int i : surfels) {
    colour_flags_[i] |= kSurfelFree;
    if (i < indexed_) index_.erase(i);
  }
  // Fill the holes (ascending) with the alive surfels at the tail (descending).
  const int new_size = size_ - int(surfels.size());
  int tail = size_ - 1;
  for (int hole : surfels) {
    if (hole >= new_size) break;  // the remaining holes are in the dropped tail
    while (colour_flags_[tail] & kSurfelFree) --tail;
    moveSurfel(tail, hole);
    ++unsorted_;
    if (moved) moved->emplace_back(tail, hole);
    --tail;
  }
  // Indexed surfels only move down, so [0, min(old indexed_, new size)) stays indexed except for
  // holes filled from the unindexed tail (allocated, not yet indexAppended()): index those.
  const int keep_indexed = std::min(indexed_, new_size);
  for (const int hole : surfels) {
    if (hole >= keep_indexed) break;
    if (index_.blockOf(hole) < 0)
      index_.insert(hole, pos_conf_[hole].head<3>(), (colour_flags_[hole] & kSurfelStable) != 0);
  }
  indexed_ = keep_indexed;
  size_ = new_size;
  resizeArrays(size_);
}

namespace {
/// a[k] <- a[old_of_new[k]] for `stride` consecutive elements per surfel, through `scratch` (at
/// least a.size() * sizeof(T) bytes, shared by the arrays: no allocation, no page faults per
/// array); the arrays keep their memory and capacity.
template <typename T>
void gatherSurfels(PodArray<T>& a, const std::vector<int>& old_of_new, std::size_t stride,
                   unsigned char* scratch) {
  static_assert(std::is_trivially_destructible_v<T>, "plain data only (as PodArray)");
  if (stride == 0) return;
  T* data = a.data();
  T* tmp = reinterpret_cast<T*>(scratch);
  const int n = int(old_of_new.size());
  constexpr int kChunk = 4096;
  const int chunks = (n + kChunk - 1) / kChunk;
  compute::forEach1D(chunks, [&](int c) {
    const int k1 = std::min(n, (c + 1) * kChunk);
    for (int k = c * kChunk; k < k1; ++k)
      std::memcpy(static_cast<void*>(tmp + std::size_t(k) * stride),
                  data + std::size_t(old_of_new[std::size_t(k)]) * stride, stride * sizeof(T));
  });
  compute::forEach1D(chunks, [&](int c) {
    const std::size_t k0 = std::size_t(c) * kChunk * stride,
                      k1 = std::min(std::size_t(n), std::size_t(c + 1) * kChunk) * stride;
    std::memcpy(static_cast<void*>(data + k0), tmp + k0, (k1 - k0) * sizeof(T));
  });
}
}  // namespace

void SurfelStore::sortByBlock(std::vector<int>* new_of_old_out) {
  if (indexed_ != size_)
    throw std::logic_error(
        "SurfelStore::sortByBlock: surfels allocated but not indexed (call indexAppended())");
  ++generation_.value;
  std::vector<int> old_of_new;
  old_of_new.reserve(std::size_t(size_));
  for (int b = 0; b < index_.blockCapacity(); ++b)
    for (const int i : index_.members(b)) old_of_new.push_back(i);
  if (int(old_of_new.size()) != size_)
    throw std::logic_error("SurfelStore::sortByBlock: the spatial index holds " +
                           std::to_string(old_of_new.size()) + " surfels, the store " +
                           std::to_string(size_));
  {
    // Transient memory, freed as soon as it is no longer needed: the largest array's size plus
    // 4 bytes per surfel (old_of_new) during the gathers, then 8 bytes per surfel.
    const std::size_t nc = opt_.n_classes > 0 ? 1 : 0, nv = std::size_t(opt_.nViewBins());
    const std::size_t scratch_bytes =
        std::size_t(size_) * std::max({sizeof(Vec4f), sizeof(ClassEvidence), nv});
    const std::unique_ptr<unsigned char[]> scratch(new unsigned char[scratch_bytes]);
    gatherSurfels(pos_conf_, old_of_new, 1, scratch.get());
    gatherSurfels(normal_radius_, old_of_new, 1, scratch.get());
    gatherSurfels(colour_flags_, old_of_new, 1, scratch.get());
    gatherSurfels(t_init_, old_of_new, 1, scratch.get());
    gatherSurfels(t_last_, old_of_new, 1, scratch.get());
    gatherSurfels(basis_, old_of_new, 1, scratch.get());
    gatherSurfels(segment_, old_of_new, 1, scratch.get());
    gatherSurfels(segment_w_, old_of_new, 1, scratch.get());
    gatherSurfels(class_ev_, old_of_new, nc, scratch.get());
    gatherSurfels(view_ic_, old_of_new, nv, scratch.get());
  }
  std::vector<int> new_of_old(static_cast<std::size_t>(size_));
  for (int k = 0; k < size_; ++k) new_of_old[std::size_t(old_of_new[std::size_t(k)])] = k;
  std::vector<int>().swap(old_of_new);
  index_.permute(new_of_old);
  unsorted_ = 0;
  if (new_of_old_out) *new_of_old_out = std::move(new_of_old);
}

std::size_t SurfelStore::bytesPerSurfel(int n_classes, int n_view_bins) {
  return 2 * sizeof(Vec4f) + sizeof(std::uint32_t) + 2 * sizeof(float) + sizeof(Vec3f) +
         sizeof(std::uint32_t) + sizeof(float) + (n_classes > 0 ? sizeof(ClassEvidence) : 0) +
         std::size_t(n_view_bins);
}

void SurfelStore::checkClassUpdate(int class_id, float p_detection, const char* who) const {
  if (opt_.n_classes <= 0)
    throw std::invalid_argument(std::string(who) + ": the map has no classes (n_classes = 0)");
  if (class_id < 1 || class_id > opt_.n_classes)
    throw std::invalid_argument(std::string(who) + ": class " + std::to_string(class_id) +
                                " outside 1.." + std::to_string(opt_.n_classes));
  if (!(p_detection >= 0.0f && p_detection <= 1.0f))
    throw std::invalid_argument(std::string(who) + ": detection probability " +
                                std::to_string(p_detection) + " outside [0, 1]");
}

namespace {
void tally(SurfelStore::ClassUpdateStats& st, ClassEvidenceResult r) {
  switch (r) {
    case kClassUpdated:
      ++st.updated;
      break;
    case kClassNewSlot:
      ++st.new_slot;
      break;
    case kClassReplaced:
      ++st.replaced;
      break;
    default:
      ++st.dropped;
  }
}
}  // namespace

SurfelStore::ClassUpdateStats SurfelStore::addClassEvidence(const std::vector<int>& surfels,
                                                            int class_id, float p_detection) {
  checkClassUpdate(class_id, p_detection, "SurfelStore::addClassEvidence");
  for (const int i : surfels)
    if (i < 0 || i >= size_)
      throw std::invalid_argument("SurfelStore::addClassEvidence: surfel index " +
                                  std::to_string(i) + " outside 0.." + std::to_string(size_ - 1));
  const int units = quantizeClassLogit(probabilityLogit(p_detection));
  ClassUpdateStats st;
  for (const int i : surfels) tally(st, classEvidenceAdd(class_ev_[i], class_id, units));
  return st;
}

SurfelStore::ClassUpdateStats SurfelStore::addClassEvidenceToSegment(std::uint32_t segment,
                                                                     int class_id,
                                                                     float p_detection) {
  checkClassUpdate(class_id, p_detection, "SurfelStore::addClassEvidenceToSegment");
  if (segment == 0)
    throw std::invalid_argument("SurfelStore::addClassEvidenceToSegment: segment 0 is 'none'");
  const int units = quantizeClassLogit(probabilityLogit(p_detection));
  constexpr int kChunk = 1 << 16;
  const int chunks = (size_ + kChunk - 1) / kChunk;
  std::vector<ClassUpdateStats> per(std::size_t(std::max(chunks, 0)));
  const std::uint32_t* seg = segment_.data();
  ClassEvidence* ev = class_ev_.data();
  compute::forEach1D(chunks, [&](int c) {
    const int i1 = std::min(size_, (c + 1) * kChunk);
    for (int i = c * kChunk; i < i1; ++i)
      if (seg[i] == segment) tally(per[std::size_t(c)], classEvidenceAdd(ev[i], class_id, units));
  });
  ClassUpdateStats st;
  for (const ClassUpdateStats& p : per) {
    st.updated += p.updated;
    st.new_slot += p.new_slot;
    st.replaced += p.replaced;
    st.dropped += p.dropped;
  }
  return st;
}

int SurfelStore::relabelSegments(const std::vector<std::uint32_t>& table) {
  constexpr int kChunk = 1 << 16;
  const int chunks = (size_ + kChunk - 1) / kChunk;
  std::vector<int> changed(std::size_t(std::max(chunks, 0)), 0);
  std::uint32_t* seg = segment_.data();
  const std::size_t n = table.size();
  compute::forEach1D(chunks, [&](int c) {
    const int i1 = std::min(size_, (c + 1) * kChunk);
    int k = 0;
    for (int i = c * kChunk; i < i1; ++i)
      if (seg[i] < n && table[seg[i]] != seg[i]) {
        seg[i] = table[seg[i]];
        ++k;
      }
    changed[std::size_t(c)] = k;
  });
  int total = 0;
  for (int k : changed) total += k;
  return total;
}

std::size_t SurfelStore::memoryBytes() const {
  return pos_conf_.capacity() * sizeof(Vec4f) + normal_radius_.capacity() * sizeof(Vec4f) +
         colour_flags_.capacity() * 4 + t_init_.capacity() * 4 + t_last_.capacity() * 4 +
         basis_.capacity() * sizeof(Vec3f) + segment_.capacity() * 4 + segment_w_.capacity() * 4 +
         class_ev_.capacity() * sizeof(ClassEvidence) + view_ic_.capacity() + index_.memoryBytes();
}

bool SurfelStore::checkConsistency(std::string* why) const {
  if (indexed_ != size_) {
    if (why) *why = "surfels appended but not indexed (call indexAppended())";
    return false;
  }
  for (int i = 0; i < size_; ++i)
    if (colour_flags_[i] & kSurfelFree) {
      if (why) *why = "free flag set on live surfel " + std::to_string(i);
      return false;
    }
  return index_.checkConsistency(pos_conf_.data(), size_, why, colour_flags_.data(), kSurfelStable);
}

}  // namespace rasm::maps
