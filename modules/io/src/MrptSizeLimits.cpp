// Bounds the image and point-cloud sizes MRPT's deserializers take from a rawlog or map before
// reading the data (found by fuzz_rawlog). MRPT 2.5's
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
//
// CImage::serializeFrom itself is defined here too: MRPT's sizes the buffer of a compressed
// (JPEG) image from its uint32 byte count and zero-fills it before reading (up to 4 GB, and a
// timeout of the fuzzer while it is zeroed), and its version-0 reader copies as many bytes as the
// file says into the image it has just sized (a heap overflow for a corrupt count). This
// definition reads MRPT 2.5's CImage format (versions 0-9 and 100; CImage.cpp of 2.5.8, the
// writer rasm's rawlogs come from) through the class's public API, with the byte count capped at
// kMaxCompressedBytes, the buffer grown only as bytes arrive, and a raw payload checked against
// the image it fills (CorruptImageByteCountIsAnErrorNotAnAllocation).
//
// mrpt::aligned_malloc / aligned_calloc, the allocator under every MRPT matrix and aligned
// vector, are bounded last: the sizes above are not the only ones MRPT takes from a file before
// reading the data (a version-10 range scan's extra range layers are sized by
// CMatrixDynamic::resize(rows, cols) from two uint32 in the file; found by fuzz_rawlog as a
// 7 EB request). Any single MRPT allocation over kMaxAlignedBytes is an error naming its size,
// and one the system refuses is std::bad_alloc instead of the null pointer MRPT's containers
// would write through (CorruptRangeLayerSizeIsAnErrorNotAnAllocation).
#include <mrpt/core/exceptions.h>
#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/serialization/CArchive.h>

#include <opencv2/core/mat.hpp>
#include <opencv2/imgcodecs.hpp>

#include <dlfcn.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

