#include "tests/shaft_test_room.h"

#include <glm/glm.hpp>

#include "core/colour.h"

namespace penumbra::shadow::testing {

namespace {

// A grid of (nu x nv) patches on the parallelogram origin + s*edgeU + t*edgeV, vertices
// shared inside the grid, two counter-clockwise triangles per patch (patch_mesh.h).
void addGrid(scene::PatchMesh& mesh, const glm::dvec3& origin, const glm::dvec3& edgeU,
             const glm::dvec3& edgeV, int nu, int nv, const glm::dvec3& emission) {
  const auto base = static_cast<uint32_t>(mesh.positions.size());
  const glm::dvec3 normal = glm::normalize(glm::cross(edgeU, edgeV));
  for (int j = 0; j <= nv; ++j) {
    for (int i = 0; i <= nu; ++i) {
      mesh.positions.push_back(origin + (double(i) / nu) * edgeU + (double(j) / nv) * edgeV);
      mesh.normals.push_back(normal);
    }
  }
  const auto vertex = [&](int i, int j) { return base + static_cast<uint32_t>(j * (nu + 1) + i); };
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      scene::Patch patch;
      patch.centre = origin + ((i + 0.5) / nu) * edgeU + ((j + 0.5) / nv) * edgeV;
      patch.normal = normal;
      patch.area = glm::length(glm::cross(edgeU, edgeV)) / (nu * nv);
      patch.reflectance = glm::dvec3(0.6);
      patch.emission = emission;
      patch.firstTriangle = static_cast<uint32_t>(mesh.triangleCount());
      const auto index = static_cast<uint32_t>(mesh.patches.size());
      mesh.indices.insert(mesh.indices.end(),
                          {vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j),
                           vertex(i + 1, j + 1), vertex(i, j + 1)});
      mesh.trianglePatch.insert(mesh.trianglePatch.end(), {index, index});
      mesh.patches.push_back(patch);
    }
  }
}

}  // namespace

void buildTestRoom(int floorCells, int lightCols, int lightRows, bool wallAndWindow,
                   scene::PatchMesh& mesh, SourceReceiverSets& sets, RadianceTransfers& t,
                   bool equalSources) {
  mesh = {};
  sets = {};
  t = {};
  addGrid(mesh, {0, 0, 0}, {0, 0, 4}, {4, 0, 0}, floorCells, floorCells, glm::dvec3(0));
  if (wallAndWindow) addGrid(mesh, {0, 0, 0}, {4, 0, 0}, {0, 2.5, 0}, 6, 4, glm::dvec3(0));
  const auto receiverEnd = static_cast<uint32_t>(mesh.patches.size());
  // Ceiling panel facing down, centred, 2.4 m x 1.6 m.
  addGrid(mesh, {0.8, 2.5, 1.2}, {2.4, 0, 0}, {0, 0, 1.6}, lightCols, lightRows, glm::dvec3(1));
  if (wallAndWindow) addGrid(mesh, {0, 0.9, 1.0}, {0, 0, 1.2}, {0, 1.2, 0}, 2, 2, glm::dvec3(3));
  for (uint32_t p = receiverEnd; p < mesh.patches.size(); ++p) {
    // Varied brightness so averages differ (and some tie: period 5).
    if (!equalSources) mesh.patches[p].emission *= 1.0 + 0.37 * ((p * 7) % 5);
    sets.sources.push_back(p);
  }
  std::vector<uint32_t> receiverVertexOf(mesh.positions.size(), kNoIndex);
  for (uint32_t p = 0; p < receiverEnd; ++p) {
    sets.receivers.push_back(p);
    for (uint32_t k = 0; k < 6; ++k) {
      const uint32_t v = mesh.indices[3 * mesh.patches[p].firstTriangle + k];
      if (receiverVertexOf[v] == kNoIndex) {
        receiverVertexOf[v] = static_cast<uint32_t>(t.receiverVertices.size());
        t.receiverVertices.push_back(v);
      }
    }
  }
  const size_t vertexCount = t.receiverVertices.size();
  t.vertexRadiance.assign(vertexCount, glm::vec3(0.01f));  // a little light from elsewhere
  t.sourceStart.push_back(0);
  for (uint32_t j : sets.sources) {
    const scene::Patch& src = mesh.patches[j];
    double sum = 0;
    for (uint32_t i = 0; i < vertexCount; ++i) {
      const uint32_t v = t.receiverVertices[i];
      const double ff = scene::pointToPatchFormFactor(mesh.positions[v], mesh.normals[v],
                                                      src.centre, src.normal, src.area);
      const glm::vec3 l(0.6 * ff * src.emission);
      if (core::luminance(l) > 1e-7f) {
        t.entryVertex.push_back(i);
        t.entryTransfer.push_back(l);
        t.vertexRadiance[i] += l;
        sum += core::luminance(l);
      }
    }
    t.sourceStart.push_back(static_cast<uint32_t>(t.entryVertex.size()));
    t.sourceAverage.push_back(static_cast<float>(sum / static_cast<double>(vertexCount)));
  }
}

}  // namespace penumbra::shadow::testing
