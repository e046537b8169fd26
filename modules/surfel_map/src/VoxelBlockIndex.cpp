#include "rasm/surfel_map/VoxelBlockIndex.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rasm::maps {

namespace {
constexpr int kBits = 21;
constexpr std::int64_t kBias = std::int64_t(1) << (kBits - 1);
constexpr std::uint64_t kMask = (std::uint64_t(1) << kBits) - 1;

std::uint64_t packKey(const Eigen::Vector3i& c) {
  return (std::uint64_t(c.x() + kBias) & kMask) |
         ((std::uint64_t(c.y() + kBias) & kMask) << kBits) |
         ((std::uint64_t(c.z() + kBias) & kMask) << (2 * kBits));
}
}  // namespace

CameraFrustum CameraFrustum::fromCamera(const RigidF& T_world_cam, const PinholeF& K,
                                        float min_depth_m, float max_depth_m) {
  // Side planes through the optical centre: x >= xl z, x <= xr z, y >= yt z, y <= yb z (camera
  // frame) with the image borders at the outer pixel edges. fx or fy may be negative (ICL-NUIM).
  float xl = (-0.5f - K.cx) / K.fx, xr = (float(K.width) - 0.5f - K.cx) / K.fx;
  float yt = (-0.5f - K.cy) / K.fy, yb = (float(K.height) - 0.5f - K.cy) / K.fy;
  if (xl > xr) std::swap(xl, xr);
  if (yt > yb) std::swap(yt, yb);
  const Vec3f n_cam[6] = {Vec3f(1, 0, -xl).normalized(),
                          Vec3f(-1, 0, xr).normalized(),
                          Vec3f(0, 1, -yt).normalized(),
                          Vec3f(0, -1, yb).normalized(),
                          Vec3f(0, 0, 1),
                          Vec3f(0, 0, -1)};
  const float d_cam[6] = {0, 0, 0, 0, -min_depth_m, max_depth_m};
  CameraFrustum f;
  const Vec3f t = T_world_cam.translation();
  for (int i = 0; i < 6; ++i) {
    // n_w . p_w + d_w = n_c . (R^T (p_w - t)) + d_c  =>  n_w = R n_c, d_w = d_c - n_w . t
    const Vec3f nw = T_world_cam.rotate(n_cam[i]);
    f.planes[i] = Vec4f(nw.x(), nw.y(), nw.z(), d_cam[i] - nw.dot(t));
  }
  return f;
}

VoxelBlockIndex::VoxelBlockIndex(float block_size_m) : block_size_m_(block_size_m) {
  if (!(block_size_m > 0.0f))
    throw std::invalid_argument("VoxelBlockIndex: block size must be > 0");
  inv_block_size_ = 1.0f / block_size_m;
}

std::uint64_t VoxelBlockIndex::keyOf(const Vec3f& p) const {
  const Eigen::Vector3i c(int(std::floor(p.x() * inv_block_size_)),
                          int(std::floor(p.y() * inv_block_size_)),
                          int(std::floor(p.z() * inv_block_size_)));
  return packKey(c);
}

int VoxelBlockIndex::blockFor(std::uint64_t key, const Eigen::Vector3i& coords) {
  auto it = key_to_block_.find(key);
  if (it != key_to_block_.end()) return it->second;
  int id;
  if (!free_blocks_.empty()) {
    id = free_blocks_.back();
    free_blocks_.pop_back();
  } else {
    id = int(blocks_.size());
    blocks_.emplace_back();
  }
  Block& b = blocks_[id];
  b.coords = coords;
  b.key = key;
  b.members.clear();
  b.n_stable = 0;
  key_to_block_.emplace(key, id);
  return id;
}

void VoxelBlockIndex::ensureSurfel(int surfel) {
  if (surfel >= int(surfel_block_.size())) {
    surfel_block_.resize(surfel + 1, -1);
    surfel_slot_.resize(surfel + 1, -1);
  }
}

void VoxelBlockIndex::swapSlots(Block& b, int slot_a, int slot_b) {
  if (slot_a == slot_b) return;
  std::swap(b.members[slot_a], b.members[slot_b]);
  surfel_slot_[b.members[slot_a]] = slot_a;
  surfel_slot_[b.members[slot_b]] = slot_b;
}

void VoxelBlockIndex::addToBlock(int surfel, int block_id, bool stable) {
  Block& b = blocks_[block_id];
  surfel_block_[surfel] = block_id;
  surfel_slot_[surfel] = int(b.members.size());
  b.members.push_back(surfel);
  if (stable) swapSlots(b, surfel_slot_[surfel], b.n_stable++);
}

