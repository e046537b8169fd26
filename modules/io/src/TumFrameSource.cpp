#include "rasm/io/TumFrameSource.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <regex>

#include "ImageCv.h"
#include "TextFiles.h"
#include "rasm/core/Error.h"
#include "rasm/io/TimestampAssociation.h"
#include "rasm/io/Trajectory.h"

namespace fs = std::filesystem;

namespace rasm::io {

namespace {

struct StampedFile {
  double t = 0;
  std::string file;
};

std::vector<StampedFile> readImageList(const std::string& path) {
  std::vector<StampedFile> out;
  for (const auto& l : detail::readFieldLines(path, "TUM image list")) {
    if (l.fields.size() < 2)
      throwInputError(detail::where(path, l.number), "expected 'timestamp filename'");
    out.push_back({detail::parseDouble(l.fields[0], path, l.number, "timestamp"), l.fields[1]});
  }
  return out;
}

}  // namespace

struct TumFrameSource::Impl {
  std::string folder;
  TumSourceOptions opt;
  CameraIntrinsics K;               // as delivered: positive fy, size of the images
  bool flip_rows = false;           // the given intrinsics had a negative fy
  bool intrinsics_guessed = false;  // no override and no fr1/fr2/fr3 in the folder name
  struct Pair {
    StampedFile rgb, depth;
  };
  std::vector<Pair> pairs;
  Trajectory groundtruth;
  Trajectory groundtruth_by_index;  ///< truth_cam_poses.txt: row k = frame k
  std::size_t next = 0;
};

bool TumFrameSource::looksLikeTumFolder(const std::string& folder) {
  return fs::is_regular_file(fs::path(folder) / "rgb.txt") &&
         fs::is_regular_file(fs::path(folder) / "depth.txt");
}

CameraIntrinsics TumFrameSource::intrinsicsForFolderName(const std::string& folder) {
  std::string name = fs::path(folder).lexically_normal().filename().string();
  if (name.empty()) name = fs::path(folder).lexically_normal().parent_path().filename().string();
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  // "rgbd_dataset_freiburg1_xyz", "fr1_xyz_first37", "freiburg3_cabinet", ...
  static const std::regex re("(^|[^a-z0-9])(freiburg|fr)([123])([^0-9]|$)");
  std::smatch m;
  if (std::regex_search(name, m, re)) return CameraIntrinsics::preset("tum_fr" + m[3].str());
  return CameraIntrinsics::preset("tum_default");
}

TumFrameSource::TumFrameSource(const std::string& folder, const TumSourceOptions& opt)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.folder = folder;
  m.opt = opt;
  if (!fs::is_directory(folder))
    throwInputError("TUM folder " + folder, "not found (or not a folder)");
  for (const char* f : {"rgb.txt", "depth.txt"})
    if (!fs::is_regular_file(fs::path(folder) / f))
      throwInputError(
          "TUM folder " + folder,
          std::string("missing ") + f +
              " (a TUM RGB-D sequence has rgb.txt, depth.txt, rgb/, depth/ and optionally "
              "groundtruth.txt)");
  if (!(opt.depth_factor > 0)) throwInputError("TUM folder " + folder, "depth_factor must be > 0");

  const auto rgb = readImageList((fs::path(folder) / "rgb.txt").string());
  const auto depth = readImageList((fs::path(folder) / "depth.txt").string());
  std::vector<double> trgb, tdepth;
  for (const auto& s : rgb) trgb.push_back(s.t);
  for (const auto& s : depth) tdepth.push_back(s.t);
  for (const auto& [i, j] : associateTimestamps(trgb, tdepth, opt.max_association_dt_s))
    m.pairs.push_back({rgb[i], depth[j]});
  if (m.pairs.empty())
    throwInputError("TUM folder " + folder,
                    "no rgb/depth pair within " + std::to_string(opt.max_association_dt_s) +
                        " s (rgb.txt " + std::to_string(rgb.size()) + " entries, depth.txt " +
                        std::to_string(depth.size()) + ")");

