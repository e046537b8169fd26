// Bounds the image and point-cloud sizes MRPT's deserializers take from a rawlog or map before
// reading the data (issue 15, found by fuzz_rawlog). MRPT 2.5's
// CObservation3DRangeScan::serializeFrom reads a range image's rows and cols (two uint32) and
// calls rangeImage_setSize(rows, cols), and reads a point count N and calls
// resizePoints3DVectors(N), before any pixel or point is read; CImage::serializeFrom calls
// CImage::resize(width, height, ...) the same way. One corrupt size field thus allocated up to
// 12 PB (ASan allocation-size-too-big; in a release build a std::bad_alloc, or gigabytes of
// overcommitted memory touched by the read that follows).
//
// These definitions of the same exported member functions interpose MRPT's for the process, as
// MrptStringLimit.cpp does for strings (rasm_io is loaded before libmrpt-obs / libmrpt-img, and
// MRPT calls them through the PLT): each checks the size against a limit far above any depth
// camera (kMaxPixels, 33.5 M pixels or points; a side of at most 32768) and then calls MRPT's own
// definition, found with dlsym(RTLD_NEXT), so the behaviour for valid sizes is MRPT's.
// tests/io/RawlogFrameSource_unittest.cpp (CorruptRangeImageSizeIsAnErrorNotAnAllocation).
#include <mrpt/core/exceptions.h>
#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservation3DRangeScan.h>

#include <dlfcn.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace rasm::io {
/// Largest image (width x height) or point cloud accepted from an MRPT archive.
constexpr std::uint64_t kMaxPixels = std::uint64_t(1) << 25;
/// Largest image side: a corrupt 1 x 2^24 image is as suspicious as a huge square one.
constexpr std::uint64_t kMaxSide = std::uint64_t(1) << 15;

namespace {
/// MRPT's definition of the interposed symbol (the next one after rasm_io's in lookup order).
template <typename Fn>
Fn mrptDefinition(const char* mangled) {
  void* f = dlsym(RTLD_NEXT, mangled);
  if (f == nullptr) THROW_EXCEPTION_FMT("rasm: MRPT's %s not found (dlsym: %s)", mangled, dlerror());
  return reinterpret_cast<Fn>(f);
}

void checkImageSize(const char* what, std::int64_t height, std::int64_t width) {
  if (height < 0 || width < 0 || std::uint64_t(height) > kMaxSide || std::uint64_t(width) > kMaxSide ||
      std::uint64_t(height) * std::uint64_t(width) > kMaxPixels)
    THROW_EXCEPTION_FMT(
        "serialized %s of %lld x %lld pixels (corrupt file?); rasm reads images of at most %llu "
        "pixels per side and %llu in all",
        what, static_cast<long long>(width), static_cast<long long>(height),
        static_cast<unsigned long long>(kMaxSide), static_cast<unsigned long long>(kMaxPixels));
}
}  // namespace
}  // namespace rasm::io

namespace mrpt::obs {

void CObservation3DRangeScan::rangeImage_setSize(const int H, const int W) {
  using Fn = void (*)(CObservation3DRangeScan*, int, int);
  static const Fn mrpt = rasm::io::mrptDefinition<Fn>("_ZN4mrpt3obs23CObservation3DRangeScan18rangeImage_setSizeEii");
  rasm::io::checkImageSize("range image", H, W);
  mrpt(this, H, W);
}

void CObservation3DRangeScan::resizePoints3DVectors(const size_t nPoints) {
  using Fn = void (*)(CObservation3DRangeScan*, size_t);
  static const Fn mrpt =
      rasm::io::mrptDefinition<Fn>("_ZN4mrpt3obs23CObservation3DRangeScan21resizePoints3DVectorsEm");
  if (nPoints > rasm::io::kMaxPixels)
    THROW_EXCEPTION_FMT("serialized point cloud of %zu points (corrupt file?); rasm reads at most %llu",
                        nPoints, static_cast<unsigned long long>(rasm::io::kMaxPixels));
  mrpt(this, nPoints);
}

}  // namespace mrpt::obs

namespace mrpt::img {

void CImage::resize(std::size_t width, std::size_t height, TImageChannels nChannels, PixelDepth depth) {
  using Fn = void (*)(CImage*, std::size_t, std::size_t, TImageChannels, PixelDepth);
  static const Fn mrpt =
      rasm::io::mrptDefinition<Fn>("_ZN4mrpt3img6CImage6resizeEmmNS0_14TImageChannelsENS0_10PixelDepthE");
  rasm::io::checkImageSize("image", static_cast<std::int64_t>(std::min<std::size_t>(height, 1u << 31)),
                           static_cast<std::int64_t>(std::min<std::size_t>(width, 1u << 31)));
  mrpt(this, width, height, nChannels, depth);
}

}  // namespace mrpt::img
