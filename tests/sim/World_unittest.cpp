// Worlds: the shipped worlds load, the class table, the procedural models, and world-file errors
// that name the file, the line and the key.
#include "rasm/sim/World.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "rasm/core/Error.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/models/Mesh.h"
#include "rasm/models/ProceduralModels.h"

namespace fs = std::filesystem;
using namespace rasm::sim;
using namespace rasm::models;

namespace {

std::string errorOf(const std::string& yaml, const std::string& source = "test_world.yaml") {
  try {
    loadWorldFromString(yaml, source);
  } catch (const rasm::InputError& e) {
    return e.what();
  }
  return "";
}

std::string readFile(const std::string& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace

TEST(SimClasses, CocoOrderAndProjectClasses) {
  EXPECT_EQ(numClasses(), 1 + 80 + 8);
  EXPECT_EQ(className(0), "none");
  EXPECT_EQ(className(1), "person");  // coco.names line 0 -> id 1
  EXPECT_EQ(className(80), "toothbrush");
  EXPECT_EQ(classIdFromName("cup"), 42);
  EXPECT_EQ(classIdFromName("mug"), classIdFromName("cup"));
  EXPECT_EQ(classIdFromName("tvmonitor"), classIdFromName("tv"));
  EXPECT_EQ(classIdFromName("diningtable"), classIdFromName("dining table"));
  EXPECT_EQ(classIdFromName("unknown"), 0);
  EXPECT_EQ(classIdFromName("spaceship"), -1);
  EXPECT_GT(classIdFromName("conference_phone"), 80);
  EXPECT_FALSE(isCocoClass(classIdFromName("headphones")));
  EXPECT_TRUE(isStructureClass(classIdFromName("wall")));
  EXPECT_FALSE(isStructureClass(classIdFromName("box")));
}

TEST(World, ShippedWorldsLoadByName) {
  const auto names = shippedWorlds();
  for (const char* w : {"office", "cluttered_lab", "two_rooms"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), w), names.end()) << w;
    const World world = loadWorld(w);
    EXPECT_EQ(world.name, w);
    EXPECT_GT(world.objects.size(), 20u) << w;
    int unknown = 0, zero_shot = 0;
    for (const auto& o : world.objects) {
      EXPECT_FALSE(o.mesh.empty());
      unknown += o.class_id == 0;
      zero_shot += o.class_id == classIdFromName("conference_phone") ||
                   o.class_id == classIdFromName("headphones");
    }
    EXPECT_GT(unknown, 0) << w << " has no unknown objects";
    EXPECT_GT(zero_shot, 0) << w << " has no zero-shot targets";
  }
  // A path loads the file itself.
  const World byPath = loadWorld(resolveWorldPath("office"));
  EXPECT_EQ(byPath.objects.size(), loadWorld("office").objects.size());
}

TEST(World, OfficeContents) {
  const World w = loadWorld("office");
  const Eigen::AlignedBox3f b = w.bounds();
  // One room of about 8 x 6 m.
  EXPECT_NEAR(b.max().x() - b.min().x(), 8.2, 0.05);
  EXPECT_NEAR(b.max().y() - b.min().y(), 6.2, 0.05);
  std::map<std::string, int> count;
  for (const auto& o : w.objects) ++count[className(o.class_id)];
  for (const char* c : {"chair", "dining table", "tv", "keyboard", "cup", "bottle", "clock",
                        "shelf", "box", "conference_phone", "headphones", "door", "wall", "floor"})
    EXPECT_GT(count[c], 0) << c;
}

TEST(World, UnknownWorldNameListsShippedOnes) {
  try {
    loadWorld("no_such_world");
    FAIL();
  } catch (const rasm::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("office"), std::string::npos) << e.what();
  }
}

TEST(World, MissingKeyNamesFileLineAndKey) {
  const std::string e = errorOf(
      "objects:\n"
      "  - {id: 1, class: cup, primitive: box, size: [1, 1, 1], position: [0, 0, 0]}\n"
      "  - {class: cup, primitive: box, size: [1, 1, 1], position: [0, 0, 0]}\n");
  EXPECT_NE(e.find("test_world.yaml:3"), std::string::npos) << e;
  EXPECT_NE(e.find("objects[1]"), std::string::npos) << e;
  EXPECT_NE(e.find("missing key 'id'"), std::string::npos) << e;
}

TEST(World, BadTypeNamesKeyPath) {
  const std::string e = errorOf(
      "static:\n"
      "  - id: 4\n"
      "    class: wall\n"
      "    primitive: box\n"
      "    size: [1, 1, 1]\n"
      "    position: [0, zero, 0]\n");
  EXPECT_NE(e.find("test_world.yaml:6"), std::string::npos) << e;
  EXPECT_NE(e.find("static[0].position[1]"), std::string::npos) << e;
  EXPECT_NE(e.find("expected a number"), std::string::npos) << e;
  const std::string e2 =
      errorOf("objects:\n  - {id: 1, class: cup, primitive: box, size: 3, position: [0, 0, 0]}\n");
  EXPECT_NE(e2.find("objects[0].size"), std::string::npos) << e2;
}

