#include "rasm/models/ProceduralModels.h"
#include "rasm/core/Angles.h"

#include <cmath>
#include <filesystem>
#include <functional>
#include <map>

#include "rasm/core/Error.h"

namespace rasm::models {
namespace {

using V2 = Eigen::Vector2f;
using V3 = Eigen::Vector3f;

Eigen::Affine3f at(const V3& t, float yaw_deg = 0.f, float pitch_deg = 0.f, float roll_deg = 0.f) {
  Eigen::Affine3f T = Eigen::Affine3f::Identity();
  T.translate(t);
  T.rotate(Eigen::AngleAxisf(yaw_deg * kRadPerDegF, V3::UnitZ()) *
           Eigen::AngleAxisf(pitch_deg * kRadPerDegF, V3::UnitY()) *
           Eigen::AngleAxisf(roll_deg * kRadPerDegF, V3::UnitX()));
  return T;
}

void addBox(TriangleMesh& m, const V3& centre, const V3& size, float yaw_deg = 0.f,
            float pitch_deg = 0.f, float roll_deg = 0.f) {
  m.append(makeBox(size), at(centre, yaw_deg, pitch_deg, roll_deg));
}

/// Tube of radius r along a circular arc: centre c, arc in the plane spanned by unit vectors
/// (e1, e2), radius R, angles a0..a1 (rad). Ends are open (they sit inside other parts).
void addArcTube(TriangleMesh& m, const V3& c, const V3& e1, const V3& e2, float R, float a0,
                float a1, float r, int steps, int sides) {
  const V3 normal = e1.cross(e2);
  const int base = int(m.vertices.size());
  for (int i = 0; i <= steps; ++i) {
    const float a = a0 + (a1 - a0) * float(i) / float(steps);
    const V3 radial = std::cos(a) * e1 + std::sin(a) * e2;
    const V3 p = c + R * radial;
    for (int k = 0; k < sides; ++k) {
      const float b = float(2.0 * M_PI * k / sides);
      m.vertices.push_back(p + r * (std::cos(b) * radial + std::sin(b) * normal));
    }
  }
  for (int i = 0; i < steps; ++i)
    for (int k = 0; k < sides; ++k) {
      const int a = base + i * sides + k, b = base + i * sides + (k + 1) % sides;
      const int c2 = b + sides, d = a + sides;
      m.triangles.emplace_back(a, b, c2);
      m.triangles.emplace_back(a, c2, d);
    }
}

TriangleMesh mug() {
  // 8 cm diameter, 9.5 cm tall, 4 mm wall, hollow, handle on +x.
  TriangleMesh m = makeLathe({{0.f, 0.f},
                              {0.040f, 0.f},
                              {0.041f, 0.095f},
                              {0.037f, 0.095f},
                              {0.036f, 0.008f},
                              {0.f, 0.008f}},
                             24);
  addArcTube(m, V3(0.040f, 0.f, 0.050f), V3::UnitX(), V3::UnitZ(), 0.026f, -80 * kRadPerDegF,
             80 * kRadPerDegF, 0.0065f, 10, 6);
  return m;
}

TriangleMesh bottle() {
  // 0.5 l water bottle: 6.6 cm diameter, 24.5 cm tall with cap.
  return makeLathe({{0.f, 0.f},
                    {0.033f, 0.f},
                    {0.033f, 0.150f},
                    {0.030f, 0.170f},
                    {0.020f, 0.190f},
                    {0.013f, 0.205f},
                    {0.013f, 0.222f},
                    {0.015f, 0.222f},
                    {0.015f, 0.245f},
                    {0.f, 0.245f}},
                   20);
}

TriangleMesh chair() {
  TriangleMesh m;
  addBox(m, {0.f, 0.f, 0.450f}, {0.45f, 0.45f, 0.05f});  // seat, top at 0.475
  for (float sx : {-1.f, 1.f})
    for (float sy : {-1.f, 1.f})
      addBox(m, {sx * 0.19f, sy * 0.19f, 0.2125f}, {0.035f, 0.035f, 0.425f});
  addBox(m, {-0.205f, 0.f, 0.72f}, {0.04f, 0.45f, 0.44f}, 0.f,
         -8.f);  // backrest, slightly reclined
  return m;
}

TriangleMesh monitor() {
  TriangleMesh m;
  addBox(m, {0.f, 0.f, 0.0075f}, {0.18f, 0.24f, 0.015f});    // foot
  addBox(m, {-0.04f, 0.f, 0.12f}, {0.03f, 0.06f, 0.21f});    // neck
  addBox(m, {0.f, 0.f, 0.295f}, {0.035f, 0.56f, 0.34f});     // panel, screen facing +x
  addBox(m, {0.019f, 0.f, 0.300f}, {0.004f, 0.52f, 0.30f});  // screen, slightly proud of the bezel
  return m;
}

TriangleMesh keyboard() {
  TriangleMesh m;
  addBox(m, {0.f, 0.f, 0.010f}, {0.15f, 0.44f, 0.020f});  // long axis y, keys face up, user at +x
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 12; ++k)
      addBox(m, {-0.048f + 0.024f * float(r), -0.187f + 0.034f * float(k), 0.024f},
             {0.019f, 0.028f, 0.008f});
  addBox(m, {0.050f, 0.f, 0.024f}, {0.019f, 0.16f, 0.008f});  // space bar, nearest the user
  return m;
}

TriangleMesh wallClock() {
  // 30 cm wall clock; origin at the back centre (on the wall), face towards +x.
  TriangleMesh m;
  const TriangleMesh body = makeLathe({{0.f, 0.f},
                                       {0.150f, 0.f},
                                       {0.150f, 0.040f},
                                       {0.138f, 0.040f},
                                       {0.136f, 0.030f},
                                       {0.f, 0.030f}},
                                      32);
  m.append(body, at(V3::Zero(), 0.f, 90.f));                   // lathe axis z -> x
  addBox(m, {0.033f, 0.f, 0.035f}, {0.004f, 0.012f, 0.075f});  // hour hand, up
  addBox(m, {0.036f, 0.045f, -0.026f}, {0.004f, 0.009f, 0.105f}, 0.f, 0.f, 120.f);  // minute hand
  return m;
}

TriangleMesh conferencePhone() {
  // Three-lobed speakerphone (Polycom SoundStation style), ~28 cm across, 5 cm tall.
  std::vector<V2> outline;
  for (int i = 0; i < 48; ++i) {
    const float a = float(2.0 * M_PI * i / 48);
    const float r = 0.115f + 0.03f * std::cos(3.f * a);
    outline.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  TriangleMesh m = makeExtrusion(outline, 0.f, 0.028f);
  m.append(makeLathe(
      {{0.f, 0.028f}, {0.065f, 0.028f}, {0.055f, 0.042f}, {0.030f, 0.050f}, {0.f, 0.051f}}, 24));
  addBox(m, {0.095f, 0.f, 0.031f}, {0.045f, 0.07f, 0.008f});  // display on the front lobe
  return m;
}

TriangleMesh headphones() {
  // Over-ear headphones standing on their ear cups; headband arc over the top.
  TriangleMesh m;
  for (float s : {-1.f, 1.f}) {
    m.append(makeCylinder(0.045f, 0.035f, 20), at({0.f, s * 0.085f, 0.045f}, 0.f, 0.f, 90.f));
    m.append(makeCylinder(0.010f, 0.030f, 8), at({0.f, s * 0.098f, 0.100f}));  // yoke
  }
  addArcTube(m, V3(0.f, 0.f, 0.105f), V3::UnitY(), V3::UnitZ(), 0.098f, 0.f, float(M_PI), 0.011f,
             16, 6);
  return m;
}

TriangleMesh laptop() {
  TriangleMesh m;
  addBox(m, {0.f, 0.f, 0.009f}, {0.23f, 0.33f, 0.018f});  // base, keyboard side up
  // Lid hinged at the rear edge, opened 110 degrees (tilted back 20 degrees), screen facing +x.
  Eigen::Affine3f hinge = at({-0.112f, 0.f, 0.018f}, 0.f, -20.f);
  m.append(makeBox({0.008f, 0.33f, 0.22f}), hinge * Eigen::Translation3f(0.004f, 0.f, 0.11f));
  return m;
}

TriangleMesh desk() {
  // 1.4 x 0.7 m desk, top surface at 0.74 m; the user sits on the +x side.
  TriangleMesh m;
  addBox(m, {0.f, 0.f, 0.725f}, {0.70f, 1.40f, 0.03f});
  for (float sx : {-1.f, 1.f})
    for (float sy : {-1.f, 1.f}) addBox(m, {sx * 0.30f, sy * 0.65f, 0.355f}, {0.05f, 0.05f, 0.71f});
  addBox(m, {-0.31f, 0.f, 0.50f}, {0.02f, 1.25f, 0.36f});  // modesty panel
  return m;
}

TriangleMesh shelf() {
  // Bookcase 0.8 m wide (y), 0.35 m deep (x), 1.8 m tall, open towards +x.
  TriangleMesh m;
  for (float s : {-1.f, 1.f}) addBox(m, {0.f, s * 0.39f, 0.90f}, {0.35f, 0.02f, 1.80f});
  for (float z : {0.01f, 0.45f, 0.90f, 1.35f, 1.79f})
    addBox(m, {0.f, 0.f, z}, {0.35f, 0.76f, 0.02f});
  addBox(m, {-0.17f, 0.f, 0.90f}, {0.01f, 0.78f, 1.78f});
  return m;
}

struct Entry {
  ProceduralModel info;
  std::function<TriangleMesh()> make;
};

const std::vector<Entry>& entries() {
  static const std::vector<Entry> e = {
      {{"mug", "cup", "8 cm mug with handle, hollow"}, mug},
      {{"bottle", "bottle", "0.5 l bottle with cap"}, bottle},
      {{"chair", "chair", "four-legged chair, seat at 0.475 m"}, chair},
      {{"monitor", "tv", "24-inch monitor on a stand, screen towards +x"}, monitor},
      {{"keyboard", "keyboard", "keyboard, 4 rows x 12 keys + space bar"}, keyboard},
      {{"clock", "clock", "30 cm wall clock; origin on the wall, face towards +x"}, wallClock},
      {{"conference_phone", "conference_phone", "three-lobed conference speakerphone"},
       conferencePhone},
      {{"headphones", "headphones", "over-ear headphones standing on the ear cups"}, headphones},
      {{"laptop", "laptop", "open laptop, screen towards +x"}, laptop},
      {{"desk", "dining table", "1.4 x 0.7 m desk, top at 0.74 m"}, desk},
      {{"shelf", "shelf", "0.8 x 0.35 x 1.8 m bookcase, open towards +x"}, shelf},
  };
  return e;
}

}  // namespace

const std::vector<ProceduralModel>& proceduralModels() {
  static const std::vector<ProceduralModel> v = [] {
    std::vector<ProceduralModel> out;
    for (const auto& e : entries()) out.push_back(e.info);
    return out;
  }();
  return v;
}

TriangleMesh makeProceduralModel(const std::string& name) {
  for (const auto& e : entries())
    if (e.info.name == name) return e.make();
  std::string list;
  for (const auto& e : entries()) list += (list.empty() ? "" : ", ") + e.info.name;
  throwInputError("procedural model '" + name + "'", "unknown; expected one of " + list);
}

std::vector<std::string> writeProceduralModels(const std::string& dir) {
  std::filesystem::create_directories(dir);
  std::vector<std::string> written;
  for (const auto& e : entries()) {
    const std::string path = (std::filesystem::path(dir) / (e.info.name + ".obj")).string();
    saveObj(
        e.make(), path,
        "rasm procedural model '" + e.info.name + "' (class " + e.info.class_name +
            "): " + e.info.description +
            "\nGenerated by `rasm sim make-models` (modules/models/src/ProceduralModels.cpp); do "
            "not edit.\n"
            "Metres, z up, origin at the footprint centre on the supporting surface, front "
            "towards +x.");
    written.push_back(path);
  }
  return written;
}

}  // namespace rasm::models
