#pragma once
// rasm::Image<T>: owning, pitched image of plain pixels. Rows are padded to 64 bytes so SIMD
// loops and CUDA copies stay aligned. Kernels see it through view() (compute's ImageView<T>).

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#include "rasm/compute/ImageView.h"

namespace rasm {

template <typename T>
class Image {
 public:
  Image() = default;
  Image(int width, int height) { resize(width, height); }
  Image(int width, int height, const T& fill) {
    resize(width, height);
    setTo(fill);
  }
  Image(const Image& o) { *this = o; }
  Image(Image&&) noexcept = default;
  Image& operator=(Image&&) noexcept = default;
  Image& operator=(const Image& o) {
    if (this == &o) return *this;
    resize(o.width_, o.height_);
    // (element types are trivially copyable in practice; Eigen vectors do not declare it)
    for (int y = 0; y < height_; ++y)
      std::memcpy(static_cast<void*>(row(y)), o.row(y), sizeof(T) * width_);
    return *this;
  }

  /// Reallocates only when the size changes; contents are then undefined.
  void resize(int width, int height) {
    if (width < 0 || height < 0) throw std::invalid_argument("Image::resize: negative size");
    if (width == width_ && height == height_ && buf_) return;
    width_ = width;
    height_ = height;
    pitch_ = ((sizeof(T) * width + 63) / 64) * 64;
    if (pitch_ == 0) pitch_ = 64;
    buf_.reset(new char[pitch_ * std::max(height, 1) + 64]);
  }
  void setTo(const T& v) {
    for (int y = 0; y < height_; ++y) {
      T* r = row(y);
      for (int x = 0; x < width_; ++x) r[x] = v;
    }
  }

  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t pitchBytes() const { return pitch_; }
  bool empty() const { return width_ == 0 || height_ == 0; }
  bool sameSize(int w, int h) const { return width_ == w && height_ == h; }
  template <typename U>
  bool sameSize(const Image<U>& o) const {
    return width_ == o.width() && height_ == o.height();
  }

  T* data() { return reinterpret_cast<T*>(aligned()); }
  const T* data() const { return reinterpret_cast<const T*>(aligned()); }
  T* row(int y) { return reinterpret_cast<T*>(aligned() + pitch_ * y); }
  const T* row(int y) const { return reinterpret_cast<const T*>(aligned() + pitch_ * y); }
  T& operator()(int x, int y) { return row(y)[x]; }
  const T& operator()(int x, int y) const { return row(y)[x]; }

  ImageView<T> view() { return ImageView<T>(data(), width_, height_, pitch_); }
  ImageView<const T> view() const { return ImageView<const T>(data(), width_, height_, pitch_); }
  ImageView<const T> cview() const { return view(); }

 private:
  char* aligned() const {
    auto p = reinterpret_cast<std::uintptr_t>(buf_.get());
    return reinterpret_cast<char*>((p + 63) & ~std::uintptr_t(63));
  }
  std::unique_ptr<char[]> buf_;
  int width_ = 0, height_ = 0;
  std::size_t pitch_ = 0;
};

}  // namespace rasm