  const fs::path gt = fs::path(folder) / "groundtruth.txt";
  const fs::path by_index = fs::path(folder) / "truth_cam_poses.txt";
  if (fs::is_regular_file(gt)) {
    m.groundtruth = readTumTrajectory(gt.string());
  } else if (fs::is_regular_file(by_index)) {
    // Keyframe sets (e.g. the cuboid-SLAM fr3_cabinet keyframes): row k is the pose of frame k
    // (its own timestamp is the original one, the image lists count 0..n-1).
    m.groundtruth_by_index = readTumTrajectory(by_index.string());
    if (m.groundtruth_by_index.size() != m.pairs.size())
      throwInputError(by_index.string(),
                      std::to_string(m.groundtruth_by_index.size()) + " poses for " +
                          std::to_string(m.pairs.size()) +
                          " frames (expected one row per frame, row k = frame k)");
  }

  m.K = opt.intrinsics_override ? *opt.intrinsics_override : intrinsicsForFolderName(folder);
  m.intrinsics_guessed = !opt.intrinsics_override && m.K == CameraIntrinsics::preset("tum_default");
  if (m.K.fx <= 0 || m.K.fy == 0)
    throwInputError("TUM folder " + folder, "invalid intrinsics " + m.K.toString());
  // Image size from the first depth image (all frames must match it).
  const cv::Mat first =
      detail::readDepthU16((fs::path(folder) / m.pairs[0].depth.file).string(), "TUM depth image");
  m.K.width = first.cols;
  m.K.height = first.rows;
  m.flip_rows = m.K.fy < 0;
  if (m.flip_rows) {
    // v = cy + fy y/z with fy < 0  <=>  v' = (H-1) - v = (H-1-cy) + |fy| y/z (see header).
    m.K.fy = -m.K.fy;
    m.K.cy = (m.K.height - 1) - m.K.cy;
  }
}

TumFrameSource::~TumFrameSource() = default;

std::string TumFrameSource::describe() const {
  // The guess is said wherever the source is named: the run's first line, report.json "source".
  return "TUM folder " + impl_->folder +
         (impl_->intrinsics_guessed
              ? " (WARNING: intrinsics guessed, tum_default fx = fy = 525: no fr1/fr2/fr3 in the "
                "folder name; give the camera's in [camera])"
              : "");
}
long long TumFrameSource::sizeHint() const {
  return (long long)impl_->pairs.size();
}

const CameraIntrinsics& TumFrameSource::intrinsics() const {
  return impl_->K;
}
bool TumFrameSource::flipsRows() const {
  return impl_->flip_rows;
}

std::optional<RgbdFrame> TumFrameSource::next() {
  Impl& m = *impl_;
  if (m.next >= m.pairs.size()) return std::nullopt;
  const std::size_t idx = m.next++;
  const auto& p = m.pairs[idx];
  const std::string ctx =
      describe() + ", frame " + std::to_string(idx) + " (depth " + p.depth.file + ")";

  RgbdFrame f;
  f.index = idx;
  f.timestamp_s = p.depth.t;
  const std::string frame = "TUM frame " + std::to_string(idx) + ",";
  const cv::Mat raw = detail::readDepthU16((fs::path(m.folder) / p.depth.file).string(),
                                           frame + " depth image", cv::Size(m.K.width, m.K.height));
  detail::depthFromU16(raw, 1.0 / m.opt.depth_factor, f.depth_m);
  const cv::Mat bgr =
      detail::readColourImage((fs::path(m.folder) / p.rgb.file).string(), frame + " colour image");
  detail::colourFromMat(bgr, f.colour, ctx);

  f.intrinsics = m.K;
  if (m.flip_rows) {
    detail::flipRows(f.depth_m);
    detail::flipRows(f.colour);
  }
  if (!m.groundtruth_by_index.empty())
    f.gt_T_world_cam = m.groundtruth_by_index[idx].T_world_cam;
  else
    f.gt_T_world_cam = interpolatePose(m.groundtruth, f.timestamp_s, m.opt.max_groundtruth_dt_s);
  f.validate(ctx);
  return f;
}

}  // namespace rasm::io
