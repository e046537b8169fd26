#pragma once
// Growable array of plain (bitwise-copyable, trivially destructible) elements for the surfel
// arrays: growth never copies the contents. On Linux the buffer is an anonymous mapping grown with
// mremap(MREMAP_MAYMOVE), which moves page-table entries instead of bytes, so appending to a map
// of millions of surfels has no O(N) reallocation spike (std::vector copies the whole array each
// time it outgrows its capacity: ~100 MB per surfel-map doubling). Elsewhere it falls back to
// realloc. Pages are zero-filled by the kernel on first touch, so reserving costs no memory.

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <new>
#include <type_traits>
#include <utility>

namespace rasm::maps {

namespace detail {
/// Page-granular buffer: allocate / grow (contents kept) / free. Throw std::bad_alloc.
void* podAllocate(std::size_t bytes);
void* podGrow(void* p, std::size_t old_bytes, std::size_t new_bytes);
void podFree(void* p, std::size_t bytes);
/// Capacity in bytes actually reserved for a request (page rounding).
std::size_t podRoundBytes(std::size_t bytes);
}  // namespace detail

template <typename T>
class PodArray {
  static_assert(std::is_trivially_destructible_v<T>, "PodArray holds plain data only");

 public:
  PodArray() = default;
  ~PodArray() { detail::podFree(data_, cap_bytes_); }
  PodArray(const PodArray& o) { *this = o; }
  PodArray(PodArray&& o) noexcept { swap(o); }
  PodArray& operator=(const PodArray& o) {
    if (this != &o) {
      size_ = 0;
      reserve(o.size_);
      if (o.size_) std::memcpy(static_cast<void*>(data_), o.data_, o.size_ * sizeof(T));
      size_ = o.size_;
    }
    return *this;
  }
  PodArray& operator=(PodArray&& o) noexcept {
    swap(o);
    return *this;
  }
  void swap(PodArray& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(size_, o.size_);
    std::swap(cap_bytes_, o.cap_bytes_);
  }

  T* data() { return data_; }
  const T* data() const { return data_; }
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return cap_bytes_ / sizeof(T); }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }

  void reserve(std::size_t n) {
    if (n <= capacity()) return;
    const std::size_t bytes = detail::podRoundBytes(n * sizeof(T));
    data_ = static_cast<T*>(data_ ? detail::podGrow(data_, cap_bytes_, bytes)
                                  : detail::podAllocate(bytes));
    cap_bytes_ = bytes;
  }
  /// New elements are set to `fill`; growth is geometric (x1.5), shrinking keeps the memory.
  void resize(std::size_t n, const T& fill) {
    if (n > capacity()) reserve(std::max(n, capacity() + capacity() / 2));
    for (std::size_t i = size_; i < n; ++i) data_[i] = fill;
    size_ = n;
  }
  /// Frees the memory.
  void clear() {
    detail::podFree(data_, cap_bytes_);
    data_ = nullptr;
    size_ = 0;
    cap_bytes_ = 0;
  }

 private:
  T* data_ = nullptr;
  std::size_t size_ = 0;
  std::size_t cap_bytes_ = 0;
};

}  // namespace rasm::maps
