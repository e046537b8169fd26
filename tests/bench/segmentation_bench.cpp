// Benchmark of section III in the Mapper (issue 16, 6): two Mappers over the same frames of a real
// RGB-D sequence, one with [segmentation] enabled and one without, processed alternately frame by
// frame (paired: both see the same machine load). Prints one JSON line with, over the frames after
// the first `--warmup`: the segmentation steps' mean and median ms (edges incl. the normal filter,
// components, propagation, merge), the whole frame's median ms and process-CPU ms per frame with
// and without segmentation, and their difference.
//   bench_segmentation --source DIR [--frames 150] [--warmup 10] [--set section.key=value ...]
// (--set: keys of the Mapper with the stage, e.g. segmentation.colour_edges=true)
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <mrpt/config/CConfigFileMemory.h>

#include "rasm/io/FrameSource.h"
#include "rasm/pipeline/Mapper.h"

using namespace rasm;

namespace {
double cpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return 1e3 * double(ts.tv_sec) + 1e-6 * double(ts.tv_nsec);
}
double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return v[v.size() / 2];
}
double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / double(v.size());
}
}  // namespace

int main(int argc, char** argv) {
  std::string source;
  int frames = 150, warmup = 10;
  std::vector<std::string> sets;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--source")
      source = argv[i + 1];
    else if (a == "--frames")
      frames = std::atoi(argv[i + 1]);
    else if (a == "--warmup")
      warmup = std::atoi(argv[i + 1]);
    else if (a == "--set")
      sets.push_back(argv[i + 1]);
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  if (source.empty()) {
    std::fprintf(
        stderr,
        "usage: bench_segmentation --source DIR [--frames 150] [--warmup 10] [--set s.k=v ...]\n");
    return 2;
  }
  try {
    auto src = io::openFrameSource(source, io::FrameSourceOptions());
    mrpt::config::CConfigFileMemory on_ini, off_ini;
    off_ini.write("segmentation", "enabled", "false");
    for (const std::string& kv : sets) {
      const auto dot = kv.find('.'), eq = kv.find('=');
      if (dot == std::string::npos || eq == std::string::npos || eq < dot) {
        std::fprintf(stderr, "bench_segmentation: --set %s: expected section.key=value\n",
                     kv.c_str());
        return 2;
      }
      on_ini.write(kv.substr(0, dot), kv.substr(dot + 1, eq - dot - 1), kv.substr(eq + 1));
    }
    pipeline::Mapper with(on_ini, "bench"), without(off_ini, "bench");
    const auto& timers = with.timerNames();
    std::map<std::string, std::vector<double>> ms;
    std::vector<double> total_on, total_off, cpu_on, cpu_off;
    int n = 0, tracked_on = 0, tracked_off = 0;
    while (n < frames) {
      std::optional<RgbdFrame> f = src->next();
      if (!f) break;
      double c0 = cpuMs();
      const pipeline::FrameResult a = with.processFrame(*f);
      double c1 = cpuMs();
      const pipeline::FrameResult b = without.processFrame(*f);
      double c2 = cpuMs();
      tracked_on += a.tracked;
      tracked_off += b.tracked;
      if (n++ < warmup) continue;
      for (std::size_t t = 0; t < timers.size(); ++t) ms[timers[t]].push_back(a.ms[t]);
      total_on.push_back(a.ms.back());
      total_off.push_back(b.ms.back());
      cpu_on.push_back(c1 - c0);
      cpu_off.push_back(c2 - c1);
    }
    std::printf(
        "{\"bench\":\"segmentation\",\"source\":\"%s\",\"frames\":%d,\"measured\":%zu,"
        "\"tracked_with\":%d,\"tracked_without\":%d,\"steps_ms\":{",
        source.c_str(), n, total_on.size(), tracked_on, tracked_off);
    bool first = true;
    for (const char* k :
         {"segmentation", "seg_edges", "seg_components", "seg_propagation", "seg_merge"}) {
      std::printf("%s\"%s\":{\"mean\":%.3f,\"median\":%.3f}", first ? "" : ",", k, mean(ms[k]),
                  median(ms[k]));
      first = false;
    }
    std::printf(
        "},\"frame_ms_median_with\":%.2f,\"frame_ms_median_without\":%.2f,"
        "\"cpu_ms_per_frame_with\":%.2f,\"cpu_ms_per_frame_without\":%.2f,\"cpu_ms_added\":%.2f}\n",
        median(total_on), median(total_off), mean(cpu_on), mean(cpu_off),
        mean(cpu_on) - mean(cpu_off));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_segmentation: %s\n", e.what());
    return 3;
  }
  return 0;
}
