#include "rasm/models/Mesh.h"

#ifdef RASM_HAVE_ASSIMP
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#endif
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <sstream>

#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"

namespace rasm::models {

void TriangleMesh::append(const TriangleMesh& other, const Eigen::Affine3f& T) {
  const int base = int(vertices.size());
  vertices.reserve(vertices.size() + other.vertices.size());
  for (const auto& v : other.vertices) vertices.push_back(T * v);
  for (const auto& t : other.triangles) triangles.push_back(t + Eigen::Vector3i::Constant(base));
}

Eigen::AlignedBox3f TriangleMesh::bounds() const {
  Eigen::AlignedBox3f b;
  if (vertices.empty())
    return Eigen::AlignedBox3f(Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero());
  for (const auto& v : vertices) b.extend(v);
  return b;
}

double TriangleMesh::surfaceArea() const {
  double a = 0;
  for (const auto& t : triangles)
    a += 0.5 *
         double((vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]).norm());
  return a;
}

TriangleMesh makeBox(const Eigen::Vector3f& size) {
  TriangleMesh m;
  const Eigen::Vector3f h = 0.5f * size;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(),
                            (i & 4) ? h.z() : -h.z());
  // Two triangles per face, counter-clockwise seen from outside.
  const int f[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : f) {
    m.triangles.emplace_back(q[0], q[1], q[2]);
    m.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return m;
}

TriangleMesh makeLathe(const std::vector<Eigen::Vector2f>& profile, int segments) {
  TriangleMesh m;
  const int n = int(profile.size());
  std::vector<int> first(n);  // index of the first vertex of each profile point's ring
  for (int i = 0; i < n; ++i) {
    first[i] = int(m.vertices.size());
    const float r = profile[i].x(), z = profile[i].y();
    if (r <= 0.f) {
      m.vertices.emplace_back(0.f, 0.f, z);
      continue;
    }
    for (int s = 0; s < segments; ++s) {
      const float a = float(2.0 * M_PI * s / segments);
      m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), z);
    }
  }
  auto vid = [&](int i, int s) {
    return profile[i].x() <= 0.f ? first[i] : first[i] + (s % segments);
  };
  for (int i = 0; i + 1 < n; ++i) {
    const bool pole0 = profile[i].x() <= 0.f, pole1 = profile[i + 1].x() <= 0.f;
    if (pole0 && pole1) continue;
    for (int s = 0; s < segments; ++s) {
      const int a = vid(i, s), b = vid(i, s + 1), c = vid(i + 1, s + 1), d = vid(i + 1, s);
      if (!pole0) m.triangles.emplace_back(a, b, c);
      if (!pole1) m.triangles.emplace_back(a, c, d);
    }
  }
  return m;
}

TriangleMesh makeCylinder(float radius, float height, int segments) {
  const float h = 0.5f * height;
  return makeLathe({{0.f, -h}, {radius, -h}, {radius, h}, {0.f, h}}, segments);
}

TriangleMesh makeSphere(float radius, int rings, int segments) {
  std::vector<Eigen::Vector2f> profile;
  for (int i = 0; i <= rings; ++i) {
    const double a = M_PI * i / rings;  // from the south pole up
    profile.emplace_back(i == 0 || i == rings ? 0.f : float(radius * std::sin(a)),
                         float(-radius * std::cos(a)));
  }
  return makeLathe(profile, segments);
}

TriangleMesh makeExtrusion(const std::vector<Eigen::Vector2f>& poly, float z0, float z1) {
  TriangleMesh m;
  const int n = int(poly.size());
  for (const auto& p : poly) m.vertices.emplace_back(p.x(), p.y(), z0);
  for (const auto& p : poly) m.vertices.emplace_back(p.x(), p.y(), z1);
  // Caps as fans around their centroid (the polygons used here are star-shaped about it).
  Eigen::Vector2f c = Eigen::Vector2f::Zero();
  for (const auto& p : poly) c += p;
  c /= float(n);
  const int c0 = int(m.vertices.size());
  m.vertices.emplace_back(c.x(), c.y(), z0);
  m.vertices.emplace_back(c.x(), c.y(), z1);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.triangles.emplace_back(i, j, n + j);
    m.triangles.emplace_back(i, n + j, n + i);
    m.triangles.emplace_back(c0, j, i);
    m.triangles.emplace_back(c0 + 1, n + i, n + j);
  }
  return m;
}

TriangleMesh loadMesh(const std::string& path, const std::string& what) {
  if (!std::filesystem::is_regular_file(path))
    throwInputError(what, "mesh file '" + path + "' not found");
#ifndef RASM_HAVE_ASSIMP
  throwInputError(what, "cannot read mesh file '" + path +
                            "': this rasm was built without the simulator (-DRASM_WITH_SIM=OFF), "
                            "which brings the mesh reader (assimp); use a procedural model");
#else
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode)
    throwInputError(what, "cannot read mesh file '" + path + "': " + importer.GetErrorString());
  TriangleMesh out;
  // Walk the node tree so node transforms (used by some exporters) are applied.
  std::function<void(const aiNode*, const aiMatrix4x4&)> visit = [&](const aiNode* node,
                                                                     const aiMatrix4x4& parent) {
    const aiMatrix4x4 T = parent * node->mTransformation;
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      const aiMesh* mesh = scene->mMeshes[node->mMeshes[k]];
      const int base = int(out.vertices.size());
      for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
        const aiVector3D v = T * mesh->mVertices[i];
        out.vertices.emplace_back(v.x, v.y, v.z);
      }
      for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines
        out.triangles.emplace_back(base + int(face.mIndices[0]), base + int(face.mIndices[1]),
                                   base + int(face.mIndices[2]));
      }
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) visit(node->mChildren[c], T);
  };
  visit(scene->mRootNode, aiMatrix4x4());
  if (out.triangles.empty()) throwInputError(what, "mesh file '" + path + "' holds no triangles");
  return out;
#endif
}

void saveObj(const TriangleMesh& mesh, const std::string& path, const std::string& comment) {
  std::ostringstream f;
  std::istringstream lines(comment);
  for (std::string l; std::getline(lines, l);) f << "# " << l << "\n";
  char buf[96];
  for (const auto& v : mesh.vertices) {
    // Round to 0.1 mm and avoid "-0.0000" so files are byte-stable across platforms.
    auto q = [](float x) {
      const double r = std::round(double(x) * 1e4) / 1e4;
      return r == 0.0 ? 0.0 : r;
    };
    std::snprintf(buf, sizeof(buf), "v %.4f %.4f %.4f\n", q(v.x()), q(v.y()), q(v.z()));
    f << buf;
  }
  for (const auto& t : mesh.triangles)
    f << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  try {
    writeFileAtomic(path, f.str());
  } catch (const std::runtime_error& e) {
    throwInputError(path, e.what());
  }
}

}  // namespace rasm::models
