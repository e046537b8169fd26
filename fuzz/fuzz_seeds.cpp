// Writes the seed corpora of the fuzz targets from the project's own files and tiny generated
// ones (no binaries are committed): fuzz_seeds <source dir> <corpus dir>; scripts/fuzz.sh runs it.
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "rasm/io/RawlogWriter.h"
#include "rasm/surfel_map/CSurfelMap.h"

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

/// <dir>/<name> = one selector byte (when >= 0) + body.
void seed(const fs::path& dir, const std::string& name, int selector, const std::string& body) {
  fs::create_directories(dir);
  std::ofstream f(dir / name, std::ios::binary);
  if (selector >= 0) f.put(char(selector));
  f << body;
}

rasm::RgbdFrame tinyFrame(int i) {
  rasm::RgbdFrame f;
  f.index = std::size_t(i);
  f.timestamp_s = 100.0 + 0.1 * i;
  f.intrinsics = rasm::CameraIntrinsics(10, 10, 3.5, 2.5, 8, 6);
  f.depth_m = rasm::Image<float>(8, 6, 1.0f + 0.1f * float(i));
  f.colour = rasm::Image<rasm::Bgr8>(8, 6);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x)
      f.colour(x, y) = rasm::Bgr8{std::uint8_t(x * 30), std::uint8_t(y * 40), 7};
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.1 * i, 0.0, 0.5);
  f.gt_T_world_cam = T;
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: fuzz_seeds <rasm source dir> <corpus dir>\n");
    return 2;
  }
  const fs::path src = argv[1], out = argv[2];
  const fs::path tmp = out / "tmp";
  fs::create_directories(tmp);

  // rawlog: two tiny rasm rawlogs (gzip level 0 and 1), MRPT's one-frame Kinect rawlog when
  // installed; images: a colour PNG, a colour JPEG and a 16-bit depth PNG.
  for (int level : {0, 1}) {
    const fs::path p = tmp / ("tiny" + std::to_string(level) + ".rawlog");
    rasm::io::RawlogWriterOptions o;
    o.compression_level = level;
    rasm::io::RawlogWriter w(p.string(), o);
    for (int i = 0; i < 2; ++i) w.write(tinyFrame(i));
    w.close();
    seed(out / "rawlog", "tiny" + std::to_string(level) + ".rawlog", 0, slurp(p));
  }
  const fs::path mrpt_rawlog = "/usr/share/mrpt/datasets/tests_rgbd.rawlog";
  if (fs::is_regular_file(mrpt_rawlog) && fs::file_size(mrpt_rawlog) < (256u << 10))
    seed(out / "rawlog", "tests_rgbd.rawlog", 0, slurp(mrpt_rawlog));
  const rasm::RgbdFrame f = tinyFrame(0);
  cv::Mat colour(6, 8, CV_8UC3), depth(6, 8, CV_16UC1, cv::Scalar(1234));
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x)
      colour.at<cv::Vec3b>(y, x) = {std::uint8_t(x * 30), std::uint8_t(y * 40), 7};
  for (const char* ext : {".png", ".jpg"}) {
    std::vector<unsigned char> b;
    cv::imencode(ext, colour, b);
    seed(out / "rawlog", std::string("colour") + ext, 1, std::string(b.begin(), b.end()));
  }
  {
    std::vector<unsigned char> b;
    cv::imencode(".png", depth, b);
    seed(out / "rawlog", "depth.png", 1, std::string(b.begin(), b.end()));
  }

  // surfelmap: a map of a few surfels with classes, view bins, a keyframe and class names.
  {
    rasm::maps::CSurfelMap::TCreationOptions co;
    co.n_classes = 3;
    co.view_bins_azimuth = 2;
    co.view_bins_elevation = 1;
    rasm::maps::CSurfelMap map(co);
    map.insertionOptions.fusion_keys = {{"max_depth_m", "3.5"}};
    for (int i = 0; i < 5; ++i) {
      rasm::maps::Surfel s;
      s.position = rasm::Vec3f(0.1f * float(i), 0.2f, 1.0f);
      s.radius = 0.01f;
      s.confidence = 3.0f + float(i);
      s.segment = std::uint32_t(1 + i % 2);
      s.segment_weight = 1.0f;
      s.t_init_s = s.t_last_s = 100.0 + i;
      map.append(s);
    }
    rasm::maps::Keyframe kf;
    kf.intrinsics = f.intrinsics;
    kf.points_world = {Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(0.1f, 0, 1)};
    kf.keypoints_px = {Eigen::Vector2f(1, 2), Eigen::Vector2f(3, 4)};
    kf.descriptors.assign(2 * rasm::maps::Keyframe::kDescriptorBytes, 0x5a);
    kf.thumb_width = 4;
    kf.thumb_height = 3;
    kf.thumbnail.assign(12, 9);
    map.keyframes().push_back(kf);
    map.classes() = {{"chair", "coco"}, {"mug", "coco"}, {"monitor", "zero_shot"}};
    const fs::path p = tmp / "tiny.surfelmap";
    {
      mrpt::io::CFileOutputStream fo(p.string());
      auto a = mrpt::serialization::archiveFrom(fo);
      a << map;
    }
    seed(out / "surfelmap", "tiny.surfelmap", -1, slurp(p));
    rasm::maps::CSurfelMap empty;
    const fs::path pe = tmp / "empty.surfelmap";
    {
      mrpt::io::CFileOutputStream fo(pe.string());
      auto a = mrpt::serialization::archiveFrom(fo);
      a << empty;
    }
    seed(out / "surfelmap", "empty.surfelmap", -1, slurp(pe));
  }

  // config: the shipped INIs, one with command-line overrides.
  for (const auto& e : fs::directory_iterator(src / "ini"))
    if (e.path().extension() == ".ini")
      seed(out / "config", e.path().filename().string(), -1, slurp(e.path()));
  seed(out / "config", "overrides.ini", -1,
       "[source]\ntype = tum\npath = x\n[camera]\npreset = tum_fr1\nfx = 517.3\nfy = 516.5\n"
       "cx = 318.6\ncy = 255.3\n[mapper]\nmax_depth_m = 3.5\n--set\nmapper.pyramid_levels=2\n"
       "source.drop_frames=3-5,9\nrobot.camera_pitch_deg=-12.5\noutput.dir=out\n");
  // The hostile INIs of the input probe (docs/io.md): a BOM, a key before any section, a key twice,
  // an unterminated section header, an absurd focal length.
  seed(out / "config", "bom.ini", -1, "\xEF\xBB\xBF[source]\ntype = sim\n");
  seed(out / "config", "before_section.ini", -1, "max_depth_m = 3\n[mapper]\n");
  seed(out / "config", "twice.ini", -1,
       "[mapper]\nmax_depth_m = 3\n[source]\n[mapper]\nmax_depth_m = 4\n");
  seed(out / "config", "unterminated.ini", -1, "[source\ntype = sim\n");
  seed(out / "config", "huge_fx.ini", -1,
       "[camera]\nfx = 1e30\nfy = 1e30\ncx = 319.5\ncy = 239.5\nwidth = 640\nheight = 480\n");

  // world: the shipped worlds (selector 0) and trajectory specs (selector 1).
  for (const char* kind : {"worlds", "trajectories"})
    for (const auto& e : fs::directory_iterator(src / "modules/sim" / kind))
      if (e.path().extension() == ".yaml")
        seed(out / "world", std::string(kind) + "_" + e.path().filename().string(),
             std::string(kind) == "worlds" ? 0 : 1, slurp(e.path()));
  // The hostile numbers and keys of the input probe.
  const std::string cup = "objects:\n  - {id: 1, class: cup, primitive: box, size: [1, 1, 1], ";
  seed(out / "world", "nan_position.yaml", 0, cup + "position: [0, .nan, 0]}\n");
  seed(out / "world", "huge_size.yaml", 0,
       "objects:\n  - {id: 1, class: cup, primitive: box, size: [1e30, 1, 1], position: [0, 0, "
       "0]}\n");
  seed(out / "world", "repeated_key.yaml", 0,
       "world: a\nworld: b\n" + cup + "position: [0, 0, 0]}\n");
  const std::string kf =
      "type: handheld\nkeyframes:\n  - {t: 0, position: [0, 0, 1], look_at: [1, 0, 1]}\n";
  seed(out / "world", "nan_keyframe.yaml", 1,
       kf + "  - {t: 1, position: [.nan, 2, 1.5], look_at: [1, 0, 1]}\n");
  seed(out / "world", "inf_look_at.yaml", 1,
       kf + "  - {t: 1, position: [0, 0, 1], look_at: [.inf, 1, 1]}\n");

  // trajectory: TUM lines (0), a 7-Scenes pose (1) and intrinsics (2), a TUM groundtruth.txt (3).
  {
    std::ostringstream tum;
    tum << "# timestamp tx ty tz qx qy qz qw\n";
    for (int i = 0; i < 12; ++i)
      tum << 1.0 + 0.05 * i << " " << 0.01 * i << " " << -0.02 * i << " 1.5 0 " << 0.01 * i << " 0 "
          << std::sqrt(1 - 0.0001 * i * i) << "\n";
    seed(out / "trajectory", "tum.txt", 0, tum.str());
    seed(out / "trajectory", "groundtruth.txt", 3, tum.str());
    seed(out / "trajectory", "pose.txt", 1,
         "1.0e+00 0.0e+00 0.0e+00 1.2e-01\n0.0e+00 0.0e+00 -1.0e+00 -3.0e-01\n"
         "0.0e+00 1.0e+00 0.0e+00 1.5e+00\n0.0e+00 0.0e+00 0.0e+00 1.0e+00\n");
    seed(out / "trajectory", "intrinsics.txt", 2, "10 0 3.5\n0 10 2.5\n0 0 1\n");
  }
  fs::remove_all(tmp);
  std::printf("seed corpora in %s\n", out.c_str());
  return 0;
}
