#pragma once
// Running the built `rasm` binary (or a script) from tests/app and reading what it printed.

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>

namespace rasm::app::testing {

struct Result {
  int status = -1;     ///< exit code; -1 when it did not exit normally
  std::string output;  ///< stdout (and stderr unless split)
};

/// Runs `command` through the shell; stderr joins stdout unless `keep_stderr_apart`.
inline Result shell(const std::string& command, bool keep_stderr_apart = false) {
  Result r;
  const std::string cmd = command + (keep_stderr_apart ? " 2>/dev/null" : " 2>&1");
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), int(buf.size()), p)) r.output += buf.data();
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

/// `rasm <args>`.
inline Result runRasm(const std::string& args, bool keep_stderr_apart = false) {
  return shell(std::string(RASM_BINARY) + " " + args, keep_stderr_apart);
}

inline std::string readFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// A fresh folder <temp>/rasm_app_<name>_<pid>.
inline std::string freshDir(const std::string& name) {
  const auto p = std::filesystem::temp_directory_path() /
                 ("rasm_app_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

/// `rasm run` arguments of a very short simulated run: the embedded default (the robot explores
/// the office) for `frames` frames with the 320x240 camera.
inline std::string shortRunArgs(int frames) {
  return "--set source.max_frames=" + std::to_string(frames) +
         " --set camera.preset= --set camera.fx=262.5 --set camera.fy=262.5 --set camera.cx=159.5"
         " --set camera.cy=119.5 --set camera.width=320 --set camera.height=240";
}

/// A two-frame TUM sequence in `seq_dir` (rgb/, depth/, rgb.txt, depth.txt): 8x6 images, flat
/// colour (10, 20, 30) and depth 5000 + k counts, frames 1/30 s apart from t = 1 s.
inline void writeTwoFrameTumSequence(const std::string& seq_dir) {
  std::filesystem::create_directories(seq_dir + "/rgb");
  std::filesystem::create_directories(seq_dir + "/depth");
  std::ofstream rgb(seq_dir + "/rgb.txt"), depth(seq_dir + "/depth.txt");
  for (int k = 0; k < 2; ++k) {
    const std::string name = std::to_string(k) + ".png";
    cv::imwrite(seq_dir + "/rgb/" + name, cv::Mat(6, 8, CV_8UC3, cv::Scalar(10, 20, 30)));
    cv::imwrite(seq_dir + "/depth/" + name, cv::Mat(6, 8, CV_16UC1, cv::Scalar(5000 + k)));
    rgb << 1.0 + k / 30.0 << " rgb/" << name << "\n";
    depth << 1.0 + k / 30.0 << " depth/" << name << "\n";
  }
}

}  // namespace rasm::app::testing