namespace rasm::io {
/// Largest image (width x height) or point cloud accepted from an MRPT archive.
constexpr std::uint64_t kMaxPixels = std::uint64_t(1) << 25;
/// Largest image side: a corrupt 1 x 2^24 image is as suspicious as a huge square one.
constexpr std::uint64_t kMaxSide = std::uint64_t(1) << 15;
/// Largest compressed (JPEG) image read from an MRPT archive (a 32 M pixel image compresses to
/// far less).
constexpr std::uint32_t kMaxCompressedBytes = 256u << 20;
/// Largest single allocation through mrpt::aligned_malloc: a kMaxPixels image of doubles; what
/// rasm keeps in MRPT containers (poses, camera images' matrices, point maps of a few million
/// points) is far smaller. Below the fuzzers' -malloc_limit_mb (scripts/fuzz.sh).
constexpr std::size_t kMaxAlignedBytes = std::size_t(kMaxPixels) * sizeof(double);

namespace {
/// MRPT's definition of the interposed symbol (the next one after rasm_io's in lookup order).
template <typename Fn>
Fn mrptDefinition(const char* mangled) {
  void* f = dlsym(RTLD_NEXT, mangled);
  if (f == nullptr)
    THROW_EXCEPTION_FMT("rasm: MRPT's %s not found (dlsym: %s)", mangled, dlerror());
  return reinterpret_cast<Fn>(f);
}

void checkImageSize(const char* what, std::int64_t height, std::int64_t width) {
  if (height < 0 || width < 0 || std::uint64_t(height) > kMaxSide ||
      std::uint64_t(width) > kMaxSide || std::uint64_t(height) * std::uint64_t(width) > kMaxPixels)
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
  static const Fn mrpt =
      rasm::io::mrptDefinition<Fn>("_ZN4mrpt3obs23CObservation3DRangeScan18rangeImage_setSizeEii");
  rasm::io::checkImageSize("range image", H, W);
  mrpt(this, H, W);
}

void CObservation3DRangeScan::resizePoints3DVectors(const size_t nPoints) {
  using Fn = void (*)(CObservation3DRangeScan*, size_t);
  static const Fn mrpt = rasm::io::mrptDefinition<Fn>(
      "_ZN4mrpt3obs23CObservation3DRangeScan21resizePoints3DVectorsEm");
  if (nPoints > rasm::io::kMaxPixels)
    THROW_EXCEPTION_FMT(
        "serialized point cloud of %zu points (corrupt file?); rasm reads at most %llu", nPoints,
        static_cast<unsigned long long>(rasm::io::kMaxPixels));
  mrpt(this, nPoints);
}

}  // namespace mrpt::obs

namespace mrpt::img {

void CImage::resize(std::size_t width, std::size_t height, TImageChannels nChannels,
                    PixelDepth depth) {
  using Fn = void (*)(CImage*, std::size_t, std::size_t, TImageChannels, PixelDepth);
  static const Fn mrpt = rasm::io::mrptDefinition<Fn>(
      "_ZN4mrpt3img6CImage6resizeEmmNS0_14TImageChannelsENS0_10PixelDepthE");
  rasm::io::checkImageSize("image",
                           static_cast<std::int64_t>(std::min<std::size_t>(height, 1u << 31)),
                           static_cast<std::int64_t>(std::min<std::size_t>(width, 1u << 31)));
  mrpt(this, width, height, nChannels, depth);
}

namespace {
/// A JPEG of n bytes from the archive into img: n capped, the buffer grown as bytes arrive.
void readJpeg(mrpt::serialization::CArchive& in, std::uint32_t n, CImage& img) {
  if (n > rasm::io::kMaxCompressedBytes)
    THROW_EXCEPTION_FMT("serialized JPEG image of %u bytes (corrupt file?); rasm reads at most %u",
                        unsigned(n), unsigned(rasm::io::kMaxCompressedBytes));
  std::vector<std::uint8_t> buf;
  constexpr std::uint32_t kChunk = 1u << 20;
  for (std::uint32_t done = 0; done < n;) {
    const std::uint32_t m = std::min(kChunk, n - done);
    buf.resize(std::size_t(done) + m);
    if (in.ReadBuffer(buf.data() + done, m) != m) THROW_EXCEPTION("truncated JPEG image data");
    done += m;
  }
  // Decoded by OpenCV, not by CImage::loadFromStreamAsJPEG: MRPT's libjpeg source over a
  // CMemoryStream lets a corrupt marker length skip past the end of the buffer, and the next
  // read is a memcpy of negative size (ASan, fuzz_rawlog). OpenCV bounds its reads.
  if (buf.size() < 2 || buf[0] != 0xFF || buf[1] != 0xD8)
    THROW_EXCEPTION("corrupt JPEG image: no start-of-image marker (FF D8)");
  const cv::Mat decoded = cv::imdecode(buf, cv::IMREAD_UNCHANGED);
  if (decoded.empty() || decoded.depth() != CV_8U ||
      (decoded.channels() != 1 && decoded.channels() != 3))
    THROW_EXCEPTION_FMT("corrupt JPEG image (%zu bytes): OpenCV cannot decode it", buf.size());
  img = CImage(decoded, DEEP_COPY);
}

/// `bytes` raw bytes from the archive into img's pixels, which must hold at least that many.
void readRaw(mrpt::serialization::CArchive& in, std::size_t bytes, CImage& img) {
  cv::Mat& m = img.asCvMatRef();
  const std::size_t have = m.isContinuous() ? m.total() * m.elemSize() : 0;
  if (bytes > have)
    THROW_EXCEPTION_FMT(
        "serialized image of %zu bytes for a %d x %d image of %zu bytes (corrupt file?)", bytes,
        m.cols, m.rows, have);
  if (bytes > 0 && in.ReadBuffer(m.data, bytes) != bytes) THROW_EXCEPTION("truncated image data");
}

/// A serialized bool, read as its byte: anything but 0 or 1 is a corrupt file (loading such a
/// byte as a bool, as MRPT's `in >> flag` leaves it, is undefined behaviour).
bool readFlag(mrpt::serialization::CArchive& in, const char* name) {
  std::uint8_t byte = 0;
  in >> byte;
  if (byte > 1)
    THROW_EXCEPTION_FMT("corrupt CImage: flag %s holds the byte %u", name, unsigned(byte));
  return byte == 1;
}

/// Version 2-9, not externally stored: grey raw bytes or a colour JPEG / raw RGB image.
void readInMemory(mrpt::serialization::CArchive& in, std::uint8_t version, CImage& img) {
  std::uint8_t has_colour = 0;
  in >> has_colour;
  if (!has_colour) {
    std::int32_t width = 0, height = 0, origin = 0, image_size = 0;
    in >> width >> height >> origin >> image_size;
    PixelDepth depth = PixelDepth::D8U;
    if (version >= 9) {
      std::int32_t d = 0;
      in >> d;
      depth = PixelDepth(d);
    }
    img.resize(std::uint32_t(width), std::uint32_t(height), CH_GRAY, depth);
    const bool empty = width == 0 || height == 0;  // no pixels to reach (asCvMatRef throws)
    const std::uint32_t step = empty ? 0u : std::uint32_t(img.asCvMatRef().step[0]);
    ASSERT_EQUAL_(std::uint32_t(image_size), std::uint32_t(height) * step);
    bool zip = version != 2;
    if (version == 4 && image_size <= 16 * 1024) zip = false;
    if (version >= 5) zip = readFlag(in, "imageIsZIP");
    if (zip) THROW_EXCEPTION("ZIP image deserialization not supported anymore");  // as MRPT 2.5
    if (!empty) readRaw(in, std::uint32_t(image_size), img);
    return;
  }
  if (version >= 7) {
    std::int32_t width = 0, height = 0;
    in >> width >> height;
    if (width < 1 || height < 1) {
      if (width < 0 && height < 0) {  // v8: raw RGB, sizes negated
        img.resize(std::size_t(-std::int64_t(width)), std::size_t(-std::int64_t(height)), CH_RGB);
        const cv::Mat& m = img.asCvMatRef();
        readRaw(in, std::size_t(m.cols) * 3 * std::size_t(m.rows), img);
      } else {  // 0 x N or N x 0: nothing follows
        img.resize(std::uint32_t(width), std::uint32_t(height),
                   CH_RGB);  // bounded: corrupt sizes throw
      }
      return;
    }
  }
  std::uint32_t n = 0;
  in >> n;
  readJpeg(in, n, img);
}
}  // namespace

void CImage::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version) {
  clear();
  switch (version) {
    case 100:  // written by an MRPT built without OpenCV: an external file name at most
      m_imgIsExternalStorage = readFlag(in, "m_imgIsExternalStorage");
      if (m_imgIsExternalStorage) in >> m_externalFile;
      return;
    case 0: {
      std::uint32_t width = 0, height = 0, channels = 0, length = 0;
      std::uint8_t origin_top_left = 0;
      in >> width >> height >> channels >> origin_top_left >> length;
      resize(width, height, static_cast<TImageChannels>(channels));
      readRaw(in, length, *this);
      return;
    }
    case 1: {
      std::uint32_t n = 0;
      in >> n;
      readJpeg(in, n, *this);
      return;
    }
    case 2:
    case 3:
    case 4:
    case 5:
    case 6:
    case 7:
    case 8:
    case 9:
      m_imgIsExternalStorage = version >= 6 && readFlag(in, "m_imgIsExternalStorage");
      if (m_imgIsExternalStorage) {
        in >> m_externalFile;
        return;
      }
      readInMemory(in, version, *this);
      return;
    default:
      MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
  }
}

}  // namespace mrpt::img