void VoxelBlockIndex::setStable(int surfel, bool stable) {
  const int id = blockOf(surfel);
  if (id < 0) throw std::logic_error("VoxelBlockIndex::setStable: surfel not indexed");
  Block& b = blocks_[id];
  const int slot = surfel_slot_[surfel];
  if ((slot < b.n_stable) == stable) return;
  if (stable)
    swapSlots(b, slot, b.n_stable++);
  else
    swapSlots(b, slot, --b.n_stable);
}

void VoxelBlockIndex::insert(int surfel, const Vec3f& p, bool stable) {
  ensureSurfel(surfel);
  if (surfel_block_[surfel] >= 0)
    throw std::logic_error("VoxelBlockIndex::insert: surfel already indexed");
  const Eigen::Vector3i c(int(std::floor(p.x() * inv_block_size_)),
                          int(std::floor(p.y() * inv_block_size_)),
                          int(std::floor(p.z() * inv_block_size_)));
  addToBlock(surfel, blockFor(packKey(c), c), stable);
}

void VoxelBlockIndex::insertRange(int first, int count, const Vec4f* pos_conf,
                                  const std::uint32_t* flags, std::uint32_t stable_mask) {
  if (count <= 0) return;
  ensureSurfel(first + count - 1);
  std::uint64_t last_key = ~std::uint64_t(0);
  int last_block = -1;
  for (int i = first; i < first + count; ++i) {
    if (surfel_block_[i] >= 0)
      throw std::logic_error("VoxelBlockIndex::insertRange: surfel already indexed");
    const Vec4f& p = pos_conf[i];
    const Eigen::Vector3i c(int(std::floor(p.x() * inv_block_size_)),
                            int(std::floor(p.y() * inv_block_size_)),
                            int(std::floor(p.z() * inv_block_size_)));
    const std::uint64_t key = packKey(c);
    if (key != last_key) {
      last_block = blockFor(key, c);
      last_key = key;
    }
    addToBlock(i, last_block, flags != nullptr && (flags[i] & stable_mask) != 0);
  }
}

void VoxelBlockIndex::eraseFromBlock(int surfel) {
  const int b = surfel_block_[surfel];
  Block& B = blocks_[b];
  // Leave the stable part first (its last entry takes the slot), then swap with the list's end.
  if (surfel_slot_[surfel] < B.n_stable) swapSlots(B, surfel_slot_[surfel], --B.n_stable);
  std::vector<int>& m = B.members;
  swapSlots(B, surfel_slot_[surfel], int(m.size()) - 1);
  m.pop_back();
  surfel_block_[surfel] = -1;
  surfel_slot_[surfel] = -1;
  if (m.empty()) {
    key_to_block_.erase(blocks_[b].key);
    free_blocks_.push_back(b);
  }
}

void VoxelBlockIndex::erase(int surfel) {
  if (surfel < 0 || surfel >= int(surfel_block_.size()) || surfel_block_[surfel] < 0)
    throw std::logic_error("VoxelBlockIndex::erase: surfel not indexed");
  eraseFromBlock(surfel);
}

bool VoxelBlockIndex::move(int surfel, const Vec3f& p) {
  const int b = blockOf(surfel);
  if (b < 0) throw std::logic_error("VoxelBlockIndex::move: surfel not indexed");
  const Eigen::Vector3i c(int(std::floor(p.x() * inv_block_size_)),
                          int(std::floor(p.y() * inv_block_size_)),
                          int(std::floor(p.z() * inv_block_size_)));
  if (c == blocks_[b].coords) return false;
  const bool stable = isStable(surfel);
  eraseFromBlock(surfel);
  addToBlock(surfel, blockFor(packKey(c), c), stable);
  return true;
}

void VoxelBlockIndex::renumber(int from, int to) {
  const int b = blockOf(from);
  if (b < 0) throw std::logic_error("VoxelBlockIndex::renumber: surfel not indexed");
  ensureSurfel(to);
  if (surfel_block_[to] >= 0)
    throw std::logic_error("VoxelBlockIndex::renumber: target index in use");
  const int slot = surfel_slot_[from];
  blocks_[b].members[slot] = to;
  surfel_block_[to] = b;
  surfel_slot_[to] = slot;
  surfel_block_[from] = -1;
  surfel_slot_[from] = -1;
  // Keep the per-surfel tables as short as the highest indexed surfel.
  while (!surfel_block_.empty() && surfel_block_.back() < 0) {
    surfel_block_.pop_back();
    surfel_slot_.pop_back();
  }
}

