// Relocalisation keyframes stored with CSurfelMap: every field round-trips through the map's
// serialization (version 1), version-0 files (no keyframes) still load, copies carry the
// keyframes, clear() drops them, and corrupt keyframe records fail with a message.

#include "rasm/surfel_map/Keyframe.h"

#include <gtest/gtest.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "rasm/core/Error.h"
#include "rasm/surfel_map/CSurfelMap.h"

using namespace rasm;
using namespace rasm::maps;

namespace {

Keyframe randomKeyframe(std::mt19937& rng, std::size_t n_features, int thumb_w, int thumb_h) {
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  Keyframe kf;
  kf.frame_index = rng();
  kf.timestamp_s = 1341841278.8427 + 0.01 * double(rng() % 1000);
  kf.T_world_cam = Eigen::Translation3d(u(rng), u(rng), u(rng)) *
                   Eigen::AngleAxisd(u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized());
  kf.intrinsics = CameraIntrinsics(535.4, 539.2, 320.1, 247.6, 640, 480);
  for (std::size_t i = 0; i < n_features; ++i) {
    kf.points_world.emplace_back(u(rng), u(rng), u(rng));
    kf.keypoints_px.emplace_back(100.0f + 50.0f * u(rng), 100.0f + 30.0f * u(rng));
    for (int b = 0; b < Keyframe::kDescriptorBytes; ++b)
      kf.descriptors.push_back(std::uint8_t(rng()));
  }
  kf.thumb_width = thumb_w;
  kf.thumb_height = thumb_h;
  for (int i = 0; i < thumb_w * thumb_h; ++i) kf.thumbnail.push_back(std::uint8_t(rng()));
  return kf;
}

void expectSame(const Keyframe& a, const Keyframe& b) {
  EXPECT_EQ(a.frame_index, b.frame_index);
  EXPECT_EQ(a.timestamp_s, b.timestamp_s);
  EXPECT_EQ(a.T_world_cam.matrix(), b.T_world_cam.matrix());  // bit-exact
  EXPECT_EQ(a.intrinsics, b.intrinsics);
  EXPECT_EQ(a.points_world, b.points_world);
  EXPECT_EQ(a.keypoints_px, b.keypoints_px);
  EXPECT_EQ(a.descriptors, b.descriptors);
  EXPECT_EQ(a.thumb_width, b.thumb_width);
  EXPECT_EQ(a.thumb_height, b.thumb_height);
  EXPECT_EQ(a.thumbnail, b.thumbnail);
}

std::vector<std::uint8_t> serialize(const CSurfelMap& map) {
  mrpt::io::CMemoryStream buf;
  auto out = mrpt::serialization::archiveFrom(buf);
  out << map;
  const auto* p = static_cast<const std::uint8_t*>(buf.getRawBufferData());
  return std::vector<std::uint8_t>(p, p + buf.getTotalBytesCount());
}

CSurfelMap::Ptr deserialize(const std::vector<std::uint8_t>& bytes) {
  mrpt::io::CMemoryStream buf;
  buf.assignMemoryNotOwn(bytes.data(), bytes.size());
  auto in = mrpt::serialization::archiveFrom(buf);
  mrpt::serialization::CSerializable::Ptr obj;
  in >> obj;
  return std::dynamic_pointer_cast<CSurfelMap>(obj);
}

/// Byte offset of the class version in a serialized object: MRPT writes (name length | 0x80),
/// the class name, then the version.
std::size_t versionOffset(const std::vector<std::uint8_t>& bytes) {
  const std::string name = "rasm::maps::CSurfelMap";
  EXPECT_EQ(bytes.at(0), std::uint8_t(name.size() | 0x80));
  EXPECT_EQ(std::string(bytes.begin() + 1, bytes.begin() + 1 + std::ptrdiff_t(name.size())), name);
  return 1 + name.size();
}

}  // namespace

TEST(Keyframe, RoundTripThroughMapSerialization) {
  std::mt19937 rng(7);
  CSurfelMap map;
  Surfel s;
  s.position = Vec3f(1, 2, 3);
  s.normal = Vec3f(0, 0, 1);
  s.basis = Vec3f(1, 0, 0);
  s.radius = 0.01f;
  s.confidence = 4;
  map.append(s);
  map.keyframes().push_back(randomKeyframe(rng, 500, 80, 60));
  map.keyframes().push_back(randomKeyframe(rng, 0, 0, 0));  // no features, no thumbnail
  map.keyframes().push_back(randomKeyframe(rng, 37, 20, 15));
  for (const Keyframe& kf : map.keyframes()) ASSERT_TRUE(kf.consistent());
  // The class list (version 3) travels with the map.
  map.classes() = {{"person", "coco"}, {"cabinet", "zero_shot"}};

  const std::vector<std::uint8_t> bytes = serialize(map);
  EXPECT_EQ(bytes.at(versionOffset(bytes)), 3);
  const CSurfelMap::Ptr copy = deserialize(bytes);
  ASSERT_TRUE(copy);
  EXPECT_EQ(copy->size(), 1);
  ASSERT_EQ(copy->keyframes().size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) expectSame(map.keyframes()[k], copy->keyframes()[k]);
  EXPECT_EQ(copy->classes(), map.classes());
}

