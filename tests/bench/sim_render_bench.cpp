// Benchmark of the simulated RGB-D sensor: frames per second rendering a world (colour, noisy
// depth, instance and class labels) along a loop of camera poses inside the room.
//   bench_sim_render [--world office] [--frames 300] [--threads 2] [--camera kinect_v1]
//                    [--noise on|off] [--labels on|off] [--packets on|off]
// Prints one JSON line: {"bench":"sim_render","fps":...,"ms_per_frame":...,"width":640,...}.
// OMP threads are set with omp_set_num_threads (the target machine is a 2-core laptop).
#include <omp.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "rasm/core/Error.h"
#include "rasm/sim/CameraPoses.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/RgbdSensor.h"
#include "rasm/sim/World.h"

int main(int argc, char** argv) {
  std::string world_name = "office", camera = "kinect_v1";
  int frames = 300, threads = 2;
  bool noise = true, labels = true, packets = true;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--world")
      world_name = v;
    else if (k == "--frames")
      frames = std::stoi(v);
    else if (k == "--threads")
      threads = std::stoi(v);
    else if (k == "--camera")
      camera = v;
    else if (k == "--noise")
      noise = v == "on";
    else if (k == "--labels")
      labels = v == "on";
    else if (k == "--packets")
      packets = v == "on";
    else {
      std::fprintf(stderr, "unknown option %s\n", k.c_str());
      return 2;
    }
  }
  try {
    omp_set_num_threads(threads);
    const rasm::sim::World world = rasm::sim::loadWorld(world_name);
    const rasm::sim::RayScene scene(world);
    rasm::sim::TSensorParams sp;
    sp.camera = camera;
    sp.noise = noise;
    sp.dropouts = noise;
    sp.labels = labels;
    sp.ray_packets = packets;
    const rasm::sim::RgbdSensor sensor(scene, sp);

    // Camera loop: an ellipse around the room centre at 1.4 m, looking outwards and slightly
    // down, so every frame sees walls, furniture and objects.
    const Eigen::AlignedBox3f b = world.bounds();
    const Eigen::Vector3d c = b.center().cast<double>();
    const double rx = 0.25 * (b.max().x() - b.min().x()), ry = 0.25 * (b.max().y() - b.min().y());
    auto pose = [&](int i) {
      const double a = 2.0 * M_PI * i / 120.0;
      const Eigen::Vector3d eye(c.x() + rx * std::cos(a), c.y() + ry * std::sin(a), 1.4);
      return rasm::sim::cameraPoseFromHeading(eye, a * 180.0 / M_PI + 60.0, -15.0);
    };
    rasm::RgbdFrame f;
    for (int i = 0; i < 10; ++i) sensor.render(pose(i), 1, std::size_t(i), f);  // warm-up
    // Process CPU time too: on a shared machine the wall-clock rate depends on the other load,
    // the CPU time per frame much less (with 1 thread it is the work per frame).
    auto cpuSeconds = [] {
      rusage u{};
      getrusage(RUSAGE_SELF, &u);
      return u.ru_utime.tv_sec + u.ru_stime.tv_sec +
             1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
    };
    const double cpu0 = cpuSeconds();
    const auto t0 = std::chrono::steady_clock::now();
    double checksum = 0, cast_ms = 0, shadow_ms = 0, model_ms = 0;
    for (int i = 0; i < frames; ++i) {
      sensor.render(pose(i), 1, std::size_t(i), f);
      checksum += f.depth_m(f.width() / 2, f.height() / 2);
      cast_ms += sensor.lastStageTimes().cast_ms;
      shadow_ms += sensor.lastStageTimes().shadow_ms;
      model_ms += sensor.lastStageTimes().depth_model_ms;
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu_ms = 1000.0 * (cpuSeconds() - cpu0) / frames;
    std::printf(
        "{\"bench\":\"sim_render\",\"fps\":%.1f,\"ms_per_frame\":%.3f,\"width\":%d,\"height\":%d,"
        "\"frames\":%d,"
        "\"threads\":%d,\"world\":\"%s\",\"triangles_objects\":%zu,\"noise\":%s,\"labels\":%s,"
        "\"packets\":%s,"
        "\"cpu_ms_per_frame\":%.3f,\"cpus_used\":%.2f,\"cast_ms\":%.3f,\"shadow_ms\":%.3f,\"depth_"
        "model_ms\":%.3f,\"checksum\":%.3f}\n",
        frames / s, 1000.0 * s / frames, f.width(), f.height(), frames, threads, world_name.c_str(),
        world.objects.size(), noise ? "true" : "false", labels ? "true" : "false",
        packets ? "true" : "false", cpu_ms, cpu_ms / (1000.0 * s / frames), cast_ms / frames,
        shadow_ms / frames, model_ms / frames, checksum);
    return 0;
  } catch (const rasm::InputError& e) {
    std::fprintf(stderr, "bench_sim_render: %s\n", e.what());
    return 3;
  }
}