void VoxelBlockIndex::permute(const std::vector<int>& new_of_old) {
  const int n = numSurfels();
  if (int(new_of_old.size()) != n)
    throw std::invalid_argument("VoxelBlockIndex::permute: " + std::to_string(new_of_old.size()) +
                                " new indices for " + std::to_string(n) + " surfels");
  // The old per-surfel tables are not read again: rewritten in place (no second copy at the
  // peak of a re-sort). Every index in [0, n) is indexed, so a permutation rewrites all of them.
  std::fill(surfel_block_.begin(), surfel_block_.end(), -1);
  for (int b = 0; b < int(blocks_.size()); ++b) {
    std::vector<int>& m = blocks_[b].members;
    for (int k = 0; k < int(m.size()); ++k) {
      const int j = new_of_old[std::size_t(m[k])];
      if (j < 0 || j >= n || surfel_block_[std::size_t(j)] >= 0)
        throw std::invalid_argument(
            "VoxelBlockIndex::permute: not a permutation of the indexed surfels");
      m[k] = j;
      surfel_block_[std::size_t(j)] = b;
      surfel_slot_[std::size_t(j)] = k;
    }
  }
}

void VoxelBlockIndex::clear() {
  key_to_block_.clear();
  blocks_.clear();
  free_blocks_.clear();
  surfel_block_.clear();
  surfel_slot_.clear();
}

void VoxelBlockIndex::blocksInFrustum(const CameraFrustum& frustum, float margin_m,
                                      std::vector<int>& block_ids,
                                      std::vector<std::uint8_t>* fully_inside) const {
  const float half = 0.5f * block_size_m_;
  const float inner = half * 1.7320508f;  // circumscribed sphere of the cube
  const float radius = inner + margin_m;
  for (int b = 0; b < int(blocks_.size()); ++b) {
    if (blocks_[b].members.empty()) continue;
    const Vec3f centre = blocks_[b].coords.cast<float>() * block_size_m_ + Vec3f::Constant(half);
    if (!frustum.intersectsSphere(centre, radius)) continue;
    block_ids.push_back(b);
    if (fully_inside)
      fully_inside->push_back(frustum.containsSphere(centre, inner * 1.001f) ? 1 : 0);
  }
}

bool VoxelBlockIndex::checkConsistency(const Vec4f* pos_conf, int n, std::string* why,
                                       const std::uint32_t* flags,
                                       std::uint32_t stable_mask) const {
  auto fail = [&](const std::string& s) {
    if (why) *why = s;
    return false;
  };
  std::size_t members = 0;
  for (int b = 0; b < int(blocks_.size()); ++b) {
    members += blocks_[b].members.size();
    if (blocks_[b].n_stable < 0 || blocks_[b].n_stable > int(blocks_[b].members.size()))
      return fail("block " + std::to_string(b) + " stable count out of range");
    if (!blocks_[b].members.empty()) {
      auto it = key_to_block_.find(blocks_[b].key);
      if (it == key_to_block_.end() || it->second != b) return fail("block key table out of sync");
    }
  }
  if (members != std::size_t(n)) {
    std::ostringstream s;
    s << "index holds " << members << " surfels, map has " << n;
    return fail(s.str());
  }
  for (int i = 0; i < n; ++i) {
    const int b = blockOf(i);
    if (b < 0) return fail("surfel " + std::to_string(i) + " not indexed");
    const int slot = surfel_slot_[i];
    if (slot < 0 || slot >= int(blocks_[b].members.size()) || blocks_[b].members[slot] != i)
      return fail("surfel " + std::to_string(i) + " slot mismatch");
    if (keyOf(pos_conf[i].head<3>()) != blocks_[b].key)
      return fail("surfel " + std::to_string(i) + " is not in the block containing it");
    if (flags && isStable(i) != ((flags[i] & stable_mask) != 0))
      return fail("surfel " + std::to_string(i) +
                  (isStable(i) ? " is in the stable part but not stable"
                               : " is stable but not in the stable part"));
  }
  return true;
}

std::size_t VoxelBlockIndex::memoryBytes() const {
  std::size_t bytes =
      (surfel_block_.capacity() + surfel_slot_.capacity()) * sizeof(int) +
      blocks_.capacity() * sizeof(Block) + free_blocks_.capacity() * sizeof(int) +
      key_to_block_.size() * (sizeof(std::uint64_t) + sizeof(int) + 2 * sizeof(void*)) +
      key_to_block_.bucket_count() * sizeof(void*);
  for (const Block& b : blocks_) bytes += b.members.capacity() * sizeof(int);
  return bytes;
}

}  // namespace rasm::maps