TEST(Keyframe, MapWithoutSurfelsKeepsItsKeyframes) {
  std::mt19937 rng(8);
  CSurfelMap map;
  map.keyframes().push_back(randomKeyframe(rng, 10, 8, 6));
  const CSurfelMap::Ptr copy = deserialize(serialize(map));
  ASSERT_TRUE(copy);
  EXPECT_EQ(copy->size(), 0);
  ASSERT_EQ(copy->keyframes().size(), 1u);
  expectSame(map.keyframes()[0], copy->keyframes()[0]);
}

TEST(Keyframe, Version0MapsStillLoad) {
  // A version-0 stream is a version-1 stream of a map without keyframes minus the keyframe
  // count (uint32 0) before MRPT's one-byte end flag, with version byte 0. Without classes a
  // version-2 stream stores the surfels as version 1 did (only the class evidence changed).
  CSurfelMap::TCreationOptions no_classes;
  no_classes.n_classes = 0;
  CSurfelMap map(no_classes);
  Surfel s;
  s.position = Vec3f(0.5f, -1, 2);
  s.normal = Vec3f(0, 1, 0);
  s.basis = Vec3f(1, 0, 0);
  s.radius = 0.02f;
  s.confidence = 12;
  s.stable = true;
  map.append(s);
  std::vector<std::uint8_t> bytes = serialize(map);
  const std::size_t v = versionOffset(bytes);
  ASSERT_EQ(bytes.at(v), 3);
  // The stream ends with the keyframe count (version 1) and the class count (version 3), both 0
  // here, then MRPT's end flag: dropping both makes a version-0 stream.
  const std::size_t count_at = bytes.size() - 1 - 8;
  for (std::size_t i = count_at; i < count_at + 8; ++i) ASSERT_EQ(bytes[i], 0) << "counts";
  bytes[v] = 0;
  bytes.erase(bytes.begin() + std::ptrdiff_t(count_at),
              bytes.begin() + std::ptrdiff_t(count_at + 8));

  const CSurfelMap::Ptr old = deserialize(bytes);
  ASSERT_TRUE(old);
  EXPECT_EQ(old->size(), 1);
  EXPECT_EQ(old->store().get(0).position, s.position);
  EXPECT_TRUE(old->keyframes().empty());
}

TEST(Keyframe, CopiedWithTheMapAndDroppedByClear) {
  std::mt19937 rng(9);
  CSurfelMap map;
  map.keyframes().push_back(randomKeyframe(rng, 5, 0, 0));
  const CSurfelMap copy(map);
  ASSERT_EQ(copy.keyframes().size(), 1u);
  expectSame(copy.keyframes()[0], map.keyframes()[0]);
  CSurfelMap assigned;
  assigned = map;
  EXPECT_EQ(assigned.keyframes().size(), 1u);
  map.resetLayout(map.creationOptions());  // layout concerns surfels only
  EXPECT_EQ(map.keyframes().size(), 1u);
  map.clear();
  EXPECT_TRUE(map.keyframes().empty());
}

TEST(Keyframe, CorruptRecordIsAnInputError) {
  std::mt19937 rng(10);
  CSurfelMap map;
  Keyframe kf = randomKeyframe(rng, 0, 0, 0);
  kf.timestamp_s = 4242.125;  // located in the stream below
  map.keyframes().push_back(kf);
  std::vector<std::uint8_t> bytes = serialize(map);
  // Record: frame index (8), timestamp (8), 3x4 pose (96), fx fy cx cy (32), width height (8),
  // feature count (4), thumbnail size (8).
  std::size_t ts_at = 0;
  for (std::size_t i = 0; i + 8 <= bytes.size(); ++i) {
    double d;
    std::memcpy(&d, bytes.data() + i, 8);
    if (d == 4242.125) ts_at = i;
  }
  ASSERT_GT(ts_at, 0u);
  const std::size_t n_at = ts_at + 8 + 96 + 32 + 8;
  ASSERT_EQ(n_at + 4 + 8 + 4 + 1, bytes.size());  // then the class count (0) and the end flag
  const std::uint32_t huge = 0xFFFFFFFFu;
  std::memcpy(bytes.data() + n_at, &huge, 4);
  try {
    deserialize(bytes);
    FAIL() << "no error";
  } catch (const std::exception& e) {  // InputError, possibly wrapped by MRPT's archive
    EXPECT_NE(std::string(e.what()).find("CSurfelMap keyframe 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("features (corrupt file?)"), std::string::npos)
        << e.what();
  }

  // Inconsistent arrays refuse to serialize.
  map.keyframes()[0].points_world.emplace_back(0, 0, 0);
  EXPECT_THROW(serialize(map), std::exception);
}