TEST(World, UnknownMeshFileNamesFileAndMesh) {
  const std::string e =
      errorOf("objects:\n  - {id: 7, class: cup, mesh: teapot_missing.obj, position: [0, 0, 0]}\n",
              "w.yaml");
  EXPECT_NE(e.find("w.yaml:2"), std::string::npos) << e;
  EXPECT_NE(e.find("objects[0].mesh"), std::string::npos) << e;
  EXPECT_NE(e.find("teapot_missing.obj"), std::string::npos) << e;
}

TEST(World, OtherErrors) {
  EXPECT_NE(errorOf("objects:\n  - {id: 1, class: spaceship, primitive: sphere, radius: 1, "
                    "position: [0, 0, 0]}\n")
                .find("unknown class 'spaceship'"),
            std::string::npos);
  EXPECT_NE(errorOf("objects:\n  - {id: 1, class: cup, primitive: sphere, radius: 1, position: [0, "
                    "0, 0], colr: [1, 2, 3]}\n")
                .find("objects[0].colr: unknown key"),
            std::string::npos);
  EXPECT_NE(errorOf("objects:\n"
                    "  - {id: 3, class: cup, primitive: sphere, radius: 1, position: [0, 0, 0]}\n"
                    "  - {id: 3, class: cup, primitive: sphere, radius: 1, position: [0, 0, 0]}\n")
                .find("already used by objects[0]"),
            std::string::npos);
  EXPECT_NE(errorOf("objects:\n  - {id: 1, class: cup, primitive: cone, position: [0, 0, 0]}\n")
                .find("unknown primitive"),
            std::string::npos);
  EXPECT_NE(errorOf("objects: [\n").find("YAML syntax error"), std::string::npos);
  EXPECT_NE(
      errorOf(
          "objects:\n  - {id: 1, class: cup, primitive: box, size: [1, 1, 1], position: [0, 0, 0], "
          "colour: [300, 0, 0]}\n")
          .find("out of range"),
      std::string::npos);
}

TEST(World, PoseScaleAndMaterial) {
  const World w = loadWorldFromString(
      "objects:\n"
      "  - {id: 9, class: none, primitive: box, size: [2, 1, 1], scale: [1, 2, 3], position: [1, "
      "2, 3], yaw_deg: 90,\n"
      "     colour: '#ff8000', texture: {pattern: checker, colour2: [0, 0, 255], period_m: "
      "0.25}}\n",
      "inline");
  ASSERT_EQ(w.objects.size(), 1u);
  const WorldObject& o = w.objects[0];
  EXPECT_EQ(o.class_id, 0);
  EXPECT_EQ(o.material.pattern, Pattern::Checker);
  EXPECT_NEAR(o.material.colour_rgb.y(), 128.0 / 255.0, 1e-6);
  const Eigen::AlignedBox3f b = o.worldMesh().bounds();
  // size (2, 1, 1) scaled (1, 2, 3) = (2, 2, 3), then yawed 90 deg: x extent 2, y extent 2.
  EXPECT_NEAR(b.min().x(), 0.0, 1e-5);
  EXPECT_NEAR(b.max().y(), 3.0, 1e-5);
  EXPECT_NEAR(b.max().z() - b.min().z(), 3.0, 1e-5);
}

TEST(ProceduralModels, CommittedObjFilesMatchTheGenerator) {
  const fs::path tmp =
      fs::temp_directory_path() / ("rasm_sim_models_" + std::to_string(::getpid()));
  const auto written = writeProceduralModels(tmp.string());
  ASSERT_EQ(written.size(), proceduralModels().size());
  for (const auto& m : proceduralModels()) {
    const std::string committed = simDataDir() + "/models/" + m.name + ".obj";
    ASSERT_TRUE(fs::exists(committed)) << committed << " missing: run `rasm sim make-models`";
    EXPECT_EQ(readFile(committed), readFile((tmp / (m.name + ".obj")).string()))
        << m.name << ".obj differs from the generator: run `rasm sim make-models`";
    EXPECT_LT(fs::file_size(committed), 32u * 1024u) << "models stay small";
    // assimp reads what we write, triangle for triangle.
    const TriangleMesh loaded = loadMesh(committed);
    const TriangleMesh made = makeProceduralModel(m.name);
    EXPECT_EQ(loaded.triangles.size(), made.triangles.size()) << m.name;
    EXPECT_NEAR(loaded.surfaceArea(), made.surfaceArea(), 1e-3 * made.surfaceArea()) << m.name;
    // Model frame: resting on z = 0 (the wall clock hangs on x = 0 instead).
    const Eigen::AlignedBox3f b = made.bounds();
    if (m.name == "clock")
      EXPECT_NEAR(b.min().x(), 0.0, 1e-4);
    else
      EXPECT_NEAR(b.min().z(), 0.0, 1e-4) << m.name;
    EXPECT_GE(classIdFromName(m.class_name), 1) << m.name;
  }
  fs::remove_all(tmp);
}

TEST(Mesh, PrimitivesAreClosedWithTheRightArea) {
  EXPECT_NEAR(makeBox({1, 2, 3}).surfaceArea(), 2 * (2 + 3 + 6), 1e-5);
  EXPECT_NEAR(makeCylinder(1.f, 2.f, 256).surfaceArea(), 2 * M_PI * 2 + 2 * M_PI, 0.01);
  EXPECT_NEAR(makeSphere(1.f, 64, 128).surfaceArea(), 4 * M_PI, 0.01);
  EXPECT_THROW(loadMesh("/nonexistent/x.obj", "where"), rasm::InputError);
}
