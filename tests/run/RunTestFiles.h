#pragma once
// What the pipeline's run tests share: a fresh temporary output folder per process, reading the
// files a run writes, and the quarter-VGA camera the simulated runs use to stay fast.

#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/serialization/CArchive.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/io/FrameSource.h"
#include "rasm/io/Trajectory.h"
#include "rasm/pipeline/RunFolder.h"
#include "rasm/run/RunConfig.h"
#include "rasm/surfel_map/CSurfelMap.h"
#include "rasm/surfel_map/MapExport.h"

namespace rasm::run::testing {

/// The simulated hand-held office rawlog of the repository: 20 frames at 320x240 with ground truth.
inline const std::string kSimRawlog =
    std::string(RASM_SOURCE_DIR) + "/rawlogs/sim_office_handheld_320x240.rawlog";

/// `bytes` as the whole content of `path` (binary).
inline void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

/// <temp>/rasm_test_<name>_<pid>, created empty (removed first if it exists; tests run as
/// parallel processes). Created because a run's --out folder is made only in an existing one:
/// tests write to tempDir(name) + "/out".
inline std::string tempDir(const std::string& name) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() /
                                  ("rasm_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

inline nlohmann::json readJson(const std::string& path) {
  std::ifstream f(path);
  return nlohmann::json::parse(f);
}

inline std::string readText(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// [camera] set to K instead of a preset.
inline void setRunCamera(RunConfig& cfg, const CameraIntrinsics& K) {
  cfg.set("camera", "preset", "");
  cfg.set("camera", "fx", std::to_string(K.fx));
  cfg.set("camera", "fy", std::to_string(K.fy));
  cfg.set("camera", "cx", std::to_string(K.cx));
  cfg.set("camera", "cy", std::to_string(K.cy));
  cfg.set("camera", "width", std::to_string(K.width));
  cfg.set("camera", "height", std::to_string(K.height));
}

/// The simulated camera at 320x240 (kinect_v1's intrinsics halved) instead of [camera] preset.
inline void setQuarterVgaCamera(RunConfig& cfg) {
  setRunCamera(cfg, CameraIntrinsics(262.5, 262.5, 159.5, 119.5, 320, 240));
}

/// The 640x480 Kinect's intrinsics / 4 (the scoreboard's --planners resolution).
inline CameraIntrinsics camera160x120() {
  return CameraIntrinsics(131.25, 131.25, 79.5, 59.5, 160, 120);
}

/// The names of the files in `dir`, sorted.
/// The entries of `dir`, sorted, without rasm's bookkeeping files of a run folder (its marker
/// and lock, RunFolder.h).
inline std::vector<std::string> filesIn(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name != pipeline::kRunMarkerName && name != pipeline::kRunLockName) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

/// Checks that a run folder holds only complete files of one run (docs/io.md "Runs that never
/// lie"): no temporary; report.json parses and, unless the run was aborted, lists exactly the
/// other files, all listed in the folder's marker; every file reads back whole (JSON, PLY, gzip
/// archives, PNG, TUM trajectories and the annotated rawlog with one pose / frame per frame done).
/// Returns report.json.
/// A binary little-endian PLY triangle mesh (mesh.ply): its header names vertices with x, y, z
/// and colours and faces of vertex-index lists, at least one of each, and the file holds exactly
/// the bytes the header announces (3 indices per face).
inline void expectTriangleMeshPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line, element;
  long long vertices = -1, faces = -1, vertex_bytes = 0;
  bool colours = false;
  std::getline(in, line);
  EXPECT_EQ(line, "ply");
  const auto size_of = [](const std::string& t) {
    return t == "double"               ? 8
           : t == "float"              ? 4
           : t == "uchar"              ? 1
           : t == "int" || t == "uint" ? 4
                                       : 0;
  };
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream w(line);
    std::string word, type, name;
    w >> word;
    if (word == "format") {
      w >> type;
      EXPECT_EQ(type, "binary_little_endian");
    } else if (word == "element") {
      w >> element;
      (element == "vertex" ? vertices : faces) = [&] {
        long long n = -1;
        w >> n;
        return n;
      }();
    } else if (word == "property" && element == "vertex") {
      w >> type >> name;
      vertex_bytes += size_of(type);
      colours = colours || name == "red";
    }
  }
  ASSERT_EQ(line, "end_header");
  EXPECT_GT(vertices, 0);
  EXPECT_GT(faces, 0);
  EXPECT_TRUE(colours);
  const long long body = vertices * vertex_bytes + faces * (1 + 3 * 4);
  EXPECT_EQ(
      static_cast<long long>(std::filesystem::file_size(path)) - static_cast<long long>(in.tellg()),
      body);
}

inline nlohmann::json expectCompleteRunFolder(const std::string& dir) {
  namespace fs = std::filesystem;
  const nlohmann::json rep = readJson(dir + "/report.json");
  const long long frames = rep["frames"].get<long long>();
  std::vector<std::string> others;
  for (const std::string& f : filesIn(dir)) {
    EXPECT_NE(fs::path(f).extension(), ".part") << dir << ": temporary left: " << f;
    if (f != "report.json") others.push_back(f);
  }
  if (rep["status"] != "aborted") {
    std::vector<std::string> listed = rep["files"].get<std::vector<std::string>>();
    std::sort(listed.begin(), listed.end());
    EXPECT_EQ(listed, others) << dir << ": report.json \"files\" and the folder differ";
  }
  // The run's marker lists every file in the folder, report.json included (RunFolder.h).
  if (fs::exists(dir + "/" + pipeline::kRunMarkerName)) {
    const auto marked =
        readJson(dir + "/" + pipeline::kRunMarkerName)["files"].get<std::vector<std::string>>();
    for (const std::string& f : filesIn(dir))
      EXPECT_NE(std::find(marked.begin(), marked.end(), f), marked.end())
          << dir << ": " << f << " is not in " << pipeline::kRunMarkerName;
  }
  for (const std::string& f : others) {
    const std::string p = dir + "/" + f;
    const std::string ext = fs::path(f).extension().string();
    SCOPED_TRACE(p);
    if (ext == ".json") {
      EXPECT_NO_THROW((void)readJson(p));
    } else if (ext == ".ply" && f.rfind("mesh", 0) == 0) {
      expectTriangleMeshPly(p);
    } else if (ext == ".ply") {
      maps::PlySurfels ply;
      EXPECT_NO_THROW(ply = maps::readSurfelPly(p));
    } else if (ext == ".3Dscene") {
      mrpt::opengl::COpenGLScene scene;
      EXPECT_TRUE(scene.loadFromFile(p));
    } else if (ext == ".surfelmap") {
      maps::CSurfelMap map;
      mrpt::io::CFileGZInputStream in(p);
      EXPECT_NO_THROW(mrpt::serialization::archiveFrom(in) >> map);
    } else if (ext == ".png") {
      EXPECT_FALSE(cv::imread(p, cv::IMREAD_UNCHANGED).empty());
    } else if (f == "trajectory.txt") {
      EXPECT_EQ((long long)io::readTumTrajectory(p).size(), frames);
    } else if (f == "frames.csv") {
      const std::string text = readText(p);
      EXPECT_EQ((long long)std::count(text.begin(), text.end(), '\n'), frames + 1);
    } else if (f == "annotated.rawlog") {
      auto src = io::openFrameSource(p);
      long long n = 0;
      while (src->next()) ++n;
      EXPECT_EQ(n, frames);
    }
  }
  return rep;
}

}  // namespace rasm::run::testing
