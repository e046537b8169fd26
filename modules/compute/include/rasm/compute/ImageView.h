#pragma once
// ImageView<T>: a non-owning, pitched 2-D view of plain data (pointer, width, height, pitch in
// bytes). It is what kernels see on both backends; owning images live in core (rasm::Image<T>).

#include <cstddef>
#include <type_traits>

#include "rasm/compute/Platform.h"

namespace rasm {

template <typename T>
struct ImageView {
  T* data = nullptr;
  int width = 0;
  int height = 0;
  std::size_t pitch_bytes = 0;  ///< bytes from one row to the next (>= width * sizeof(T))

  RASM_HD ImageView() = default;
  RASM_HD ImageView(T* d, int w, int h, std::size_t pitch)
      : data(d), width(w), height(h), pitch_bytes(pitch) {}
  RASM_HD ImageView(T* d, int w, int h)
      : data(d), width(w), height(h), pitch_bytes(sizeof(T) * w) {}

  RASM_HD_INLINE T* row(int y) const {
    return reinterpret_cast<T*>(reinterpret_cast<char*>(const_cast<std::remove_const_t<T>*>(data)) +
                                static_cast<std::size_t>(y) * pitch_bytes);
  }
  RASM_HD_INLINE T& operator()(int x, int y) const { return row(y)[x]; }
  RASM_HD_INLINE bool inside(int x, int y) const {
    return x >= 0 && y >= 0 && x < width && y < height;
  }
  RASM_HD_INLINE bool empty() const { return data == nullptr || width <= 0 || height <= 0; }
  RASM_HD_INLINE int pixels() const { return width * height; }

  /// Read-only view of the same pixels.
  RASM_HD operator ImageView<const T>() const {
    return ImageView<const T>(data, width, height, pitch_bytes);
  }
};

}  // namespace rasm