namespace rasm::io {
namespace {
using AlignedAllocFn = void* (*)(std::size_t, std::size_t);
/// `bytes` from MRPT's allocator `mrpt`, bounded by kMaxAlignedBytes; a refusal is bad_alloc.
void* boundedAlignedAlloc(AlignedAllocFn mrpt, std::size_t bytes, std::size_t alignment) {
  if (bytes > kMaxAlignedBytes)
    THROW_EXCEPTION_FMT(
        "MRPT allocation of %zu bytes (corrupt file?); rasm allows at most %zu per block", bytes,
        kMaxAlignedBytes);
  void* p = mrpt(bytes, alignment);
  if (p == nullptr && bytes != 0) throw std::bad_alloc();
  return p;
}
}  // namespace
}  // namespace rasm::io

namespace mrpt {

void* aligned_malloc(std::size_t size, std::size_t alignment) {
  static const auto mrpt =
      rasm::io::mrptDefinition<rasm::io::AlignedAllocFn>("_ZN4mrpt14aligned_mallocEmm");
  return rasm::io::boundedAlignedAlloc(mrpt, size, alignment);
}

void* aligned_calloc(std::size_t bytes, std::size_t alignment) {
  static const auto mrpt =
      rasm::io::mrptDefinition<rasm::io::AlignedAllocFn>("_ZN4mrpt14aligned_callocEmm");
  return rasm::io::boundedAlignedAlloc(mrpt, bytes, alignment);
}

}  // namespace mrpt
