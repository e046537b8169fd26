#include "rasm/io/SevenScenesFrameSource.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <regex>

#include "ColourRegistration.h"
#include "ImageCv.h"
#include "TextFiles.h"
#include "rasm/core/Error.h"
#include "rasm/core/SE3.h"

namespace fs = std::filesystem;

namespace rasm::io {

namespace {

const std::regex& depthFileRegex() {
  static const std::regex re("frame-([0-9]+)\\.depth\\.png");
  return re;
}

std::string frameStem(const std::string& digits) {
  return "frame-" + digits;
}

/// camera-intrinsics.txt: a 3x3 K (row-major, whitespace separated).
CameraIntrinsics readIntrinsicsFile(const std::string& path) {
  std::vector<double> v;
  for (const auto& l : detail::readFieldLines(path, "7-Scenes intrinsics"))
    for (const auto& f : l.fields) v.push_back(detail::parseDouble(f, path, l.number, "K entry"));
  if (v.size() != 9)
    throwInputError(path,
                    "expected a 3x3 camera matrix (9 numbers), got " + std::to_string(v.size()));
  CameraIntrinsics K;
  K.fx = v[0];
  K.cx = v[2];
  K.fy = v[4];
  K.cy = v[5];
  if (!(K.fx > 0 && K.fy > 0)) throwInputError(path, "focal lengths must be > 0: " + K.toString());
  return K;
}

/// frame-NNNNNN.pose.txt: 4x4 T_world_cam, finite and rigid. A missing file, a non-finite entry
/// (NaN, Inf) or a matrix that is not a rigid transform is an error naming the file (and line):
/// the TUM reader treats its ground truth the same way.
Eigen::Isometry3d readPoseFile(const std::string& path, const std::string& ctx) {
  if (!fs::is_regular_file(path))
    throwInputError(ctx, "missing " + path +
                             " (the sequence's first frame has a pose file, so every frame needs "
                             "one: a 4x4 camera-to-world matrix)");
  std::vector<double> v;
  for (const auto& l : detail::readFieldLines(path, "7-Scenes pose"))
    for (const auto& f : l.fields)
      v.push_back(detail::parseDouble(f, path, l.number, "pose entry"));
  if (v.size() != 16)
    throwInputError(path, "expected a 4x4 matrix (16 numbers), got " + std::to_string(v.size()));
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) M(r, c) = v[r * 4 + c];
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  const double ortho = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (ortho > 1e-3 || R.determinant() < 0 ||
      (M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6)
    throwInputError(path, "not a rigid transform (rotation not orthonormal: |R^T R - I| = " +
                              std::to_string(ortho) + ", det " + std::to_string(R.determinant()) +
                              ", or last row not 0 0 0 1); expected a 4x4 camera-to-world matrix");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.matrix() = M;
  return orthonormalize(T);
}

}  // namespace

SevenScenesSourceOptions::ColourRegistration
SevenScenesSourceOptions::approximateKinectV1Calibration() {
  ColourRegistration r;
  r.K_colour = CameraIntrinsics(525.0, 525.0, 320.0, 240.0, 640, 480);
  // Depth (IR) camera -> colour camera, metres; LIRIS Kinect calibration
  // (projet.liris.cnrs.fr/voir/activities-dataset/kinect-calibration.html).
  Eigen::Matrix4d M;
  M << 9.9996518012567637e-01, 2.6765126468950343e-03, -7.9041012313000904e-03,
      -2.5558943178152542e-02, -2.7409311281316700e-03, 9.9996302803027592e-01,
      -8.1504520778013286e-03, 1.0109636268061706e-04, 7.8819942130445332e-03,
      8.1718328771890631e-03, 9.9993554558014031e-01, 2.0318321729487039e-03, 0, 0, 0, 1;
  r.T_colour_depth.matrix() = M;
  r.T_colour_depth = orthonormalize(r.T_colour_depth);
  return r;
}

struct SevenScenesFrameSource::Impl {
  std::string folder;
  SevenScenesSourceOptions opt;
  CameraIntrinsics K;
  struct Entry {
    long index;
    std::string stem;  // "frame-000123"
  };
  std::vector<Entry> frames;
  std::string colour_ext;  // ".color.png" or ".color.jpg"
  bool has_poses = false;  // the first frame has a pose.txt: then every frame must
  std::size_t next = 0;
};

bool SevenScenesFrameSource::looksLikeSevenScenesFolder(const std::string& folder) {
  if (!fs::is_directory(folder)) return false;
  if (fs::is_regular_file(fs::path(folder) / "frame-000000.depth.png")) return true;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder, ec))
    if (std::regex_match(e.path().filename().string(), depthFileRegex())) return true;
  return false;
}

SevenScenesFrameSource::SevenScenesFrameSource(const std::string& folder,
                                               const SevenScenesSourceOptions& opt)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.folder = folder;
  m.opt = opt;
  const std::string what = "7-Scenes folder " + folder;
  if (!fs::is_directory(folder)) throwInputError(what, "not found (or not a folder)");
  if (!(opt.frame_rate_hz > 0)) throwInputError(what, "frame_rate_hz must be > 0");

  bool has_seq_subfolders = false;
  for (const auto& e : fs::directory_iterator(folder)) {
    const std::string name = e.path().filename().string();
    std::smatch sm;
    if (std::regex_match(name, sm, depthFileRegex()))
      m.frames.push_back({std::stol(sm[1].str()), frameStem(sm[1].str())});
    if (e.is_directory() && name.rfind("seq-", 0) == 0) has_seq_subfolders = true;
  }
  if (m.frames.empty())
    throwInputError(
        what,
        std::string("missing frame-000000.depth.png (a 7-Scenes sequence folder holds "
                    "frame-NNNNNN.color.png|jpg, .depth.png and .pose.txt)") +
            (has_seq_subfolders ? "; this looks like a scene folder: pass one of its seq-NN folders"
                                : ""));
  std::sort(m.frames.begin(), m.frames.end(),
            [](const auto& a, const auto& b) { return a.index < b.index; });

  const fs::path first = fs::path(folder) / m.frames[0].stem;
  for (const char* ext : {".color.png", ".color.jpg"})
    if (fs::is_regular_file(first.string() + ext)) m.colour_ext = ext;
  if (m.colour_ext.empty())
    throwInputError(what, "missing " + m.frames[0].stem + ".color.png (or .color.jpg)");

  m.has_poses = fs::exists(first.string() + ".pose.txt");
  const fs::path kfile = fs::path(folder) / "camera-intrinsics.txt";
  if (opt.intrinsics_override)
    m.K = *opt.intrinsics_override;
  else if (fs::is_regular_file(kfile))
    m.K = readIntrinsicsFile(kfile.string());
  else
    m.K = CameraIntrinsics::preset("7scenes");
  const cv::Mat d0 = detail::readDepthU16(first.string() + ".depth.png", "7-Scenes depth image");
  m.K.width = d0.cols;
  m.K.height = d0.rows;
  if (!m.K.valid())
    throwInputError(what, "invalid intrinsics " + m.K.toString() + ": " + m.K.problem());
}

SevenScenesFrameSource::~SevenScenesFrameSource() = default;

std::string SevenScenesFrameSource::describe() const {
  return "7-Scenes folder " + impl_->folder;
}
long long SevenScenesFrameSource::sizeHint() const {
  return (long long)impl_->frames.size();
}
const CameraIntrinsics& SevenScenesFrameSource::intrinsics() const {
  return impl_->K;
}

std::optional<RgbdFrame> SevenScenesFrameSource::next() {
  Impl& m = *impl_;
  if (m.next >= m.frames.size()) return std::nullopt;
  const std::size_t i = m.next++;
  const auto& e = m.frames[i];
  const std::string base = (fs::path(m.folder) / e.stem).string();
  const std::string ctx = describe() + ", frame " + std::to_string(i) + " (" + e.stem + ")";

  RgbdFrame f;
  f.index = i;
  f.timestamp_s = double(e.index) / m.opt.frame_rate_hz;
  f.intrinsics = m.K;
  // Millimetres; 0 and 65535 mark missing measurements.
  const std::string frame = "7-Scenes frame " + std::to_string(i) + ",";
  detail::depthFromU16(detail::readDepthU16(base + ".depth.png", frame + " depth image",
                                            cv::Size(m.K.width, m.K.height)),
                       1e-3, f.depth_m, 65535);
  const cv::Mat bgr = detail::readColourImage(base + m.colour_ext, frame + " colour image");
  if (m.opt.register_colour) {
    Image<Bgr8> raw;
    detail::colourFromMat(bgr, raw, ctx);
    const auto cal = m.opt.colour_registration
                         ? *m.opt.colour_registration
                         : SevenScenesSourceOptions::approximateKinectV1Calibration();
    CameraIntrinsics Kc = cal.K_colour;
    Kc.width = raw.width();
    Kc.height = raw.height();
    detail::registerColourToDepthFilled(f.depth_m, f.intrinsics, raw, Kc, cal.T_colour_depth,
                                        f.colour);
  } else {
    detail::colourFromMat(bgr, f.colour, ctx);
  }
  if (m.has_poses) f.gt_T_world_cam = readPoseFile(base + ".pose.txt", ctx);
  f.validate(ctx);
  return f;
}

}  // namespace rasm::io
